"""`bifurc map`: a two-parameter regime map to netCDF and a figure."""
from ._guards import check_budget, check_grid_options
from ._common import (add_grid_options, add_range_options, add_scene_options, check_outputs, check_plot,
                      check_scheduler, problem_kwargs)


def register(subparsers):
    p = subparsers.add_parser("map", help="regime map over two parameters",
                              description="Classify every cell of a two-parameter grid as a diagram value "
                                          "(period n with m impacts, quasi-periodic, chaotic, ...; Lyapunov "
                                          "exponent, clearance); write netCDF and a figure. Interrupted maps resume "
                                          "from <output>.parts/. An existing output is refused unless --force.")
    add_scene_options(p, default_tol=None)
    add_range_options(p, "relay_hz", 50)
    add_range_options(p, "V", 50, "2")
    add_grid_options(p, "cell", exclude=("mode",))
    p.set_defaults(func=run)


def run(args) -> int:
    import numpy as np

    from maps.parameters import ParameterError

    from ..plots.map import regime_categories
    from ..sweeps.method import Diagram
    from ..sweeps.regime import regime_map
    from ._options import run_from_args, settings_from_args
    for opt, n in (("--n", args.n), ("--n2", args.n2)):
        if n < 1:
            raise ParameterError(f"{opt} {n}: need at least 1 value")
    check_grid_options(args, [("--param", args.param), ("--param2", args.param2)])
    est = check_budget(args, args.n * args.n2, "cells")
    kw = problem_kwargs(args)
    method, run_on = settings_from_args(Diagram, args, exclude=("mode",)), run_from_args(args)
    check_outputs(args, args.output, need_bytes=est["file"])
    check_plot(args)
    check_scheduler(args.scheduler)
    ds = regime_map(args.scene, args.param, np.linspace(args.start, args.stop, args.n), args.param2,
                    np.linspace(args.start2, args.stop2, args.n2), method, run=run_on, **kw)
    if args.plot:
        from ..plots.map import plot_regime_map
        plot_regime_map(ds, args.plot, overwrite=args.force, period_of=args.period_of)
    index, cats = regime_categories(ds)
    counts = "; ".join(f"{text}: {int((index == i).sum())}" for i, (text, _) in enumerate(cats))
    a = ds.attrs
    resumed = f", {a['resumed_values']} resumed" if a["resumed_values"] else ""
    print(f"{a['scene']}: {args.param} {args.start:g}..{args.stop:g} x {args.param2} {args.start2:g}..{args.stop2:g} "
          f"({args.n} x {args.n2} cells) in {a['values_seconds']:.1f} s of computation ({a['sweep_seconds']:.1f} s "
          f"wall this run{resumed}): {counts}")
    from ..report import undecided_summary
    for line in undecided_summary(ds):
        print("  " + line)
    print(f"  wrote {args.output}" + (f" and {args.plot}" if args.plot else ""))
    return 0
