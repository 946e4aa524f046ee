"""A plugin module whose import raises (test fixture)."""

raise RuntimeError("plugin module is broken on purpose")
