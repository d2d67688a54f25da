"""The package version, in a module of its own so that submodules need not import the package."""
from maps._version import __version__
