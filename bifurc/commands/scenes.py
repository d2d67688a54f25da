"""`bifurc scenes`: one line per scene (name, states, summary, default preset)."""
import maps


def register(subparsers):
    p = subparsers.add_parser("scenes", help="list the scenes",
                              description="List the scenes: name, states, what it models, default preset.")
    p.set_defaults(func=run)


def run(args) -> int:
    scenes, broken = [], []
    for name in maps.scene_names():
        try:
            scenes.append(maps.get_scene(name))
        except maps.ParameterError as exc:      # an installed entry point that does not load
            broken.append(str(exc))
    states = {sc.name: "[" + ",".join(sc.system.state_names) + "]" for sc in scenes}
    w_name = max(len(sc.name) for sc in scenes)
    w_states = max(map(len, states.values()))
    for sc in scenes:
        law = f", dc_law {sc.options.dc_law}" if sc.options is not None and sc.options.dc else ""
        if sc.options is not None and sc.options.dof == 2:
            law += f", soil {sc.options.soil} (--soil viscous|coulomb|drift)"
        preset = f"preset {sc.preset}" if sc.preset else "no preset: parameters by name"
        print(f"{sc.name:<{w_name}}  {states[sc.name]:<{w_states}}  {sc.summary}; {preset}{law}")
    for line in broken:
        print(line)
    return 0
