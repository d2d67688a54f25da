"""maps: hybrid electro-vibro-impact dynamics on heyoka.

Public API: what is integrated (:class:`Problem`, built by :func:`problem`), scenes
(:func:`get_scene`, :func:`scene_names`, :func:`register_scene`), time histories
(:func:`simulate`), hybrid systems (:class:`HybridSystem`, :class:`Guard` with its
role, :class:`PeriodicSwitch`, :class:`State`, :class:`HybridState`), the engines that
integrate them (:class:`HybridRun`, :class:`ScalarEngine`, :class:`BatchEngine`, with
every transition rule in :mod:`maps.transitions`), the maps (:class:`StroboscopicMap`,
:class:`ImpactMap`), named parameters (:class:`Parameter`, :class:`ParameterError`), the 2-DOF
soil laws (``SOIL_LAWS``), progression measures (:func:`progression_measures`) and the reduced
coordinates of a shift-invariant system (:func:`translation_basis`, :func:`reduce_points`,
:func:`reduce_jacobian`).
"""
from ._version import __version__
from .examples import forced_oscillator_with_stop
from .engines import BatchEngine, HybridRun, OrbitJob, OrbitResult, ScalarEngine, engine_for
from .hybrid import (ROLES, Escaped, EventCap, EventRecord, Guard, HybridState, HybridSystem, IntegrationFailure,
                     PeriodicSwitch, State)
from .model import PARAMETERS, SOIL_LAWS, ModelOptions, build_system
from .parameters import Parameter, ParameterError
from .poincare import ImpactLinearization, ImpactMap, MapLinearization, MapOrbit, StroboscopicMap
from .presets import PRESETS
from .progression import progression_measures
from .problem import Problem, problem
from .registry import get_scene, register_scene, scene_names
from .scenes import SCENES, ParameterValues, Scene
from .simulate import resolve, run_scene, simulate
from .translation import reduce_jacobian, reduce_points, translation_basis

__all__ = ["__version__", "Escaped", "EventRecord", "Guard", "HybridRun", "HybridSystem", "IntegrationFailure",
           "PeriodicSwitch", "State", "PARAMETERS", "ModelOptions", "build_system", "Parameter",
           "ParameterError", "PRESETS", "SCENES", "Scene", "get_scene", "scene_names", "resolve",
           "run_scene", "simulate", "forced_oscillator_with_stop", "StroboscopicMap", "ImpactMap",
           "MapOrbit", "HybridState", "EventCap", "ROLES", "ScalarEngine", "BatchEngine", "OrbitJob",
           "OrbitResult", "engine_for", "MapLinearization", "ImpactLinearization", "SOIL_LAWS",
           "progression_measures", "translation_basis", "reduce_points", "reduce_jacobian", "Problem", "problem",
           "register_scene", "ParameterValues"]
