"""`bifurc attractors`: the attractor census over one parameter (basin fractions, matching, events)."""
from ._common import add_force_option, add_scene_options, check_outputs, check_plot, scene_kwargs


def register(subparsers):
    p = subparsers.add_parser("attractors", help="every attractor and its basin fraction over one parameter",
                              description="Run an ensemble of starts at each value; find every attractor by recurrence "
                                          "on a state-space grid, its basin fraction with a 95 % Wilson interval, and "
                                          "follow the attractors across the values (seeding and matching). Outcomes "
                                          "(escaped, not_converged, failed, neutral, transient: still on a chaotic "
                                          "saddle at --max-periods) are attractor entries, so the fractions sum to 1; "
                                          "eventual_fraction apportions the transient starts by where those that left "
                                          "the saddle went. --from A --to A --n 1 is one value.")
    add_scene_options(p, default_tol=1e-10)
    p.add_argument("--param", default="V", help="parameter to vary (default V)")
    p.add_argument("--from", dest="start", type=float, required=True, help="first value")
    p.add_argument("--to", dest="stop", type=float, required=True, help="last value")
    p.add_argument("--n", type=int, default=1, help="number of values (default 1)")
    p.add_argument("--starts", type=int, default=200, help="fresh starts per value (default 200)")
    src = p.add_mutually_exclusive_group()
    src.add_argument("--box", default=None, metavar="x=0:0.03,v=-1.5:1.5",
                     help="states drawn uniformly within SI bounds (others: the scene's start); default: the "
                          "scene's declared box")
    src.add_argument("--starts-from", choices=("switch-on",), default=None,
                     help="switch-on: the scene's declared switch-on distribution (thesis: the bar at rest on the "
                          "stop, the circuit at rest, a declared spread)")
    p.add_argument("--seed", type=int, default=0, help="random seed of the starts (default 0)")
    p.add_argument("--cells", type=int, default=100, help="recurrence grid cells per box side (default 100)")
    p.add_argument("--max-periods", type=int, default=2000,
                   help="strobe periods after which a start is transient (on a chaotic saddle) or not_converged "
                        "(default 2000)")
    p.add_argument("--max-period", type=int, default=16, help="longest period searched (default 16; a contracting "
                   "record that repeats at a longer lag, up to a quarter of its length, is polished at that lag)")
    p.add_argument("--no-link", action="store_true",
                   help="do not continue appearing/disappearing orbits to link them to local bifurcations")
    p.add_argument("--refine-from", nargs="+", default=None, metavar="BRANCH.nc",
                   help="branch files from continuation in --param (bifurc continue -o ...): a value is added between "
                        "each two of their located events that share a step")
    p.add_argument("--batch-size", type=int, default=4, help="starts per heyoka batch (SIMD lanes; default 4)")
    p.add_argument("--workers", type=int, default=None,
                   help="worker processes (default: every available core, at least 4 values each)")
    p.add_argument("--scheduler", default=None, help="Dask scheduler address tcp://host:port")
    p.add_argument("-o", "--output", required=True, help="netCDF file to write")
    p.add_argument("--plot", default=None, help="figure file (.png, .pdf, .svg, ...)")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    add_force_option(p)
    p.set_defaults(func=run)


def run(args) -> int:
    import numpy as np

    from maps.parameters import ParameterError

    from ..attractors.atlas import attractors
    from ..attractors.starts import check_box, parse_box
    if not 1 <= args.n <= 100_000:
        raise ParameterError(f"--n {args.n}: from 1 to 100000 values")
    if not 1 <= args.starts <= 10_000_000:
        raise ParameterError(f"--starts {args.starts}: from 1 to 10000000 starts per value")
    for name, v, lo in (("--cells", args.cells, 2), ("--max-periods", args.max_periods, 1),
                        ("--max-period", args.max_period, 1), ("--batch-size", args.batch_size, 1)):
        if v < lo:
            raise ParameterError(f"{name} {v}: at least {lo}")
    if args.workers is not None and not 1 <= args.workers <= 1024:
        raise ParameterError(f"--workers {args.workers}: from 1 to 1024")
    if args.scheduler is not None:
        from ._common import check_scheduler
        check_scheduler(args.scheduler)
    if args.n == 1 and args.start != args.stop:
        raise ParameterError(f"--n 1 needs --from = --to (got {args.start:g} and {args.stop:g})")
    kw = scene_kwargs(args)
    box = None
    if args.box is not None:
        from maps.problem import problem
        pb = problem(args.scene, kw["preset"], kw["params"], circuit=kw["circuit"], ac_sign=kw["ac_sign"],
                     dc_law=kw["dc_law"], soil=kw["soil"], compaction=kw["compaction"])
        box = check_box(parse_box(args.box), pb.system, "--box")
    check_outputs(args, args.output)
    check_plot(args)
    refine = None
    if args.refine_from:
        from ..storage.load import load
        refine = [load(f, kind="branch") for f in args.refine_from]
    values = np.linspace(args.start, args.stop, args.n)
    params = dict(kw["params"])
    ds = attractors(args.scene, args.param, values, starts=args.starts_from or "box", n_starts=args.starts, box=box,
                    seed=args.seed, preset=kw["preset"], params=params or None, tol=kw["tol"], cells=args.cells,
                    max_periods=args.max_periods, max_period=args.max_period, link=not args.no_link,
                    batch_size=args.batch_size, workers=args.workers, scheduler=args.scheduler,
                    progress=not args.quiet, path=args.output, overwrite=args.force, refine=refine,
                    circuit=kw["circuit"], ac_sign=kw["ac_sign"], dc_law=kw["dc_law"], soil=kw["soil"],
                    compaction=kw["compaction"])
    if args.plot:
        from ..attractors.plots import plot_attractors
        plot_attractors(ds, args.plot, overwrite=args.force)
    _summary(ds, args)
    return 0


def _summary(ds, args) -> None:
    from ..attractors.dataset import census_lines
    print("\n".join(census_lines(ds)))
    print(f"  wrote {args.output}" + (f" and {args.plot}" if args.plot else ""))
