"""Inverse kinematics: solvers checked against the table's verified FK."""
