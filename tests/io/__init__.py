"""Tests of fkcheck.io."""
