"""Tests of fkcheck.model: model files, lint, conversion."""
