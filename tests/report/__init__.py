"""Tests of fkcheck.report: HTML pages, diagnosis section, a real browser."""
