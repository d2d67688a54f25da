"""Named scenes: a model variant, its states and its default parameters.

A scene's DC-force law (option ``dc_law``) follows the preset its values come from
(``maps.presets.PRESET_DC_LAW``): thesis-text uses "fit", matlab-listing and dynamics-listing
"listing", unless the law was chosen (``with_options(dc_law=...)``).  The values a scene returns
carry the model they belong to (:class:`ParameterValues`), so a map given them runs that model.

>>> from maps import get_scene
>>> scene = get_scene("thesis-1dof")
>>> params = scene.parameters(preset="matlab-listing", V=90, relay_hz=9)   # params.options.dc_law: listing
"""
from __future__ import annotations

from dataclasses import dataclass, field, fields, replace

from .examples import forced_oscillator_with_stop
from .model import ModelOptions, build_system
from .parameters import ParameterError
from .presets import preset_dc_law, preset_values

_BUILT: dict = {}


class ParameterValues(dict):
    """Validated parameter values {name: value} that remember the model they belong to: the
    ``scene`` (a :class:`Scene` with its options applied), the ``preset`` they came from and
    their ``provenance`` {name: source}.  A plain dict in every other respect."""

    def __init__(self, values, scene=None, preset=None, provenance=None):
        super().__init__(values)
        self.scene, self.preset, self.provenance = scene, preset, dict(provenance or {})

    @property
    def options(self):
        """The structural options of the model these values belong to (None: not a model scene)."""
        return self.scene.options if self.scene is not None else None

    def __reduce__(self):
        return (ParameterValues, (dict(self), self.scene, self.preset, self.provenance))


class SystemBuilder:
    """A builder that returns one given :class:`~maps.hybrid.HybridSystem` (a user's system as a scene)."""

    def __init__(self, system):
        self.system = system

    def __call__(self):
        return self.system


@dataclass(frozen=True)
class Scene:
    """A model variant with defaults: ``options`` fix the structure (what compiles).

    A scene of another system (``builder``: a function returning its HybridSystem, e.g. the
    impact oscillator of :mod:`maps.examples`) has no structural options and no preset: its
    parameter defaults are its ``overrides``."""

    name: str
    summary: str
    options: ModelOptions | None
    preset: str | None = "thesis-text"
    overrides: dict = field(default_factory=dict)   # name -> (value, provenance)
    x0: dict = field(default_factory=dict)          # default initial state by name [SI]
    builder: object = None
    chosen: frozenset = frozenset()                 # options set by with_options (a preset leaves them)
    address: str | None = None                      # "package.module:NAME" it was loaded from (maps.registry)
    box: dict = field(default_factory=dict)         # state -> (low, high) [SI]: the attractor census' default box
    switch_on: dict = field(default_factory=dict)   # state -> (low, high) [SI]: the "switch-on" start distribution

    @property
    def system(self):
        if self.builder is not None:
            if self.builder not in _BUILT:
                _BUILT[self.builder] = self.builder()
            return _BUILT[self.builder]
        return build_system(self.options)

    @property
    def key(self) -> tuple:
        """What identifies the compiled model: the scene's name and options (or its builder)."""
        return (self.name, self.options.key() if self.options is not None else self.builder)

    def for_preset(self, preset: str | None) -> "Scene":
        """This scene with the DC-force law of ``preset`` unless the law was chosen."""
        if preset is None or self.options is None or not self.options.dc or "dc_law" in self.chosen:
            return self
        law = preset_dc_law(preset)
        return self if law == self.options.dc_law else replace(self, options=replace(self.options, dc_law=law))

    def with_options(self, **kw) -> "Scene":
        """The same scene with other structural options (e.g. circuit='kvl')."""
        if self.options is None:
            raise ParameterError(f"scene {self.name!r} has no structural options (circuit, ac_sign, dc_law, ...): "
                                 f"they belong to the electro-vibro-impact scenes")
        unknown = sorted(set(kw) - {f.name for f in fields(self.options)})
        if unknown:
            raise ParameterError(f"unknown option {unknown[0]!r}; options: "
                                 f"{', '.join(f.name for f in fields(self.options))}")
        return replace(self, options=replace(self.options, **kw), chosen=self.chosen | frozenset(kw))

    def with_elements(self, names) -> "Scene":
        """This scene with the optional elements (:data:`maps.laws.ELEMENTS`) whose parameter is
        among ``names`` switched on: setting ``c_air``, ``e_rear`` or ``tau_dc`` adds its element."""
        from .laws import ELEMENTS
        if self.options is None:
            return self
        on = {opt: True for opt, (par, _) in ELEMENTS.items() if par in names and not getattr(self.options, opt)}
        return self.with_options(**on) if on else self

    def parameters(self, preset: str | None = None, **overrides) -> ParameterValues:
        """Validated values of this scene's parameters: preset, scene defaults, then overrides;
        they carry the scene under that preset (its DC-force law, :meth:`for_preset`).  Setting the
        parameter of an optional element (``c_air``, ``e_rear``, ``tau_dc``) switches it on."""
        sc = self.for_preset(preset).with_elements(overrides)
        table = sc.parameters_with_provenance(preset, **overrides)
        return ParameterValues({k: v for k, (v, _) in table.items()}, sc, preset,
                               {k: src for k, (_, src) in table.items()})

    def parameters_with_provenance(self, preset: str | None = None, **overrides) -> dict:
        """name -> (value, provenance) for this scene's parameters, under this scene's options as
        they are (see :meth:`for_preset`)."""
        system = self.system
        from .well import WELL_INPUTS, apply_inputs, check_inputs
        inputs = {k: overrides.pop(k) for k in list(overrides) if k in WELL_INPUTS}
        check_inputs(inputs, overrides, self.name)
        if self.options is None:
            if preset is not None:
                raise ParameterError(f"scene {self.name!r} has no presets; set its parameters by name")
            table = {}
        else:
            table = preset_values(preset or self.preset, dc_law=self.options.dc_law)
        if preset is None or preset == self.preset:
            table.update({k: (float(v), f"scene {self.name}: {src}") for k, (v, src) in self.overrides.items()})
        for k, v in overrides.items():
            if k not in system.param_names:
                raise ParameterError(f"unknown parameter {k!r} for scene {self.name!r}; its parameters are: "
                                     f"{', '.join(system.param_names)}")
            table[k] = (v, "set by user")
        missing = [k for k in system.param_names if k not in table]
        if missing:
            raise ParameterError(f"parameter {missing[0]!r} of scene {self.name!r} has no value")
        chosen = {k: table[k] for k in system.param_names}
        values = system.validate({k: v for k, (v, _) in chosen.items()})
        if inputs:     # dc_rest, dc_stiffness: d_dc and dc_scale placed on the law (maps/well.py)
            chosen = apply_inputs(self.options, {k: (values[k], chosen[k][1]) for k in chosen}, inputs)
            values = system.validate({k: v for k, (v, _) in chosen.items()})
        return {k: (values[k], chosen[k][1]) for k in system.param_names}

    def initial_state(self, **components) -> dict:
        """Default initial state with named components replaced."""
        x0 = {n: 0.0 for n in self.system.state_names}
        x0.update(self.x0)
        for k, v in components.items():
            if k not in x0:
                raise ParameterError(f"unknown state {k!r} for scene {self.name!r}; its states are: "
                                     f"{', '.join(x0)}")
            try:
                x0[k] = float(v)
            except (TypeError, ValueError):
                raise ParameterError(f"initial state {k!r} must be a number, got {v!r}") from None
        return x0


