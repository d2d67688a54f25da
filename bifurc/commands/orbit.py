"""`bifurc orbit`: a periodic orbit (stable or unstable) by multiple shooting, with its multipliers."""
from ._common import add_force_option, add_scene_options, check_outputs, problem_kwargs
from ._options import add_settings_options


def register(subparsers):
    p = subparsers.add_parser("orbit", help="find a periodic orbit and its Floquet multipliers",
                              description="Find a periodic orbit of the stroboscopic map (stable or unstable) by "
                                          "Newton's method with multiple shooting; print its period, impacts, "
                                          "multipliers, stability, residual and multiplier error.")
    add_scene_options(p, default_tol=None)
    from ..orbits.method import Shooting
    add_settings_options(p, Shooting, "how the orbit is found (bifurc.Shooting)")
    p.add_argument("-o", "--output", default=None, help="netCDF file to write")
    add_force_option(p)
    p.set_defaults(func=run)


def run(args) -> int:
    from ..storage.files import write_netcdf
    from ..orbits.orbit import periodic_orbit
    from ..orbits.periodic import OrbitNotFound
    from ..orbits.method import Shooting
    from ._options import settings_from_args
    if args.output:
        check_outputs(args, args.output)
    try:
        ds = periodic_orbit(args.scene, settings_from_args(Shooting, args), **problem_kwargs(args))
    except OrbitNotFound as exc:
        import sys
        print(f"bifurc: error: no periodic orbit found: {exc.reason}", file=sys.stderr)   # a result: exit 1
        return 1
    mu = ds.multiplier_abs.values
    args_ = ds.multiplier_arg.values
    err = float(ds.multiplier_error)
    print(f"{ds.attrs['scene']}: period {int(ds.period)} (strobe periods from k = {ds.attrs['k0']}), "
          f"{int(ds.impacts_per_period)} impact{'' if int(ds.impacts_per_period) == 1 else 's'} per period, "
          f"{'stable' if int(ds.stable) else 'UNSTABLE'}")
    print("  multipliers |mu| (arg): " + ", ".join(f"{m:.6g} ({a:+.3f})" for m, a in zip(mu, args_)))
    print(f"  Newton residual {float(ds.newton_residual):.2g} after {ds.attrs['newton_iterations']} iterations; "
          f"multiplier error {'not measured' if err != err else f'{err:.2g}'}; "
          f"min clearance {float(ds.min_clearance):.3g} m; {float(ds.run_seconds):.2f} s")
    if args.output:
        write_netcdf(ds, args.output, overwrite=args.force)
        print(f"  wrote {args.output}")
    return 0
