"""`bifurc scenes`: one line per scene."""
import maps


def register(subparsers):
    p = subparsers.add_parser("scenes", help="list the scenes")
    p.set_defaults(func=run)


def run(args) -> int:
    width = max(map(len, maps.scene_names()))
    for name in maps.scene_names():
        sc = maps.get_scene(name)
        states = ",".join(sc.system.state_names)
        print(f"{name:<{width}}  [{states}]  {sc.summary}; preset {sc.preset}")
    return 0
