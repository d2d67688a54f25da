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

#: What each study costs on the shared 2-core development machine: (quick form, full form, where the figures
#: come from). Committed measurements only, with their commit, date and load where stated; "idle" marks a figure
#: from a quiet machine (each quick form run alone, one after another, load 0.9-1.7 from the run itself; a loaded
#: machine is slower by about the load over the cores). `bifurc study --help` prints this table and README.md states
#: it (tests/test_readme.py checks that they agree).
DURATIONS = {
    "dc-well": ("37 s idle", "263 s idle (its census and windows included)",
                "quick idle at 7ba01d4, 2026-11-29; full idle at e505efe, 2026-11-29, report committed"),
    "attractor-atlas": ("65 s idle", "30 min (1788 s) idle",
                        "quick idle at 7ba01d4, 2026-11-29; full idle at e505efe, 2026-11-30, report committed"),
    "prototype-progression": ("20 s idle", "318 s idle (8 of 25 frequencies for the variants)",
                              "quick idle at 7ba01d4, 2026-11-29; full idle at e505efe, 2026-11-29, report committed"),
    "regime-maps": ("154 s idle", "not measured to its end: of its 4 maps of 41 x 41 cells, the first one's first 1508 "
                    "cells took 19 min idle (resumable)", "quick idle at 7ba01d4, 2026-11-29; part of the full form idle "
                    "at e505efe, 2026-11-30"),
    "sensitivity": ("14 s idle", "29 min (1724 s) idle, N = 256 (2560 samples; resumable per sample)",
                    "quick idle at 7ba01d4, 2026-11-29; full idle at 64145f6, 2026-11-30, report committed"),
    "thesis-1dof-relay": ("63 s idle", "376 s idle (3 diagrams of 81 values to budget 6000)",
                          "quick idle at 7ba01d4, 2026-11-29; full idle at e505efe, 2026-11-29, report committed"),
    "thesis-2dof-rig": ("5 s idle", "14 s idle", "quick idle at 7ba01d4, 2026-11-29; full idle at e505efe, 2026-11-30, "
                        "report committed"),
    "thesis-orbits": ("32 s idle", "17 min (1025 s) idle", "quick idle at 7ba01d4, 2026-11-29; full idle at e505efe, "
                      "2026-11-30, report committed"),
    "thesis-replay": ("17 s idle", "11 min (634 s) idle", "quick idle at 7ba01d4, 2026-11-29; full idle at e505efe, "
                      "2026-11-30, report committed"),
}


def durations_table() -> str:
    """The :data:`DURATIONS` as a Markdown table (README.md's, and the help's text)."""
    rows = ["| study | `--quick` | full | measured |", "|---|---|---|---|"]
    rows += [f"| {name} | {q} | {f} | {when} |" for name, (q, f, when) in DURATIONS.items()]
    return "\n".join(rows)


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
    results = study.run(out, quick=quick, progress=progress, overwrite=overwrite, **options)
    if hasattr(study, "findings") and not options.get("cases"):
        from ..findings import table
        main = out / report_name(study)
        made_by = f"bifurc study {name}{' --quick' if quick else ''} -o DIR"
        main.write_text(main.read_text().rstrip() + "\n\n" + table(study.findings(results, quick),
                                                                    "quick" if quick else "full", made_by))
    return results


def report_name(study) -> str:
    """The file name of a study's main report in its output folder (``REPORT``, default report.md)."""
    return getattr(study, "REPORT", "report.md")


def committed_report(study, quick: bool) -> Path:
    """The report committed beside a study's module for a form: report.md (full), report-quick.md."""
    return Path(study.__file__).parent / ("report-quick.md" if quick else "report.md")


def check_study(name, out, quick=False, progress=True) -> list[str]:
    """Re-run study ``name``'s form into ``out`` and compare its findings with those its committed
    report states (:mod:`bifurc.findings`); returns the lines of the findings that do not hold."""
    from maps.parameters import ParameterError
    from ..findings import compare, parse
    study = load_study(name)
    form = "quick" if quick else "full"
    ref = committed_report(study, quick)
    if not hasattr(study, "findings"):
        raise ParameterError(f"study {name} states no findings to check")
    stated_form, stated = parse(ref.read_text()) if ref.is_file() else (None, {})
    if not stated or stated_form != form:
        raise ParameterError(f"{ref} states no {form}-form findings; run `bifurc study {name}"
                             f"{' --quick' if quick else ''}` and commit its {report_name(study)} there")
    results = run_study(name, out, quick=quick, progress=progress, overwrite=True)
    return compare(stated, study.findings(results, quick))


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
    p.add_argument("--check", action="store_true",
                   help="re-run the form (with --quick: the quick one) and check the findings its committed report "
                        "(studies/NAME/report.md, report-quick.md) states; exit 1 when one does not hold")
    p.add_argument("--scheduler", default=None, metavar="ADDRESS",
                   help="Dask scheduler address (studies that take it: sensitivity)")
    p.add_argument("--workers", type=int, default=None, help="local worker processes (studies that take it)")
    add_force_option(p)
    p.set_defaults(func=run)
    plain = p.format_help

    def format_help():   # the installed studies, read only when help is shown
        cost = "\n".join(f"  {name:<22} quick {q}; full {f}; {when}" for name, (q, f, when) in DURATIONS.items())
        return (plain() + "\nstudies: " + (", ".join(studies()) or "none installed") + "\n"
                + "\nwhat each costs on 2 shared cores (committed measurements):\n" + cost + "\n")
    p.format_help = format_help


def run(args) -> int:
    if args.check:
        import tempfile
        with tempfile.TemporaryDirectory(prefix="bifurc-check-") as tmp:
            bad = check_study(args.name, tmp, quick=args.quick)
        if bad:
            print(f"{len(bad)} stated finding(s) of {args.name} do not hold:\n  " + "\n  ".join(bad))
            return 1
        print(f"every stated finding of {args.name} ({'quick' if args.quick else 'full'} form) holds")
        return 0
    options = {"cases": args.case} if args.case else {}
    if args.scheduler is not None:
        options["scheduler"] = args.scheduler
    if args.workers is not None:
        options["workers"] = args.workers
    run_study(args.name, args.output, quick=args.quick, overwrite=args.force, hint="use --force", **options)
    print(written(args.name, args.output))
    return 0
