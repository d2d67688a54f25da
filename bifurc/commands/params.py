"""`bifurc params`: every parameter of a scene with its value, unit, allowed range and provenance."""
from ._common import add_parameter_options, parse_sets


def register(subparsers):
    p = subparsers.add_parser("params", help="list a scene's parameters: value, unit, range, provenance",
                              description="List every parameter of a scene: name, value, unit, allowed range "
                                          "and where the value comes from (preset, scene or --set).")
    g = add_parameter_options(p)
    g.add_argument("--soil", choices=("viscous", "coulomb", "drift"), default=None,
                   help="2-DOF soil law (default: the scene's); drift adds k_s, c_s and P_max")
    g.add_argument("--compaction", action="store_true", default=None,
                   help="coulomb and drift soils: the resistance grows with depth (adds soil_depth_scale)")
    p.set_defaults(func=run)


def rows(scene, preset=None, params=None, soil=None, compaction=None) -> list[tuple]:
    """(name, value, unit, allowed range, long name, provenance) for each parameter of ``scene``."""
    from maps.simulate import resolve
    sc, table = resolve(scene, params, preset, soil=soil, compaction=compaction)
    system = sc.system
    out = []
    for name, (value, source) in table.items():
        p = system.parameter(name)
        out.append((name, f"{value:g}", p.unit, p.range_text(), p.long_name, source))
    return out


def run(args) -> int:
    table = rows(args.scene, args.preset, parse_sets(args.sets), args.soil, args.compaction)
    head = ("name", "value", "unit", "allowed range", "meaning", "provenance")
    widths = [max(len(r[j]) for r in table + [head]) for j in range(len(head) - 1)]
    for r in [head] + table:
        print("  ".join(f"{c:<{w}}" for c, w in zip(r, widths)) + "  " + r[-1])
    return 0
