"""`bifurc study`: run a named study (diagram, report, comparison with the thesis).

Studies are not part of bifurc: they live in the top-level ``studies`` package, one folder each,
and are found through the entry-point group ``bifurc.studies`` (name -> module, declared in
pyproject.toml), so bifurc never imports them by name.  One calling convention: a study module
exposes ``run(out, quick=False, progress=True, overwrite=False, **options)``, writes its report,
figures and datasets into folder ``out`` and returns what it measured; ``WRITES`` (optional)
says what it writes, for the command's last line.  The refusal of an occupied output folder is
here, the same for every study.
"""
from pathlib import Path

from ._common import add_force_option

#: the entry-point group that names the studies
GROUP = "bifurc.studies"


def studies() -> dict:
    """Study name -> entry point (its module), from the installed distributions' ``bifurc.studies`` group."""
    from importlib.metadata import entry_points
    return {ep.name: ep for ep in sorted(entry_points(group=GROUP), key=lambda ep: ep.name)}


def load_study(name):
    """The module of study ``name`` (a :class:`~maps.parameters.ParameterError` naming the studies if unknown)."""
    found = studies()
    if name not in found:
        from maps.parameters import ParameterError
        raise ParameterError(f"unknown study {name!r}; studies: {', '.join(found) or 'none installed'}")
    return found[name].load()


def run_study(name, out, quick=False, progress=True, overwrite=False, hint="pass overwrite=True", **options):
    """Run study ``name`` into folder ``out``; returns what the study's ``run`` returns.

    A folder holding anything but interrupted sweeps (``*.parts``, which resume) is refused
    unless ``overwrite`` (then its files are replaced); ``hint`` completes the refusal.
    ``options`` (e.g. ``cases=[...]``) go to the study's ``run``.
    """
    import inspect
    study = load_study(name)
    out = Path(out)
    if out.exists() and not out.is_dir():
        raise NotADirectoryError(f"{out} is a file, not a folder")
    held = sorted(p.name for p in out.iterdir() if not p.name.endswith(".parts")) if out.is_dir() else []
    if held and not overwrite:
        raise FileExistsError(f"{out} is not empty ({len(held)} entries, e.g. {held[0]}); {hint} to write into it")
    unknown = sorted(set(options) - set(inspect.signature(study.run).parameters))
    if unknown:
        from maps.parameters import ParameterError
        raise ParameterError(f"study {name} takes no {', '.join(unknown)}")
    _check_cases(name, study, options.get("cases"))
    from ..storage.files import check_writable
    check_writable(out / "report.md")   # the folder takes files (read-only, missing rights: one line now)
    return study.run(out, quick=quick, progress=progress, overwrite=overwrite, **options)


def case_names(study) -> list:
    """The case names of a study module: its ``CASES`` (names, or tuples that start with the name)."""
    return [c[0] if isinstance(c, (tuple, list)) else str(c) for c in getattr(study, "CASES", [])]


def _check_cases(name, study, cases) -> None:
    """Every requested case exists (a typo would otherwise run nothing and report an empty study)."""
    if not cases:
        return
    from maps.parameters import ParameterError
    known = case_names(study)
    bad = [c for c in cases if c not in known]
    if bad:
        raise ParameterError(f"unknown case {bad[0]!r} for study {name}; cases: {', '.join(known) or 'none'}")


def written(name, out) -> str:
    """The command's last line: what study ``name`` wrote into ``out``."""
    return f"wrote {out}/{getattr(load_study(name), 'WRITES', 'report.md and its figures')}"


def register(subparsers):
    p = subparsers.add_parser("study", help="run a named, reproducible study (studies/)")
    p.add_argument("name", help="study name (listed below)")
    p.add_argument("--quick", action="store_true", help="reduced size")
    p.add_argument("-o", "--output", default="out/study", help="output folder")
    p.add_argument("--case", action="append", default=None, help="run only this case (repeatable)")
    p.add_argument("--scheduler", default=None, metavar="ADDRESS",
                   help="Dask scheduler address (studies that take it: sensitivity)")
    p.add_argument("--workers", type=int, default=None, help="local worker processes (studies that take it)")
    add_force_option(p)
    p.set_defaults(func=run)
    plain = p.format_help

    def format_help():   # the installed studies, read only when help is shown
        return plain() + "\nstudies: " + (", ".join(studies()) or "none installed") + "\n"
    p.format_help = format_help


def run(args) -> int:
    options = {"cases": args.case} if args.case else {}
    if args.scheduler is not None:
        options["scheduler"] = args.scheduler
    if args.workers is not None:
        options["workers"] = args.workers
    run_study(args.name, args.output, quick=args.quick, overwrite=args.force, hint="use --force", **options)
    print(written(args.name, args.output))
    return 0
