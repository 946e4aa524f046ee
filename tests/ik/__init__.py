"""Tests of the IK solvers and their parameters."""
