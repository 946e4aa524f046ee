"""Tests of fkcheck.engine: the check, its verdict and the evidence it keeps."""
