"""maps: hybrid electro-vibro-impact dynamics on heyoka.

Public API: what is integrated (:class:`Problem`, built by :func:`problem`), scenes
(:func:`get_scene`, :func:`scene_names`, :func:`register_scene`), time histories
(:func:`simulate`), hybrid systems (:class:`HybridSystem`, :class:`Guard` with its
role, :class:`PeriodicSwitch`, :class:`State`, :class:`HybridState`), the engines that
integrate them (:class:`HybridRun`, :class:`ScalarEngine`, :class:`BatchEngine`, with
every transition rule in :mod:`maps.transitions`), the maps (:class:`StroboscopicMap`,
:class:`ImpactMap`), named parameters (:class:`Parameter`, :class:`ParameterError`), the 2-DOF
soil laws (``SOIL_LAWS``) and the reduced
coordinates of a shift-invariant system (:func:`translation_basis`, :func:`reduce_points`,
:func:`reduce_jacobian`); and the public module :mod:`maps.studykit` (the model's measures and the
engine's parts, for studies and benchmarks).
"""
import sys
import types

from ._lazy import lazy_exports
from ._version import __version__

#: public name -> the submodule that defines it; imported on first use (PEP 562), so that
#: ``import maps.parameters`` (the command line's start) does not load heyoka
_LAZY = {
    "forced_oscillator_with_stop": "examples",
    **dict.fromkeys(("BatchEngine", "HybridRun", "OrbitJob", "OrbitResult", "ScalarEngine", "engine_for"), "engines"),
    **dict.fromkeys(("ROLES", "Escaped", "EventCap", "EventRecord", "Guard", "HybridState", "HybridSystem",
                     "IntegrationFailure", "PeriodicSwitch", "State"), "hybrid"),
    **dict.fromkeys(("PARAMETERS", "ModelOptions", "build_system"), "model"),
    "SOIL_LAWS": "laws",
    **dict.fromkeys(("Parameter", "ParameterError"), "parameters"),
    **dict.fromkeys(("ImpactLinearization", "ImpactMap", "MapLinearization", "MapOrbit", "StroboscopicMap"),
                    "poincare"),
    "PRESETS": "presets",
    **dict.fromkeys(("Problem", "problem"), "problem"),
    **dict.fromkeys(("get_scene", "register_scene", "scene_names"), "registry"),
    **dict.fromkeys(("SCENES", "ParameterValues", "Scene"), "scenes"),
    **dict.fromkeys(("run_scene", "simulate"), "simulate"),
    **dict.fromkeys(("reduce_jacobian", "reduce_points", "translation_basis"), "translation"),
}

__all__ = ["__version__", "Escaped", "EventRecord", "Guard", "HybridRun", "HybridSystem", "IntegrationFailure",
           "PeriodicSwitch", "State", "PARAMETERS", "ModelOptions", "build_system", "Parameter",
           "ParameterError", "PRESETS", "SCENES", "Scene", "get_scene", "scene_names",
           "run_scene", "simulate", "forced_oscillator_with_stop", "StroboscopicMap", "ImpactMap",
           "MapOrbit", "HybridState", "EventCap", "ROLES", "ScalarEngine", "BatchEngine", "OrbitJob",
           "OrbitResult", "engine_for", "MapLinearization", "ImpactLinearization", "SOIL_LAWS",
           "translation_basis", "reduce_points", "reduce_jacobian", "Problem", "problem",
           "register_scene", "ParameterValues", "studykit"]


class _Package(types.ModuleType):
    """``maps.simulate`` and ``maps.problem`` are the functions, as with the former eager imports,
    even after their submodules of the same names are imported (which binds the submodule)."""

    def __setattr__(self, name, value):
        if not (isinstance(value, types.ModuleType) and _LAZY.get(name) == name):
            super().__setattr__(name, value)


sys.modules[__name__].__class__ = _Package


_lazy_getattr, __dir__ = lazy_exports(__name__, _LAZY, globals())


def __getattr__(name):
    if name == "studykit":      # the public module: its names in its ``_LAZY`` are public too
        import importlib
        return importlib.import_module(".studykit", __name__)
    return _lazy_getattr(name)
