"""One module per ``fkcheck`` subcommand: ``add_parser(subparsers)`` and ``run(args)``."""