_OSC = "the forced impact oscillator of maps.examples (a stable and an unstable 1:1 orbit coexist here)"
_ABOVE = {"x": 1e-3}
#: switched on: the bar at rest on the stop (x = 0), the circuit at rest (i = z = 0), spread by 0.1 mm in x and
#: 1 mm/s in v (a declared spread, not a measured one)
_SWITCH_ON_1DOF = {"x": (0.0, 1e-4), "v": (-1e-3, 1e-3), "i": (0.0, 0.0), "z": (0.0, 0.0)}
SCENES = {s.name: s for s in [
    Scene("dc-only", "bar under DC force and weight on the stop, 2 states (thesis Fig 4.7)",
          ModelOptions(dof=1, dc=True, ac=False, stop=True, relay="none", dc_law="fit"), x0={"x": 0.0}),
    Scene("ac-only", "AC solenoid always on and weight, no DC solenoid, no stop (Fig 4.25)",
          ModelOptions(dof=1, dc=False, ac=True, stop=False, relay="none"), x0={"x": 0.0}),
    Scene("ac-stop", "AC solenoid always on, weight and the stop (Fig 4.26)",
          ModelOptions(dof=1, dc=False, ac=True, stop=True, relay="none"), x0=_ABOVE),
    Scene("thesis-1dof", "vertical bar, DC solenoid, relay-switched AC solenoid, stop (Fig 4.27)",
          ModelOptions(dof=1, dc_law="fit"), x0=_ABOVE, box={"x": (0.0, 0.03), "v": (-1.5, 1.5)},
          switch_on=_SWITCH_ON_1DOF),
    Scene("thesis-2dof", "horizontal bar and rig, viscous soil (section 4.7, listing C.4)",
          ModelOptions(dof=2, soil="viscous"), preset="matlab-listing", x0={"x1": 1e-3}),
    Scene("prototype", "2-DOF prototype, antiphase relay, dry-friction soil (Chapter 5)",
          ModelOptions(dof=2, relay="antiphase", soil="coulomb"), preset="dynamics-listing",
          overrides={"dc_scale": (1.44, "DC 24 V: (24/20)^2, assuming a linear magnetic circuit"),
                     "relay_hz": (6.0, "Tables 5.2-5.4 ran at 6 Hz")},
          x0={"x1": 1e-3}),
    Scene("impact-oscillator", "forced linear oscillator against a rigid stop, restitution r (maps.examples)",
          None, preset=None, builder=forced_oscillator_with_stop,
          overrides={"w0": (1.0, _OSC), "zeta": (0.05, _OSC), "F": (0.5, _OSC), "Omega": (2.5, _OSC),
                     "e": (0.2, _OSC), "r": (0.7, _OSC)},
          x0={"x": 0.5}, box={"x": (-1.0, 2.0), "v": (-2.0, 2.0)}),
]}
