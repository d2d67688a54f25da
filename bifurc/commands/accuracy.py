"""``bifurc accuracy``: work-precision study of the toolkit against scipy and the thesis' RK4.

    bifurc accuracy --scene thesis-1dof --preset matlab-listing --set V=90 --set relay_hz=9 \\
        --t-end 2 -o out/accuracy

writes ``accuracy.csv``, ``accuracy.nc`` and ``accuracy.png`` (error against run time).
"""
from __future__ import annotations

import argparse
from pathlib import Path

from maps.laws import DC_LAWS
from maps.parameters import ParameterError

from ._common import add_force_option, check_outputs, parse_floats

NAME = "accuracy"
#: files written into the output folder
OUTPUTS = ("accuracy.csv", "accuracy.nc", "accuracy.png")


def register(subparsers):
    from ..verification.ladders import DEFAULT_LADDERS
    p = subparsers.add_parser(NAME, help="error against run time: toolkit vs scipy and fixed-step RK4",
                              description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--scene", default="thesis-1dof", help="scene name (default thesis-1dof)")
    p.add_argument("--preset", default=None, help="parameter preset (thesis-text, matlab-listing, dynamics-listing)")
    p.add_argument("--set", dest="sets", action="append", default=[], metavar="NAME=VALUE",
                   help="override a parameter by its name (repeatable), e.g. --set V=90")
    p.add_argument("--relay-hz", type=float, default=None, help="shortcut for --set relay_hz=...")
    p.add_argument("--x0", default=None, metavar="x=0.001,v=0", help="initial state components by name")
    p.add_argument("--circuit", choices=("thesis", "kvl"), default=None,
                   help="circuit form (the scipy/RK4 baselines implement only 'thesis')")
    p.add_argument("--ac-sign", choices=("physical", "listing"), default=None, help="AC force sign")
    p.add_argument("--dc-law", choices=tuple(DC_LAWS), default=None,
                   help="DC-force law (default: the preset's; see bifurc simulate --help)")
    p.add_argument("--t-end", type=float, default=2.0, help="integration time [s] (default 2)")
    p.add_argument("--methods", default=",".join(DEFAULT_LADDERS),
                   help="comma-separated methods (default: all): " + ", ".join(DEFAULT_LADDERS))
    p.add_argument("--tols", default=None, help="comma-separated tolerances for every method except rk4-bisection "
                                                "(default: a ladder per method)")
    p.add_argument("--steps", default=None, help="comma-separated RK4 steps h [s] (default 1e-3 .. 1e-5)")
    p.add_argument("--reference", choices=("longdouble", "real128"), default="longdouble",
                   help="precision of the reference run (default longdouble at tol 1e-19; real128: tol 1e-28)")
    p.add_argument("--max-seconds", type=float, default=30.0,
                   help="stop a method's ladder after a run longer than this [s]")
    p.add_argument("-o", "--output", required=True, help="output directory")
    add_force_option(p)
    p.set_defaults(func=run)
    return p


def run(args) -> int:
    from ..verification.accuracy import DEFAULT_LADDERS, plot_work_precision, work_precision
    methods = [m.strip() for m in args.methods.split(",") if m.strip()]
    ladders = {}
    for m in methods:
        if m not in DEFAULT_LADDERS:
            raise ParameterError(f"unknown method {m!r}; methods: {', '.join(DEFAULT_LADDERS)}")
        if m == "rk4-bisection" and args.steps:
            ladders[m] = parse_floats(args.steps, "--steps")
        elif m != "rk4-bisection" and args.tols:
            ladders[m] = parse_floats(args.tols, "--tols")
        else:
            ladders[m] = DEFAULT_LADDERS[m]
    from ._common import parse_sets, parse_x0
    params = parse_sets(args.sets)
    if args.relay_hz is not None:
        params["relay_hz"] = args.relay_hz
    x0 = parse_x0(args.x0)
    out = Path(args.output)
    check_outputs(args, *(out / f for f in OUTPUTS))
    out.mkdir(parents=True, exist_ok=True)

    def progress(row):
        print(f"{row['method']:>16s} tol {row['tol']:8.1e}  error {row['final_state_error']:9.2e}  "
              f"impact-time error {row['impact_time_error']:9.2e} s  impacts {row['n_impacts']:3d}  "
              f"{row['run_seconds'] * 1e3:9.2f} ms", flush=True)

    ds = work_precision(args.scene, args.t_end, preset=args.preset, params=params, x0=x0, ladders=ladders,
                        reference=args.reference, max_seconds=args.max_seconds, progress=progress,
                        circuit=args.circuit, ac_sign=args.ac_sign, dc_law=args.dc_law)
    from ..storage.files import write_netcdf, write_text
    write_text(out / "accuracy.csv", ds.to_dataframe().to_csv(), overwrite=args.force)
    write_netcdf(ds, out / "accuracy.nc", overwrite=args.force)
    plot_work_precision(ds, out / "accuracy.png", overwrite=args.force)
    print(f"reference ({ds.attrs['reference_precision']}, tol {ds.attrs['reference_tol']:g}): "
          f"{ds.attrs['reference_n_impacts']} impacts, error bound {ds.attrs['reference_error_bound']:.1e}")
    print(f"wrote {out / 'accuracy.csv'}, {out / 'accuracy.nc'}, {out / 'accuracy.png'}")
    return 0


def main(argv=None) -> int:
    """``python -m bifurc.commands.accuracy ARGS`` = ``bifurc accuracy ARGS``."""
    import sys
    from ..cli import main as cli_main
    return cli_main(["accuracy"] + list(sys.argv[1:] if argv is None else argv))


if __name__ == "__main__":
    raise SystemExit(main())
