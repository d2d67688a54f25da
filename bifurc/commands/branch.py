"""`bifurc continue`: follow a periodic orbit in one parameter; locate folds, period doublings,
Neimark-Sacker points and grazings; optionally switch onto the doubled branch."""
from ._common import add_force_option, add_scene_options, check_outputs, check_plot, problem_kwargs
from ._options import add_settings_options


def register(subparsers):
    p = subparsers.add_parser("continue", help="continue a periodic orbit in one parameter (pseudo-arclength)",
                              description="Find a periodic orbit at --from (Newton by multiple shooting) and follow "
                                          "it toward --to by pseudo-arclength continuation through folds, stable and "
                                          "unstable parts alike; locate folds (LP), period doublings (PD), "
                                          "Neimark-Sacker points (NS) and grazings (G); stop where an event makes "
                                          "the map non-smooth and say why.")
    add_scene_options(p, default_tol=None)
    p.add_argument("--param", required=True, help="the continuation parameter (not relay_hz under mains forcing)")
    p.add_argument("--from", dest="p_from", type=float, required=True, help="start value of the parameter")
    p.add_argument("--to", dest="p_to", type=float, required=True, help="end value of the parameter")
    from ..orbits.method import PALC
    add_settings_options(p, PALC, "how the branch is followed (bifurc.PALC)")
    p.add_argument("--param2", default=None,
                   help="a second parameter: continue each fold, period doubling and grazing in (param, param2)")
    p.add_argument("--from2", type=float, default=None, help="start value of --param2 (the branch is computed there)")
    p.add_argument("--to2", type=float, default=None, help="end value of --param2")
    p.add_argument("--plot2", default=None, help="figure file of the two-parameter curves (curves.png)")
    p.add_argument("--diagram", default=None, help="a diagram.nc of the same parameter to draw behind the branch")
    p.add_argument("-o", "--output", default=None, help="netCDF file to write (branch.nc)")
    p.add_argument("--plot", default=None, help="figure file to write (branch.png)")
    add_force_option(p)
    p.set_defaults(func=run)


def run(args) -> int:
    import sys

    from ..orbits.branch import continue_orbit
    from ..storage.files import write_netcdf
    from ..orbits.periodic import OrbitNotFound
    from ..storage.schema import SPECIAL_KINDS
    if args.output:
        check_outputs(args, args.output)
    check_plot(args)
    if args.param2 is not None and (args.from2 is None or args.to2 is None):
        from maps.parameters import ParameterError
        raise ParameterError("--param2 needs --from2 and --to2")
    if args.plot2:
        from ..storage.files import check_figure_output
        check_figure_output(args.plot2, args.force, what="--plot2")
    diagram = None
    if args.diagram:
        from ..storage.load import load
        diagram = load(args.diagram, kind="diagram")
        if diagram.attrs.get("swept_parameter") != args.param:   # before computing the branch, not after
            from maps.parameters import ParameterError
            raise ParameterError(f"--diagram {args.diagram} sweeps {diagram.attrs.get('swept_parameter')!r}, the "
                                 f"branch {args.param!r}: give a diagram of --param {args.param}")
    from ..orbits.method import PALC
    from ._options import settings_from_args
    method = settings_from_args(PALC, args)

    def progress(line):
        print(f"  {line}", file=sys.stderr, flush=True)
    try:
        ds = continue_orbit(args.scene, args.param, (args.p_from, args.p_to), method, progress=progress,
                            param2=args.param2, span2=None if args.param2 is None else (args.from2, args.to2),
                            **problem_kwargs(args))
    except OrbitNotFound as exc:
        print(f"bifurc: error: no periodic orbit found at {args.param} = {args.p_from:g}: {exc.reason}",
              file=sys.stderr)   # a result, not a bad input: exit 1
        return 1
    par = args.param
    print(f"{ds.attrs['scene']}: {ds.sizes['point']} branch points in {par} from {float(ds[par][0]):.6g}, "
          f"{ds.attrs['run_seconds']:.1f} s, {ds.attrs['newton_iterations_total']} Newton iterations")
    for label, reason in zip(ds.attrs["branch_labels"].split(" | "), ds.attrs["branch_stop_reasons"].split(" | ")):
        print(f"  {label}: {reason}")
    for i in range(ds.sizes["special"]):
        kind = SPECIAL_KINDS[int(ds.special_kind[i])]
        tol = float(ds.special_tolerance[i])
        err = float(ds.special_multiplier_error[i])
        print(f"  {kind} at {par} = {float(ds.special_value[i]):.12g}"
              f"{'' if tol != tol else f' (+- {tol:.2g})'}; multipliers "
              + multipliers_text(ds.special_multiplier_abs.values[i], ds.special_multiplier_arg.values[i])
              + ("" if err != err else f"; multiplier error {err:.2g}")
              + (f"; {ds.special_note.values[i]}" if str(ds.special_note.values[i]) else ""))
    from ..plots.branch import codim2_points
    codim2 = codim2_points(ds)
    for c in range(ds.sizes.get("curve", 0)):
        n = int((ds.curve_id.values == c).sum())
        print(f"  curve {c} ({SPECIAL_KINDS[int(ds.curve_kind[c])]}, {n} points in "
              f"({par}, {args.param2})): {ds.curve_stop_reason.values[c]}")
        for kind, _, a, b, tol in (pt for pt in codim2 if pt[1] == c):
            print(f"    {kind} at ({par}, {args.param2}) = ({a:.12g}, {b:.12g}) (+- {tol:.2g})")
    if args.output:
        write_netcdf(ds, args.output, overwrite=args.force)
        print(f"  wrote {args.output}")
    if args.plot:
        from ..plots.branch import plot_branch
        plot_branch(ds, args.plot, diagram=diagram, overwrite=args.force)
        print(f"  wrote {args.plot}")
    if args.plot2:
        from ..plots.branch import plot_curves
        plot_curves(ds, args.plot2, overwrite=args.force)
        print(f"  wrote {args.plot2}")
    return 0


def multipliers_text(moduli, args) -> str:
    """Floquet multipliers as text: real ones signed (+1 at a fold, -1 at a period doubling), complex
    pairs as modulus and argument [rad] ("0.98 e^(+-1.23 i)"), NaN padding left out."""
    import math
    out, seen = [], set()
    for m, a in zip(moduli, args):
        if m != m:
            continue
        a = 0.0 if a != a else float(a)
        if abs(a) < 1e-9 or abs(abs(a) - math.pi) < 1e-9:
            out.append(f"{m * (1 if abs(a) < 1e-9 else -1):+.6g}")
        elif (round(m, 9), round(abs(a), 9)) not in seen:
            seen.add((round(m, 9), round(abs(a), 9)))
            out.append(f"{m:.6g} e^(+-{abs(a):.4g} i)")
    return ", ".join(out)
