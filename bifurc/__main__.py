"""``python -m bifurc ARGS`` runs the ``bifurc`` command line."""
import sys

from .cli import main

sys.exit(main())
