"""What is integrated, as one object: :class:`Problem`, and its one resolver :func:`problem`.

A problem holds the scene (its system and structural options: DC-force law, soil, circuit, AC
sign, ...), the parameter values with their provenance, the start state and mode, and the
system's declared clock (strobe period and forcing period q).  Every map, sweep, orbit solver,
continuation, regime map and study takes one; their keyword forms build one with
:func:`problem`, so a preset means the same model on every path.

>>> import maps
>>> p = maps.problem("thesis-1dof", preset="matlab-listing", params={"V": 90, "relay_hz": 9})
>>> p.options.dc_law, p.strobe_period(), p.forcing_q()
('listing', 0.111..., 18)
>>> smap = maps.StroboscopicMap(p)
>>> p2 = p.with_values(relay_hz=8.5)
"""
from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field, replace

import numpy as np

from .parameters import ParameterError
from .presets import preset_attrs
from .registry import get_scene
from .scenes import ParameterValues, Scene

@dataclass(frozen=True, eq=False)
class Problem:
    """What is integrated: ``scene`` (system and options), ``values`` {name: value} with their
    ``provenance`` {name: source}, the start ``x0`` {state: value} [SI] and mode ``flags0``
    (None: the system's rule decides), and the ``preset`` the values came from (or None).

    Picklable (its scene pickles by name, address or builder), so it travels to worker processes.
    """

    scene: Scene
    values: Mapping[str, float]
    provenance: Mapping[str, str] = field(default_factory=dict)
    x0: Mapping[str, float] = field(default_factory=dict)
    flags0: Mapping[str, float] | None = None
    preset: str | None = None

    # ----- what it is ---------------------------------------------------------
    @property
    def system(self):
        """The :class:`~maps.hybrid.HybridSystem` (built once per scene and options)."""
        return self.scene.system

    @property
    def options(self):
        """The structural options (``ModelOptions``), or None for a scene without any."""
        return self.scene.options

    @property
    def name(self) -> str:
        return self.scene.name

    @property
    def key(self) -> tuple:
        """What identifies the compiled model (scene and options): for caches."""
        return self.scene.key

    @property
    def table(self) -> dict:
        """{name: (value, provenance)}."""
        return {k: (v, self.provenance.get(k, "set by user")) for k, v in self.values.items()}

    def state_vector(self) -> np.ndarray:
        """The start state as an array in the system's state order."""
        return self.system.state_vector(dict(self.x0))

    # ----- its clock --------------------------------------------------------------
    def strobe_period(self, values: Mapping | None = None) -> float:
        """The declared stroboscopic period T [s] (:meth:`~maps.hybrid.HybridSystem.strobe_period_of`)."""
        T = self.system.strobe_period_of(self.values if values is None else values)
        if T is None:
            raise ParameterError(f"scene {self.name!r} declares no clock (no periodic switch, forcing or "
                                 f"strobe_period): give the stroboscopic period")
        return T

    def forcing_q(self, values: Mapping | None = None) -> int:
        """The forcing repeats every q strobe periods (0: incommensurate)."""
        v = self.values if values is None else values
        return self.system.forcing_q(v, self.strobe_period(v))

    def well(self) -> dict:
        """The DC well at these values (:mod:`maps.well`): ``dc_rest`` [m] (the rest height above the stop, AC off),
        ``dc_stiffness`` [N m-1], ``dc_depth`` [J], ``dc_range`` [m] (the undamped swing's top from the stop),
        ``dc_stop_force`` [N]; empty for a scene without a DC solenoid."""
        from .well import well
        return well(self.options, self.values)

    def parameter(self, name: str):
        """The parameter ``name`` an analysis varies (:class:`~maps.parameters.Parameter`); a one-line error for an
        unknown name, and for a DC-well input (``dc_rest``, ``dc_stiffness``: set once, they place ``d_dc`` and
        ``dc_scale`` on the law), naming the parameter to vary instead and how it moves the input here."""
        from .well import WELL_INPUTS, well
        if name in WELL_INPUTS and self.options is not None and self.options.dc:
            w, law = well(self.options, self.values), self.options.dc_law
            if name == "dc_rest":
                how = (f"vary d_dc: at these values the rest height is d_dc + {(w['dc_rest'] - self.values['d_dc']) * 1e3:.6g}"
                       f" mm (dc_law {law}, dc_scale {self.values['dc_scale']:g})")
            else:
                how = f"vary dc_scale: the stiffness is {w['dc_stiffness']:.6g} N m-1 at dc_scale {self.values['dc_scale']:g} (dc_law {law})"
            raise ParameterError(f"parameter {name!r} is a DC-well input, set once (--set {name}=..., or params="
                                 f"{{{name!r}: ...}}), not varied by an analysis; {how}")
        return self.system.parameter(name)

    # ----- variants ---------------------------------------------------------------
    def with_values(self, **values) -> "Problem":
        """The same problem with parameter values changed (validated; provenance "set by user")."""
        from .well import WELL_INPUTS, apply_inputs, check_inputs
        inputs = {k: values.pop(k) for k in list(values) if k in WELL_INPUTS}
        check_inputs(inputs, values, self.name)
        new = self.system.validate(dict(self.values, **values))
        prov = dict(self.provenance, **{k: "set by user" for k in values})
        if inputs:     # dc_rest, dc_stiffness: d_dc and dc_scale placed on the law (maps/well.py)
            table = apply_inputs(self.options, {k: (v, prov.get(k, "set by user")) for k, v in new.items()}, inputs)
            new = self.system.validate({k: v for k, (v, _) in table.items()})
            prov = {k: src for k, (_, src) in table.items()}
        return replace(self, values=new, provenance=prov)

    def with_start(self, x0: Mapping | None = None, flags0: Mapping | None = None) -> "Problem":
        """The same problem from another start (``x0`` components replace the scene's defaults)."""
        return replace(self, x0=self.scene.initial_state(**dict(x0 or {})),
                       flags0=dict(flags0) if flags0 is not None else None)

    def parameter_values(self) -> ParameterValues:
        """The values as :class:`~maps.scenes.ParameterValues` (they carry this problem's model)."""
        return ParameterValues(self.values, self.scene, self.preset, self.provenance)

    # ----- what datasets record ---------------------------------------------------------
    def attrs(self, skip=()) -> dict:
        """Dataset attributes: the scene, its model options with their provenance (DC-force law,
        soil, circuit, AC sign, relay), the preset, and ``param_<name>`` with ``_units`` and
        ``_source`` for every parameter except ``skip``."""
        out = {"scene": self.name, **model_attrs(self.options), **preset_attrs(self.table)}
        out.update(well_attrs(self.options, self.values, skip))
        for k, v in self.values.items():
            if k not in skip:
                out[f"param_{k}"] = v
                out[f"param_{k}_units"] = self.system.parameter(k).unit
                out[f"param_{k}_source"] = self.provenance.get(k, "set by user")
        return out

    def __repr__(self):
        opts = f", options={self.options}" if self.options is not None else ""
        return f"Problem({self.name!r}, preset={self.preset!r}{opts}, values={dict(self.values)})"


