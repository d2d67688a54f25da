"""Command-line options generated from the settings objects: one option group per method, one for the run.

Each field of a method (:class:`bifurc.Diagram`, :class:`bifurc.Census`) or of :class:`bifurc.Run` declared with a
command-line name becomes one option with the field's help, unit and default (shown once), so a setting has the
same name and default in every verb and in the API.  :func:`method_from_args` and :func:`run_from_args` build the
objects back from the parsed arguments (validated by the objects themselves).
"""
from __future__ import annotations

import dataclasses


def _option(f) -> str | None:
    cli = f.metadata.get("cli")
    if cli == "":
        return None
    return cli or "--" + f.name.replace("_", "-")


def _help(f) -> str:
    m = f.metadata
    text = m["help"]
    unit = f" [{m['unit']}]" if m.get("unit") else ""
    if f.default is not None and not isinstance(f.default, bool) and "default" not in text:
        text += f" (default {f.default:g})" if isinstance(f.default, float) else f" (default {f.default})"
    return text + unit


def add_settings_options(parser, cls, title: str | None = None, exclude=()) -> None:
    """An option per command-line field of the settings class ``cls``, in a new group ``title`` (None: in
    ``parser``, itself a group)."""
    g = parser.add_argument_group(title) if title else parser
    for f in dataclasses.fields(cls):
        if f.name in exclude or not f.metadata:
            continue
        m = f.metadata
        if isinstance(f.default, bool):
            if m.get("flag"):       # a setting on by default, switched off on the command line
                g.add_argument(m["flag"], dest=f.name, action="store_false", help="skip: " + _help(f))
            elif _option(f):
                g.add_argument(_option(f), dest=f.name, action="store_true", help=_help(f))
            continue
        option = _option(f)
        if option is None:
            continue
        kind = m.get("kind") or (int if m.get("whole") else type(f.default))
        kw = dict(dest=f.name, default=f.default, help=_help(f))
        if m.get("choices"):
            kw["choices"] = m["choices"]
        else:
            kw["type"] = kind
        if m.get("unit"):
            kw["metavar"] = f.name.upper()
        g.add_argument(option, **kw)


def settings_from_args(cls, args, exclude=(), **given):
    """An instance of ``cls`` from the parsed ``args`` (its command-line fields) and ``given`` values."""
    kw = {}
    for f in dataclasses.fields(cls):
        if f.name in exclude or f.name in given or not f.metadata:
            continue
        if hasattr(args, f.name) and (_option(f) or f.metadata.get("flag")):
            kw[f.name] = getattr(args, f.name)
    return cls(**kw, **given)


def add_run_options(parser, what: str = "value") -> None:
    """Where the job runs (workers, Dask scheduler, time budget, --yes) and its outputs (-o, --plot, --quiet,
    --force)."""
    from ..run.where import Run
    add_settings_options(parser, Run, "where it runs")
    g = parser.add_argument_group("outputs")
    g.add_argument("-o", "--output", required=True, help="netCDF file to write; completed points are kept in "
                   "<output>.parts/ and an interrupted run resumes there")
    g.add_argument("--plot", default=None, help="figure file (.png, .pdf, .svg, ...)")
    g.add_argument("--quiet", action="store_true", help="no progress bar")
    g.add_argument("--force", action="store_true", help="replace existing output files")


def run_from_args(args):
    """The :class:`bifurc.Run` of the parsed ``args``."""
    from ..run.where import Run
    return settings_from_args(Run, args, path=args.output, overwrite=args.force, progress=not args.quiet)
