"""The model's measures and the engine's parts, for studies and benchmarks built on :mod:`maps`.

A study (a ``bifurc.studies`` entry point) or a benchmark that measures the engine against a bare loop of its own
uses these names; each is imported on first use. :mod:`bifurc.studykit` has the study's writers and findings.

- the model's measures: :func:`impact_table` (a run's contacts: onset time, velocity, penetration, duration),
  :func:`progression_measures` (the rig's advance per second and per impact), :func:`held_mode` and
  :func:`held_time` (how long a 2-DOF run held a flag, e.g. stuck in the soil), :func:`load_table` (a table of
  the thesis, from ``data/``);
- the engine's parts: :func:`event_surfaces` (a system's guards grouped by surface), :class:`GuardChoice` (which
  guard of a surface acts), :func:`start_flags` (the flags a state starts in), :func:`settle_may_act` (whether the
  consistency rule may change them), :func:`forcing_period_steps` (relay periods after which the forcing repeats),
  :func:`tangent_equations` (the variational equations heyoka integrates beside the state),
  :func:`start_direction` and :data:`TANGENT_SIZE` (the tangent copies' first directions and their size);
- provenance: :func:`git_commit` (the checkout's commit, with ``+dirty`` when it has changes).
"""
from ._lazy import lazy_exports

#: public name -> the module of ``maps`` that defines it
_LAZY = {
    "impact_table": "impacts", "progression_measures": "progression", "held_mode": "progression",
    "held_time": "progression", "load_table": "thesis_data", "event_surfaces": "transitions",
    "GuardChoice": "transitions", "start_flags": "transitions", "settle_may_act": "hybrid",
    "forcing_period_steps": "poincare", "tangent_equations": "variational", "start_direction": "tangent",
    "TANGENT_SIZE": "tangent", "git_commit": "provenance",
}

__getattr__, __dir__ = lazy_exports("maps", _LAZY, globals())