def well_attrs(options, values, skip=()) -> dict:
    """Dataset attributes of the DC well (:mod:`maps.well`): ``dc_rest``, ``dc_stiffness``,
    ``dc_depth``, ``dc_range``, ``dc_stop_force`` with ``_units``, and ``dc_well_definition``;
    none for a scene without a DC solenoid, or when ``skip`` holds a parameter the well depends on
    (a sweep's parameter: the well changes along it)."""
    from .well import WELL_DEFINITIONS, WELL_OUTPUTS, well
    if options is None or not options.dc or set(skip) & set(values) - {"relay_hz", "V", "R", "C", "f_mains",
                                                                          "L0", "A", "B", "d_ac", "k", "c", "e",
                                                                          "c_air", "e_rear", "tau_dc"}:
        return {}
    out = {}
    for k, v in well(options, values).items():
        out[k], out[f"{k}_units"] = v, WELL_OUTPUTS[k][0]
    out["dc_well_definition"] = WELL_DEFINITIONS
    return out


def model_attrs(options) -> dict:
    """Dataset attributes of a scene's structural options: circuit, AC sign, relay, the DC-force
    law and the soil law with their provenance ("none" where a scene has no such part)."""
    from .model import COMPACTION, DC_LAWS, SOIL_LAWS
    if options is None:
        return {"circuit": "none", "ac_sign": "none", "relay": "none", "dc_law": "none",
                "dc_law_source": "no DC solenoid in this scene", "soil": "none",
                "soil_source": "no rig and no soil in this scene", "soil_compaction": "none"}
    o = options
    out = {"circuit": o.circuit if o.ac else "none", "ac_sign": o.ac_sign if o.ac else "none", "relay": o.relay}
    out.update({"dc_law": o.dc_law, "dc_law_source": DC_LAWS[o.dc_law]} if o.dc else
               {"dc_law": "none", "dc_law_source": "no DC solenoid in this scene"})
    out.update({"soil": o.soil, "soil_source": SOIL_LAWS[o.soil],
                "soil_compaction": COMPACTION if o.compaction else "none"} if o.dof == 2 else
               {"soil": "none", "soil_source": "no rig and no soil in this scene", "soil_compaction": "none"})
    return out


