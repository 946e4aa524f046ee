"""Reference backends, one module each, registered in :mod:`fkcheck.backends.registry`.

Importing this package imports no reference library.
"""
