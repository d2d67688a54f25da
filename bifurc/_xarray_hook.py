"""Register the ``ds.bifurc`` accessor without importing xarray in processes that never use it.

``import bifurc`` runs in every worker process of a parallel sweep, where importing xarray (and
pandas) would add ~0.7 s to each start. A Dataset cannot exist before xarray is imported, so
the accessor is registered as soon as xarray is: at once if it already is, else right after
its first import (a one-shot finder on ``sys.meta_path``).
"""
from __future__ import annotations

import importlib
import importlib.util
import sys

class _AfterXarray:
    """One-shot meta path finder: lets xarray load as usual, then imports bifurc.accessor."""

    def find_spec(self, name, path=None, target=None):
        if name != "xarray":
            return None
        sys.meta_path.remove(self)
        spec = importlib.util.find_spec(name)
        if spec is None or spec.loader is None:
            return spec
        run = spec.loader.exec_module

        def exec_module(module):
            run(module)
            importlib.import_module("bifurc.accessor")
        spec.loader.exec_module = exec_module
        return spec


def register_accessor_with_xarray() -> None:
    """Register ``ds.bifurc`` now if xarray is imported, else when it first is."""
    if "xarray" in sys.modules:
        importlib.import_module("bifurc.accessor")
    elif not any(isinstance(f, _AfterXarray) for f in sys.meta_path):
        sys.meta_path.insert(0, _AfterXarray())
