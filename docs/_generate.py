"""The documentation pages written at build time (docs/conf.py calls these; none is committed).

- ``api/``: the API reference, one autosummary table per package over its declared public surface
  (``bifurc.__all__``, ``maps.__all__``: whatever they list when the docs are built), and one per public module
  that declares names of its own (``bifurc.studykit``, ``maps.studykit``, ``bifurc.labels``, ``bifurc.explore``);
- ``studies/``: one page per committed study report (``studies/<name>/report*.md``) with the command
  that regenerates it;
- ``notebooks/``: copies of ``notebooks/*.ipynb`` (myst-nb executes them, outputs cached).
"""
from __future__ import annotations

import importlib
import shutil
import urllib.request
from pathlib import Path

#: the packages whose declared public surface the API reference lists, with one line on each
PACKAGES = {
    "bifurc": "what the motion is: diagrams, regime maps, periodic orbits and branches, attractor censuses, "
              "their plots and reports. Every function returns an :class:`xarray.Dataset` (or draws one).",
    "maps": "what the system is and how it moves: hybrid systems, scenes and their parameters, the engines, "
            "stroboscopic and impact maps with exact Jacobians, time histories.",
}

#: the report files of a study and the form each holds, in page order
REPORTS = (("report.md", "full", ""), ("report-quick.md", "quick", " --quick"), ("report-medium.md", "medium", None))


def _write(path: Path, text: str) -> None:
    """Write ``text`` unless the file already holds it (an unchanged page keeps its time: no rebuild)."""
    path.parent.mkdir(parents=True, exist_ok=True)
    if not path.is_file() or path.read_text() != text:
        path.write_text(text)


def api_pages(docs: Path) -> None:
    out = docs / "api"
    index = ["API reference", "=============", "",
             "Generated from the packages' declared public surface (their ``__all__``) and the docstrings of its names.",
             "", ".. toctree::", "   :maxdepth: 1", ""]
    for name, about in PACKAGES.items():
        module = importlib.import_module(name)
        names = [n for n in module.__all__ if not n.startswith("_")]
        index.append(f"   {name}")
        lines = [f"``{name}``", "=" * (len(name) + 4), "", about, "",
                 f".. currentmodule:: {name}", "", ".. autosummary::", "   :toctree: generated", "   :nosignatures:", ""]
        lines += [f"   {n}" for n in names]
        _write(out / f"{name}.rst", "\n".join(lines) + "\n")
        for sub, declared in public_modules(module).items():
            index.append(f"   {sub}")
            first = (importlib.import_module(sub).__doc__ or "").strip().split("\n\n")[0].replace("\n", " ")
            lines = [f"``{sub}``", "=" * (len(sub) + 4), "", first, "", f".. currentmodule:: {sub}", "",
                     ".. autosummary::", "   :toctree: generated", "   :nosignatures:", ""]
            _write(out / f"{sub}.rst", "\n".join(lines + [f"   {n}" for n in declared]) + "\n")
    _write(out / "index.rst", "\n".join(index) + "\n")


def public_modules(package) -> dict:
    """{"bifurc.studykit": [its public names], ...}: the modules ``package.__all__`` names that declare names of
    their own (a ``_LAZY`` table, as ``bifurc.studykit``); a public module without one (``bifurc.attractors``, a
    callable package) is documented as itself on the package's page."""
    out = {}
    for n in package.__all__:
        value = getattr(package, n)
        if isinstance(value, type(importlib)) and getattr(value, "_LAZY", None):
            out[value.__name__] = list(value._LAZY)
    return out


def study_pages(docs: Path, studies: Path) -> None:
    """One page per committed report, and an index (the gallery) listing them."""
    from bifurc.commands.study import DURATIONS
    out = docs / "studies"
    rows, pages = [], []
    for folder in sorted(p for p in studies.iterdir() if (p / "__init__.py").is_file()):
        name = folder.name.replace("_", "-")
        module = importlib.import_module(f"studies.{folder.name}")
        about = (module.__doc__ or "").strip().split("\n\n")[0].replace("\n", " ")
        for file, form, flag in REPORTS:
            report = folder / file
            if not report.is_file():
                continue
            page = f"{folder.name}-{form}"
            pages.append(page)
            title = report.read_text().splitlines()[0].lstrip("# ").strip()
            command = (f"`bifurc study {name}{flag} -o DIR`" if flag is not None
                       else "see the report (a form `bifurc study` does not offer)")
            cost = dict(zip(("quick", "full"), DURATIONS.get(name, ("", "", ""))[:2])).get(form, "")
            rows.append(f"| [{name}]({page}.md) | {form} | {command} | {cost} | {about} |")
            _write(out / f"{page}.md", "\n".join([
                f"# {name}: {form} form", "",
                f"Regenerate: {command}; `bifurc study {name}{flag or ''} --check` re-runs the form and fails when "
                "a stated finding no longer holds." if flag is not None else f"Regenerate: {command}.", "",
                "The figures the report names are written by that command into `DIR` (they are not committed). "
                f"Source: `studies/{folder.name}/{file}`. The report follows, as committed.", "",
                f"```{{include}} ../../studies/{folder.name}/{file}", ":heading-offset: 1", ":relative-images:", "```",
                ""]))
    index = ["# Studies", "",
             "Each study is a reproducible question about the thesis model, run by `bifurc study NAME` "
             "(`--quick` for its reduced form); its last report is committed beside its code "
             "(`studies/<name>/report*.md`) with the command, commit and date that made it. "
             "Every finding the reports state is listed, with its tolerance, in [Findings](../findings.md).", "",
             "| study | form | regenerate | cost (2 shared cores; `bifurc study --help`) | what it asks |",
             "|---|---|---|---|---|", *rows, "",
             "```{toctree}", ":hidden:", "", *pages, "```", ""]
    _write(out / "index.md", "\n".join(index))


def notebook_copies(docs: Path, notebooks: Path) -> None:
    out = docs / "notebooks"
    out.mkdir(exist_ok=True)
    for nb in sorted(notebooks.glob("*.ipynb")):
        target = out / nb.name
        if not target.is_file() or target.read_bytes() != nb.read_bytes():
            shutil.copyfile(nb, target)


def reachable_inventories(urls: dict[str, str], timeout: float = 3.0) -> dict:
    """intersphinx's mapping for the projects whose ``objects.inv`` can be read now; the others left out."""
    mapping = {}
    for name, url in urls.items():
        try:
            with urllib.request.urlopen(f"{url}/objects.inv", timeout=timeout) as r:
                r.read(16)
        except (OSError, ValueError):
            print(f"intersphinx: {name} ({url}) not reachable; its names are not linked in this build")
            continue
        mapping[name] = (url, None)
    return mapping
