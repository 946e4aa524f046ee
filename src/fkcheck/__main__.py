"""``python -m fkcheck``: the same as the ``fkcheck`` command."""

import sys

from fkcheck.cli import main

sys.exit(main())
