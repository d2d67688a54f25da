"""`bifurc attractors`: the attractor census over one parameter (basin fractions, matching, events)."""
from ..attractors.method import Box, ByDistance, Census, SwitchOn
from ._common import add_range_options, add_scene_options, check_outputs, check_plot, problem_kwargs
from ._options import add_run_options, add_settings_options, run_from_args, settings_from_args


def register(subparsers):
    p = subparsers.add_parser("attractors", help="every attractor and its basin fraction over one or two parameters",
                              description="Run an ensemble of starts at each parameter point; find every attractor by "
                                          "recurrence on a state-space grid, its basin fraction with a 95 % Wilson "
                                          "interval, and follow the attractors across the points (seeding and "
                                          "matching). Outcomes (escaped, not_converged, failed, neutral, transient: "
                                          "still on a chaotic saddle at --budget) are attractor entries, so the "
                                          "fractions sum to 1; eventual_fraction apportions the transient starts by "
                                          "where those that left the saddle went. --from A --to A --n 1 is one value; "
                                          "--param2 ... adds a second parameter (a grid of points, as bifurc map).")
    add_scene_options(p, default_tol=None)
    add_range_options(p, "V", 1)
    add_range_options(p, None, 1, "2", required=False)      # the census runs on the grid --param x --param2
    add_settings_options(p, Census, "how each point is censused (bifurc.Census)")
    g = p.add_argument_group("the fresh starts (bifurc.Box, bifurc.SwitchOn) and the matcher (bifurc.ByDistance)")
    g.add_argument("--starts", type=int, default=Box().n, help=f"fresh starts per point (default {Box().n})")
    src = g.add_mutually_exclusive_group()
    src.add_argument("--box", default=None, metavar="x=0:0.03,v=-1.5:1.5",
                     help="states drawn uniformly within SI bounds (others: the scene's start); default: the "
                          "scene's declared box")
    src.add_argument("--starts-from", choices=("switch-on",), default=None,
                     help="switch-on: the scene's declared switch-on distribution (thesis: the bar at rest on the "
                          "stop, the circuit at rest, a declared spread)")
    g.add_argument("--seed", type=int, default=0, help="random seed of the starts (default 0; 0 to 2**63 - 1)")
    add_settings_options(g, ByDistance)
    p.add_argument("--refine-from", nargs="+", default=None, metavar="BRANCH.nc",
                   help="branch files from continuation in --param (bifurc continue -o ...): a value is added between "
                        "each two of their located events that share a step")
    add_run_options(p, "point")
    p.set_defaults(func=run)


def run(args) -> int:
    import numpy as np

    from maps.parameters import ParameterError

    from ..attractors.atlas import attractors, grid_points
    from ..attractors.starts import check_box, parse_box
    if not 1 <= args.n <= 100_000:
        raise ParameterError(f"--n {args.n}: from 1 to 100000 values")
    if not 1 <= args.n2 <= 100_000:
        raise ParameterError(f"--n2 {args.n2}: from 1 to 100000 values")
    if args.n == 1 and args.start != args.stop:
        raise ParameterError(f"--n 1 needs --from = --to (got {args.start:g} and {args.stop:g})")
    two = args.param2 is not None
    if two and (args.start2 is None or args.stop2 is None):
        raise ParameterError("--param2 needs --from2 and --to2")
    if not two and (args.start2 is not None or args.stop2 is not None or args.n2 != 1):
        raise ParameterError("--from2/--to2/--n2 need --param2")
    if two and args.param2 == args.param:
        raise ParameterError(f"--param2 {args.param2}: must be another parameter than --param")
    if two and args.n2 == 1 and args.start2 != args.stop2:
        raise ParameterError(f"--n2 1 needs --from2 = --to2 (got {args.start2:g} and {args.stop2:g})")
    method = settings_from_args(Census, args)
    matcher = settings_from_args(ByDistance, args)
    sampler = SwitchOn(n=args.starts, seed=args.seed) if args.starts_from else Box(n=args.starts, seed=args.seed)
    run_on = run_from_args(args)
    if args.scheduler is not None:
        from ._common import check_scheduler
        check_scheduler(args.scheduler)
    kw = problem_kwargs(args)
    if args.box is not None:
        from maps.problem import problem
        pb = problem(args.scene, **kw)
        sampler = sampler.replace(box=check_box(parse_box(args.box), pb.system, "--box"))
        scene = pb
        kw = {}
    else:
        scene = args.scene
    check_outputs(args, args.output)
    check_plot(args)
    refine = None
    if args.refine_from:
        if two:
            raise ParameterError("--refine-from needs one parameter (no --param2)")
        from ..storage.load import load
        refine = [load(f, kind="branch") for f in args.refine_from]
    values = np.linspace(args.start, args.stop, args.n)
    if two:
        param, values = None, grid_points(args.param, values, args.param2, np.linspace(args.start2, args.stop2, args.n2))
    else:
        param = args.param
    ds = attractors(scene, param, values, method, starts=sampler, match=matcher, run=run_on,
                    **({"refine": refine} if refine is not None else {}), **kw)
    if args.plot:
        if two:
            from ..plots.census_map import plot_census_map
            plot_census_map(ds, args.plot, overwrite=args.force)
        else:
            from ..attractors.plots import plot_attractors
            plot_attractors(ds, args.plot, overwrite=args.force)
    _summary(ds, args)
    return 0


def _summary(ds, args) -> None:
    """One line per parameter point: the attractors present with their basin fractions and intervals (one
    parameter: :func:`bifurc.attractors.dataset.census_lines`, with the located events)."""
    import numpy as np

    if not args.param2:
        from ..attractors.dataset import census_lines
        print("\n".join(census_lines(ds)))
        print(f"  wrote {args.output}" + (f" and {args.plot}" if args.plot else ""))
        return
    from ..attractors.dataset import attractor_count
    from ..labels.classify import describe
    names = [args.param, args.param2]
    shape = tuple(ds.sizes[k] for k in names)
    print(f"{ds.attrs['scene']}: {' x '.join(f'{k} {ds[k].values[0]:g}..{ds[k].values[-1]:g}' for k in names)} "
          f"({' x '.join(map(str, shape))} points x {args.starts} starts) in {ds.attrs['census_seconds']:.1f} s: "
          f"{attractor_count(ds)} attractor(s)")
    frac = ds.basin_fraction.values.reshape(-1, ds.sizes["attractor"])
    code, period, impacts = (ds[k].values.reshape(frac.shape) for k in ("class_code", "period", "impacts_per_period"))
    label = ds.attractor_label.values

    def legend(flat, j):
        if not str(label[j]).startswith("A"):
            return str(label[j]).replace("_", " ")
        return f"{label[j]} {describe(int(code[flat, j]), int(period[flat, j]), int(impacts[flat, j]))}"
    low = ds.basin_fraction_low.values.reshape(frac.shape)
    high = ds.basin_fraction_high.values.reshape(frac.shape)
    for flat, idx in enumerate(np.ndindex(*shape)):
        where = ", ".join(f"{k} = {ds[k].values[i]:g}" for k, i in zip(names, idx))
        parts = []
        for j in np.flatnonzero(frac[flat] > 0):
            parts.append(f"{legend(flat, j)} {frac[flat, j]:.3f} [{low[flat, j]:.3f}, {high[flat, j]:.3f}]")
        print(f"  {where}: " + "; ".join(parts))
    print(f"  wrote {args.output}" + (f" and {args.plot}" if args.plot else ""))
