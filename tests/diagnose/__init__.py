"""Tests of fkcheck.diagnose."""
