"""`bifurc simulate`: a time history to netCDF and a figure."""
from ._common import add_force_option, add_scene_options, check_outputs, check_plot, scene_kwargs


def register(subparsers):
    p = subparsers.add_parser("simulate", help="integrate a scene and write its time history",
                              description="Integrate a scene; write the time history (netCDF) and a figure.")
    add_scene_options(p)
    span = p.add_mutually_exclusive_group()
    span.add_argument("--periods", type=float, default=None, help="duration in strobe periods (relay periods for the thesis scenes)")
    span.add_argument("--t-end", type=float, default=None, help="duration [s]")
    p.add_argument("--transient", type=float, default=None,
                   help="2-DOF: progression measures after this time [s] (default: the second half)")
    p.add_argument("--dt", type=float, default=None, help="sampling step [s] (default 2e-4)")
    p.add_argument("-o", "--output", default=None, help="netCDF file to write")
    p.add_argument("--plot", default=None, help="figure file for the time history (.png, .pdf, .svg, ...)")
    add_force_option(p)
    p.set_defaults(func=run)


def run(args) -> int:
    import maps

    kw = scene_kwargs(args)
    check_outputs(args, args.output)
    check_plot(args)
    periods, t_end = args.periods, args.t_end
    if periods is None and t_end is None:
        periods = 20.0 if maps.get_scene(args.scene).system.declares_clock else None
        t_end = None if periods else 2.0
    ds = maps.simulate(args.scene, periods=periods, t_end=t_end, dt=args.dt, transient=args.transient, **kw)
    if args.output:
        from ..storage.files import write_netcdf
        write_netcdf(ds, args.output, overwrite=args.force)
    if args.plot:
        from ..plots.history import plot_time_history
        plot_time_history(ds, args.plot, overwrite=args.force)
    a = ds.attrs
    print(f"{a['scene']}: status {a['status']}, t = {a['t_end_reached']:.6g} s, {ds.sizes['impact']} impacts, "
          f"{a['n_steps']} steps, run {a['run_seconds']:.3g} s (compile {a['compile_seconds']:.3g} s once)")
    if "progression_rate" in ds:
        w = a["progression_window"]
        print(f"  progression {1e3 * float(ds.progression_rate):.4g} mm/s over {w[0]:.4g}-{w[1]:.4g} s "
              f"({1e6 * float(ds.progression_per_period):.4g} um per relay period), soil holds the rig "
              f"{100 * float(ds.stuck_fraction):.3g} % of it, impact energy "
              f"{1e3 * float(ds.impact_energy_per_period):.4g} mJ per relay period")
    if a["status"] != "ok":
        print(f"  {a.get('failure', '')}")
    for path in (args.output, args.plot):
        if path:
            print(f"  wrote {path}")
    return 0
