"""Hostile input, outputs, processes and resources, across every layer."""
