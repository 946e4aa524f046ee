"""fkcheck's test suite, a package: shared helpers import as ``tests.helpers`` and so on."""
