"""``python -m fkcheck``: the same as the ``fkcheck`` command."""

import sys

from fkcheck.cli.main import main

sys.exit(main())
