"""Sphinx configuration of the bifurc documentation.

Build (one command, warnings as errors; the ``docs`` extra installs the tools)::

    python -m sphinx -W -b html docs docs/_build/html

At build time this file writes the generated pages that are not committed: the API reference's
lists (from ``bifurc.__all__`` and ``maps.__all__``, whatever they list then), one page per study
report, and copies of the notebooks (executed by myst-nb, cached in ``docs/_build/.jupyter_cache``).
The findings page (``docs/findings.md``, ``python -m bifurc.findings --page docs/findings.md``) and the
benchmarks page (``docs/benchmarks.md``, ``python benchmarks/results_page.py``) are generated and committed;
tests fail while either differs from its sources.

intersphinx links to numpy, scipy, xarray and matplotlib only when their inventories can be read: each
is tried once with a short timeout, and one that cannot be reached (no network, as in CI) is left out,
so that the build never fails on the network; names of those projects then render as plain code.
"""
from __future__ import annotations

import os
import shutil
import sys
import tempfile
from pathlib import Path

DOCS = Path(__file__).resolve().parent
ROOT = DOCS.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(DOCS))

import _generate  # noqa: E402  (docs/_generate.py: the pages written at build time)

import maps  # noqa: E402

project = "bifurc"
author = "the bifurc developers"
copyright = "2026, the bifurc developers"
release = maps.__version__
version = release

extensions = [
    "myst_nb",                      # Markdown pages (myst-parser) and notebooks
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "numpydoc",
    "sphinx.ext.intersphinx",
    "sphinx.ext.mathjax",
]

exclude_patterns = ["_build", "**.ipynb_checkpoints", "newcomer-answers.md", "README.md"]
source_suffix = {".rst": "restructuredtext", ".md": "myst-nb", ".ipynb": "myst-nb"}

# -- the pages written at build time -----------------------------------------------------------------
_generate.api_pages(DOCS)
_generate.study_pages(DOCS, ROOT / "studies")
_generate.notebook_copies(DOCS, ROOT / "notebooks")

# -- autodoc / autosummary / numpydoc -------------------------------------------------------------------
autosummary_generate = True
autosummary_imported_members = True
autodoc_typehints = "none"           # the signatures show them
numpydoc_show_class_members = False  # one page per public name; members listed by autodoc
numpydoc_validation_checks = set()   # docstrings are not all numpydoc yet (the lead's issue 45)
autodoc_default_options = {"members": False}

# -- intersphinx: fail soft ------------------------------------------------------------------------------
intersphinx_mapping = _generate.reachable_inventories({
    "python": "https://docs.python.org/3",
    "numpy": "https://numpy.org/doc/stable",
    "scipy": "https://docs.scipy.org/doc/scipy",
    "xarray": "https://docs.xarray.dev/en/stable",
    "matplotlib": "https://matplotlib.org/stable",
})

# -- MyST and myst-nb ---------------------------------------------------------------------------------
myst_enable_extensions = ["colon_fence", "dollarmath", "deflist"]
myst_heading_anchors = 3
nb_execution_mode = os.environ.get("BIFURC_DOCS_EXECUTE", "cache")   # "off": the committed outputs only
nb_execution_cache_path = str(DOCS / "_build" / ".jupyter_cache")
nb_execution_timeout = 900
nb_execution_raise_on_error = True
nb_execution_show_tb = True
nb_merge_streams = True
nb_output_stderr = "warn"          # a stderr output (a warning reaching the user) fails the -W build
# the notebooks write their datasets here, not into the source tree
os.environ.setdefault("BIFURC_NOTEBOOK_OUT", tempfile.mkdtemp(prefix="bifurc-docs-"))
# the kernels draw inline whatever the caller set (CI exports MPLBACKEND=Agg, which would show no figure)
os.environ["MPLBACKEND"] = "module://matplotlib_inline.backend_inline"
os.environ["PYTHONPATH"] = os.pathsep.join(p for p in (str(ROOT), os.environ.get("PYTHONPATH", "")) if p)

# -- HTML -------------------------------------------------------------------------------------------------
html_theme = "pydata_sphinx_theme"
html_title = f"bifurc {release}"
html_theme_options = {
    "navigation_with_keys": False,
    "show_toc_level": 2,
}
html_static_path: list[str] = []


# -- docstrings written as plain text ---------------------------------------------------------------------
import re  # noqa: E402

_ABS = re.compile(r"(?<![\\|`])\|([A-Za-z_][\w.]*)\|(?!`)")


def _plain_text_bars(app, what, name, obj, options, lines):
    """``|y_j|`` in a docstring is an absolute value, not a reST substitution: escape its bars."""
    lines[:] = [_ABS.sub(r"\\|\1\\|", line) for line in lines]


def setup(app):
    app.connect("autodoc-process-docstring", _plain_text_bars)
