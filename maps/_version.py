"""The version of the distribution that ships ``maps`` and ``bifurc`` together (pyproject reads it)."""
__version__ = "0.2.0"
