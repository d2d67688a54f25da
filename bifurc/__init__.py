"""bifurc: bifurcation analysis of the electro-vibro-impact system.

Sweeps, classification, grazing, storage, plotting and the command line, on
top of the dynamics in :mod:`maps`.
"""
__version__ = "0.1.0"
