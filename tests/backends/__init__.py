"""Tests of fkcheck.backends: each reference backend, and their independence from the core."""
