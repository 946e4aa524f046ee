"""One module per ``fkcheck`` subcommand: ``add_parser(subparsers)`` and ``run(args)``.

:mod:`~fkcheck.cli._console` gives them the rich console their tables go to.
"""
