"""Tests of fkcheck.core: the in-house DH FK, its kernels, geometry and pose formats."""
