"""Subcommands of the ``bifurc`` command line, one module each with ``register(subparsers)``."""
