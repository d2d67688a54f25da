"""Checks before a grid command computes: the planned work fits the machine (:mod:`bifurc.run.guard`, evaluated
before any array of values exists: ``--n 1000000000`` would otherwise allocate 8 GB for the values alone; refused
unless ``--yes``), the options agree."""
from __future__ import annotations

import math

from maps.parameters import ParameterError

from ..run.guard import check_size


def check_budget(args, n_values: int, what: str = "values") -> dict:
    """Refuse (one line) a job whose estimated memory exceeds the available memory or whose run time
    exceeds MAX_HOURS, unless ``args.yes``; returns the estimate (:func:`bifurc.run.guard.check_size`)."""
    return check_size(n_values, args.transient, args.record, args.workers, getattr(args, "budget", None),
                      getattr(args, "allow_large", False), what,
                      f"reduce --n{'/--n2' if what == 'cells' else ''}, --transient or --record, or pass --yes to run it",
                      getattr(args, "trajectories", None))


def _sets(args) -> dict:
    """The --set names given more than once, with their values."""
    seen = {}
    for item in args.sets or []:
        name, sep, value = item.partition("=")
        if sep:
            seen.setdefault(name.strip(), []).append(value.strip())
    return {k: v for k, v in seen.items() if len(v) > 1}


def check_grid_options(args, swept) -> None:
    """Contradictions refused in one line: a --set given twice, a swept parameter also fixed
    (--relay-hz or --set), a bound that is not finite, several identical values (--from A --to A
    --n N > 1), --max-period < 1."""
    for name, values in _sets(args).items():
        raise ParameterError(f"--set {name} given {len(values)} times ({', '.join(values)}); give it once")
    fixed = {item.partition("=")[0].strip() for item in args.sets or []}
    if getattr(args, "relay_hz", None) is not None:
        fixed.add("relay_hz")
    for option, name in swept:
        if name in fixed:
            shown = f"--relay-hz {args.relay_hz:g}" if name == "relay_hz" and args.relay_hz is not None else f"--set {name}"
            raise ParameterError(f"{shown} fixes {name}, which {option} {name} sweeps; drop one of them")
    for option, value in (("--from", args.start), ("--to", args.stop), ("--from2", getattr(args, "start2", 0.0)),
                          ("--to2", getattr(args, "stop2", 0.0))):
        if not math.isfinite(value):
            raise ParameterError(f"{option} {value}: must be a finite number")
    for start, stop, n, opts in ((args.start, args.stop, args.n, "--from/--to/--n"),
                                 (getattr(args, "start2", None), getattr(args, "stop2", None), getattr(args, "n2", 1),
                                  "--from2/--to2/--n2")):
        if start is not None and start == stop and n > 1:
            raise ParameterError(f"{opts}: {start:g} to {stop:g} in {n} values repeats one value {n} times; "
                                 f"use --n{'2' if '2' in opts else ''} 1")
    if args.max_period < 1:
        raise ParameterError(f"--max-period {args.max_period}: need at least 1 relay period")
