"""Package exports imported on first use (PEP 562), so that importing a package stays light."""
import importlib

def lazy_exports(package: str, table: dict, namespace: dict):
    """``__getattr__`` and ``__dir__`` for ``package`` whose public ``name`` lives in submodule
    ``table[name]`` (relative to the package); a name is imported once, then kept in ``namespace``."""
    def __getattr__(name):
        if name not in table:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        value = getattr(importlib.import_module(f".{table[name]}", package), name)
        namespace[name] = value
        return value

    def __dir__():
        return sorted(set(namespace) | set(namespace.get("__all__", ())) | set(table))
    return __getattr__, __dir__
