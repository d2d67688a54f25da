"""Scene resolution for analysis: a scene name, a Scene or a bare HybridSystem.

Names and Scenes go through :func:`maps.simulate.resolve` (the one resolver of ``maps``);
a bare :class:`~maps.hybrid.HybridSystem` is wrapped as a :class:`SystemScene` whose
parameters must all be given.
"""
from __future__ import annotations

from maps.hybrid import HybridSystem
from maps.parameters import ParameterError
from maps.simulate import resolve

__all__ = ["SystemScene", "resolve_scene"]


class SystemScene:
    """Lets a bare HybridSystem be swept like a scene: every parameter must be given."""

    def __init__(self, system):
        self.system, self.name, self.options, self.preset = system, system.name, None, None

    def initial_state(self, **components):
        x0 = {n: 0.0 for n in self.system.state_names}
        for k, v in components.items():
            if k not in x0:
                raise ParameterError(f"unknown state {k!r} for {self.name!r}; its states are: {', '.join(x0)}")
            x0[k] = float(v)
        return x0

    def parameters(self, preset=None, **values):
        return self.system.validate(values)


def resolve_scene(scene, params, preset=None, circuit=None, ac_sign=None, dc_law=None, soil=None,
                  compaction=None):
    """(scene-like, {name: (value, provenance)}) for a scene name, Scene or HybridSystem."""
    if isinstance(scene, SystemScene):
        scene = scene.system
    if isinstance(scene, HybridSystem):
        if preset or circuit or ac_sign or dc_law or soil or compaction:
            raise ParameterError("preset, circuit, ac_sign, dc_law, soil and compaction apply to scenes, not to a bare HybridSystem")
        values = scene.validate(params or {})
        return SystemScene(scene), {k: (v, "set by user") for k, v in values.items()}
    return resolve(scene, params, preset, circuit, ac_sign, dc_law=dc_law, soil=soil, compaction=compaction)
