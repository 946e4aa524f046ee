"""fkcheck in a user's own repository: assertions, the pytest plugin, types, CI."""
