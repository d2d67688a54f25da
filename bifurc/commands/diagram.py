"""`bifurc diagram`: a one-parameter bifurcation diagram to netCDF and a figure."""
from ._guards import check_budget, check_grid_options
from ._common import (add_grid_options, add_range_options, add_scene_options, check_outputs, check_plot,
                      check_scheduler, problem_kwargs)


def register(subparsers):
    p = subparsers.add_parser("diagram", help="bifurcation diagram over one parameter",
                              description="Sweep one parameter; record the stroboscopic map, impacts and the "
                                          "class of each orbit; write netCDF and a figure. Interrupted sweeps "
                                          "resume from <output>.parts/. An existing output is refused unless --force; "
                                          "a second run into the same output at once is refused (<output>.lock, "
                                          "POSIX only).")
    add_scene_options(p, default_tol=None)
    add_range_options(p, "relay_hz", 100)
    add_grid_options(p, "value")
    p.set_defaults(func=run)


def run(args) -> int:
    import numpy as np

    from maps.parameters import ParameterError

    from ..labels.classify import CLASS_LABELS
    from ..sweeps.method import Diagram
    from ..sweeps.sweep import sweep
    from ._options import run_from_args, settings_from_args
    if args.n < 1:
        raise ParameterError(f"--n {args.n}: need at least 1 value")
    check_grid_options(args, [("--param", args.param)])
    est = check_budget(args, args.n)
    kw = problem_kwargs(args)
    method, run_on = settings_from_args(Diagram, args), run_from_args(args)
    check_outputs(args, args.output, need_bytes=est["file"])
    check_plot(args)
    check_scheduler(args.scheduler)
    values = np.linspace(args.start, args.stop, args.n)
    ds = sweep(args.scene, args.param, values, method, run=run_on, **kw)
    if args.plot:
        from ..plots.diagram import plot_diagram
        plot_diagram(ds, args.plot, overwrite=args.force, period_of=args.period_of)
    codes = ds.class_code.values.ravel()
    counts = ", ".join(f"{CLASS_LABELS[c]} {int((codes == c).sum())}" for c in range(len(CLASS_LABELS))
                       if (codes == c).any())
    a = ds.attrs
    resumed = f", {a['resumed_values']} resumed" if a["resumed_values"] else ""
    print(f"{a['scene']}: {args.param} {args.start:g}..{args.stop:g} ({args.n} values, {args.mode}) in "
          f"{a['values_seconds']:.1f} s of computation ({a['sweep_seconds']:.1f} s wall this run{resumed}): "
          f"{counts}; {_grazing_text(ds)}")
    from ..report import undecided_summary
    for line in undecided_summary(ds):
        print(f"  {line}")
    if "error_map_points_rel" in a:
        print(f"  error estimate (tol/100): one map step {a.get('error_map_step_rel', float('nan')):.1e} relative; "
              f"whole re-runs of periodic values: map points {a['error_map_points_rel']:.1e}, impact times "
              f"{a['error_impact_time_s']:.1e} s (nan: none sampled)"
              + (f"; {a['error_sensitive_values']} value(s) re-run differ by "
                 f"{a['error_map_points_rel_sensitive']:.1e} (sensitivity, not error: non-periodic, or periodic "
                 f"values whose re-run reaches another attractor from the same start)"
                 if a["error_sensitive_values"] else ""))
    print(f"  wrote {args.output}" + (f" and {args.plot}" if args.plot else ""))
    return 0


def _grazing_text(ds) -> str:
    n = ds.sizes.get("grazing", 0)
    if not n:
        return "no grazing located (bisected only where a neighbour is periodic)"
    ok = int(ds.grazing_confirmed.sum()) if "grazing_confirmed" in ds else n
    return f"grazing at {ok} value(s), impact-count jumps without a graze at {n - ok}"
