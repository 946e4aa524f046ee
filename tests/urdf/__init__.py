"""Tests of fkcheck.urdf: export, DH from URDF, generated URDFs."""
