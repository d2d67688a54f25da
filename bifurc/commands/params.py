"""`bifurc params`: every parameter of a scene with its value, unit, allowed range and provenance."""
import maps

from ._common import add_parameter_options, parse_sets


def register(subparsers):
    p = subparsers.add_parser("params", help="list a scene's parameters: value, unit, range, provenance",
                              description="List every parameter of a scene: name, value, unit, allowed range "
                                          "and where the value comes from (preset, scene or --set).")
    add_parameter_options(p)
    p.set_defaults(func=run)


def rows(scene, preset=None, params=None) -> list[tuple]:
    """(name, value, unit, allowed range, long name, provenance) for each parameter of ``scene``."""
    sc = maps.get_scene(scene)
    system = sc.system
    out = []
    for name, (value, source) in sc.parameters_with_provenance(preset, **(params or {})).items():
        p = system.parameter(name)
        out.append((name, f"{value:g}", p.unit, p.range_text(), p.long_name, source))
    return out


def run(args) -> int:
    table = rows(args.scene, args.preset, parse_sets(args.sets))
    head = ("name", "value", "unit", "allowed range", "meaning", "provenance")
    widths = [max(len(r[j]) for r in table + [head]) for j in range(len(head) - 1)]
    for r in [head] + table:
        print("  ".join(f"{c:<{w}}" for c, w in zip(r, widths)) + "  " + r[-1])
    return 0
