"""The progress bar class: a widget in Jupyter where ipywidgets is installed, text on stderr elsewhere.

``tqdm.auto`` in Jupyter without ipywidgets warns (``TqdmWarning: IProgress not found``) and prints text
anyway: the text bar is taken directly then."""
from __future__ import annotations

__all__ = ["tqdm_class"]


def tqdm_class():
    """``tqdm.auto.tqdm`` where ipywidgets can be imported, else the text ``tqdm.tqdm``."""
    try:
        import ipywidgets  # noqa: F401
        from tqdm.auto import tqdm
    except ImportError:
        from tqdm import tqdm
    return tqdm