#: the keywords of :func:`problem` that an entry point takes beside a scene (``bifurc``'s analyses through
#: ``**options``, :func:`maps.simulate.simulate` with ``energy`` too); :func:`problem` itself takes any field of
#: ``ModelOptions``
KEYWORDS = ("preset", "params", "x0", "flags0", "circuit", "ac_sign", "dc_law", "soil", "compaction")


def problem(scene, preset: str | None = None, params: Mapping | None = None, x0: Mapping | None = None,
            flags0: Mapping | None = None, **options) -> Problem:
    """The one resolver: a :class:`Problem` from a scene (name, ``package.module:NAME``,
    :class:`~maps.scenes.Scene`, :class:`~maps.hybrid.HybridSystem` or a Problem), a ``preset``,
    parameter ``params`` {name: value}, a start ``x0`` {state: value} and mode ``flags0``, and
    structural ``options`` (``circuit``, ``ac_sign``, ``energy``, ``dc_law``, ``soil``,
    ``compaction``, or any other field of ``ModelOptions``; None: not set).

    The DC-force law follows the preset unless ``dc_law`` is given.  ``params`` that a scene
    returned (:meth:`Scene.parameters`) carry their model: with no scene options and no preset
    given here, the problem runs that model (its preset's DC law included).  A Problem passes
    through with ``params``, ``x0`` and ``flags0`` applied (options and presets are refused: build
    a new one).
    """
    opts = {k: v for k, v in options.items() if v is not None}
    if params is not None and not isinstance(params, Mapping):
        raise ParameterError(f"params must map parameter names to values, e.g. {{'V': 90}}; got {params!r}")
    if isinstance(scene, Problem):
        if opts or preset is not None:
            raise ParameterError("a Problem's options and preset are fixed: call maps.problem(scene, ...) anew")
        p = scene.with_values(**dict(params or {})) if params else scene
        return p.with_start(x0, flags0) if (x0 is not None or flags0 is not None) else p
    sc = get_scene(scene)
    carried = params if isinstance(params, ParameterValues) else None
    if carried is not None and carried.scene is not None and carried.scene.name == sc.name and not opts \
            and preset is None:
        sc, preset = carried.scene, carried.preset      # the model these values belong to
    if opts:
        if sc.options is None:
            raise ParameterError(f"options ({', '.join(opts)}) apply to the electro-vibro-impact scenes; scene "
                                 f"{sc.name!r} has none")
        if "soil" in opts and sc.options.dof != 2:
            from .model import SOIL_LAWS
            raise ParameterError(f"option 'soil' = {opts['soil']!r} needs a 2-DOF scene (bar and rig); scene "
                                 f"{sc.name!r} has no soil (soil laws: {', '.join(SOIL_LAWS)})")
        sc = sc.with_options(**opts)
    sc = sc.for_preset(preset).with_elements(params or {})   # c_air, e_rear, tau_dc switch their element on
    table = sc.parameters_with_provenance(preset, **dict(params or {}))
    if carried is not None:   # keep the provenance the values came with where they are unchanged
        table = {k: (v, carried.provenance.get(k, src) if k in carried and carried[k] == v else src)
                 for k, (v, src) in table.items()}
    if x0 is not None and not isinstance(x0, Mapping):
        raise ParameterError(f"x0 must map state names to values, e.g. {{'x': 0.001}}; "
                             f"{sc.name!r} has the states {', '.join(sc.system.state_names)}")
    return Problem(sc, {k: v for k, (v, _) in table.items()}, {k: s for k, (_, s) in table.items()},
                   sc.initial_state(**dict(x0 or {})), dict(flags0) if flags0 is not None else None, preset)
