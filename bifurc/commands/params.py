"""`bifurc params`: every parameter of a scene with its value, unit, allowed range and provenance."""
from maps.laws import DC_LAWS

from ._common import add_force_option, add_parameter_options, parse_sets


def register(subparsers):
    p = subparsers.add_parser("params", help="list a scene's parameters: value, unit, range, provenance",
                              description="List every parameter of a scene: name, value, unit, allowed range "
                                          "and where the value comes from (preset, scene or --set).")
    g = add_parameter_options(p)
    g.add_argument("--soil", choices=("viscous", "coulomb", "drift"), default=None,
                   help="2-DOF soil law (default: the scene's); drift adds k_s, c_s and P_max")
    g.add_argument("--dc-law", choices=tuple(DC_LAWS), default=None,
                   help="DC-force law (default: the preset's); catalogue adds F_dc_sat, u_dc and s_dc")
    g.add_argument("--compaction", action="store_true", default=None,
                   help="coulomb and drift soils: the resistance grows with depth (adds soil_depth_scale)")
    p.add_argument("--plot", metavar="FILE", default=None,
                   help="also draw the force laws as the thesis plots them (Figs 4.5, 4.6, 4.10-4.12, 4.26: DC force "
                        "of every DC law with Table 4.1, inductance and its derivatives with Table 4.2, AC force "
                        "over the run's start) into FILE (.png, .pdf, .svg)")
    add_force_option(p)
    p.set_defaults(func=run)


def rows(scene, preset=None, params=None, soil=None, compaction=None, dc_law=None) -> list[tuple]:
    """(name, value, unit, allowed range, long name, provenance) for each parameter of ``scene``."""
    from maps.problem import problem
    pb = problem(scene, preset, params, soil=soil, compaction=compaction, dc_law=dc_law)
    system, table = pb.scene.system, pb.table
    out = []
    for name, (value, source) in table.items():
        p = system.parameter(name)
        out.append((name, f"{value:g}", p.unit, p.range_text(), p.long_name, source))
    return out


def optional_rows(scene, preset=None, params=None, soil=None, compaction=None, dc_law=None) -> list[tuple]:
    """(name, value if set, unit, allowed range, long name, what it adds) for the optional elements
    (maps.laws.ELEMENTS) the scene can take and does not use: ``--set NAME=VALUE`` switches one on."""
    from maps.laws import ELEMENTS
    from maps.model import PARAMETERS
    from maps.presets import COMMON
    from maps.problem import problem
    pb = problem(scene, preset, params, soil=soil, compaction=compaction, dc_law=dc_law)
    o = pb.scene.options
    if o is None:
        return []
    usable = {"air_damping": True, "rear_stop": o.stop, "dc_delay": o.dc and o.relay == "antiphase"}
    out = []
    for opt, (name, what) in ELEMENTS.items():
        if usable[opt] and not getattr(o, opt):
            p = PARAMETERS[name]
            out.append((name, f"{COMMON[name][0]:g}", p.unit, p.range_text(), p.long_name,
                        f"OFF (--set {name}=VALUE switches it on): {what}; default value: {COMMON[name][1]}"))
    return out


def well_rows(scene, preset=None, params=None, soil=None, compaction=None, dc_law=None) -> list[tuple]:
    """(name, value, unit, settable range or "derived", meaning, how it is set) for the DC well's
    derived quantities (maps.well; empty for a scene without a DC solenoid)."""
    from maps.problem import problem
    from maps.well import WELL_INPUTS, WELL_OUTPUTS, well
    pb = problem(scene, preset, params, soil=soil, compaction=compaction, dc_law=dc_law)
    out = []
    for name, value in well(pb.options, pb.values).items():
        unit, meaning = WELL_OUTPUTS[name]
        if name in WELL_INPUTS:
            how = (f"--set {name}=VALUE sets it ({'d_dc' if name == 'dc_rest' else 'dc_scale'} follows; the law's "
                   f"shape kept)" + (" [set]" if name in (params or {}) else ""))
            rng = WELL_INPUTS[name].range_text()
        else:
            how, rng = "derived", "-"
        out.append((name, f"{value:g}", unit, rng, meaning, how))
    return out


def run(args) -> int:
    sets = parse_sets(args.sets)
    if args.plot is not None:
        from ..storage.files import check_figure_output
        check_figure_output(args.plot, args.force, what="--plot")
        from ..plots.laws import check_force_laws
        check_force_laws(args.scene, args.preset, sets)
    table = rows(args.scene, args.preset, sets, args.soil, args.compaction, args.dc_law)
    extra = optional_rows(args.scene, args.preset, sets, args.soil, args.compaction, args.dc_law)
    wells = well_rows(args.scene, args.preset, sets, args.soil, args.compaction, args.dc_law)
    head = ("name", "value", "unit", "allowed range", "meaning", "provenance")
    widths = [max(len(r[j]) for r in table + extra + wells + [head]) for j in range(len(head) - 1)]
    for r in [head] + table:
        print("  ".join(f"{c:<{w}}" for c, w in zip(r, widths)) + "  " + r[-1])
    if extra:
        print("\noptional elements, off (today's model):")
        for r in extra:
            print("  ".join(f"{c:<{w}}" for c, w in zip(r, widths)) + "  " + r[-1])
    if wells:
        from maps.well import WELL_DEFINITIONS
        from maps.problem import problem
        law = problem(args.scene, args.preset, sets, soil=args.soil, compaction=args.compaction,
                      dc_law=args.dc_law).options.dc_law
        print(f"\nDC well, derived (dc_law {law}; {WELL_DEFINITIONS}):")
        for r in wells:
            print("  ".join(f"{c:<{w}}" for c, w in zip(r, widths)) + "  " + r[-1])
    if args.plot is not None:
        from ..plots.laws import plot_force_laws
        plot_force_laws(args.scene, args.preset, sets, args.dc_law, path=args.plot, overwrite=args.force)
        print(f"wrote {args.plot}")
    return 0
