"""What a study or a benchmark is built from: findings, writers that never overwrite, parallel maps, cost estimates.

A study is a ``bifurc.studies`` entry point (``bifurc study NAME``): one installed by another distribution uses
these names as the built-in studies do. Each is imported on first use.

- findings and reports: :class:`Finding` (a stated finding that ``bifurc study NAME --check`` re-checks);
  :func:`write_text`, :func:`write_netcdf`, :func:`save_figure` (refuse an existing file unless ``overwrite``),
  :func:`refuse_existing`, :func:`check_figure_output` (refuse before computing);
- datasets: :func:`in_convention` (a diagram's periods in the mechanical or the full sense),
  :func:`regime_categories` (a regime map's cells as categories), :func:`attractor_count` (attractors a census
  found), :func:`no_contraction` (a chaotic set's area-rate interval excludes contraction), the codes of a
  branch's special points :data:`SPECIAL_KINDS` (the index is the stored ``special_kind``), those located by
  bisection :data:`LOCATED_KINDS`, and :data:`BIRTH_NOTE` (the note of a branch born at a period doubling);
- where and how long: :func:`map_values` (a job over values on workers or a Dask scheduler),
  :func:`available_cores`, :func:`estimate` (a sweep's seconds and memory before it runs);
- accuracy: :func:`work_precision` (error against run time of one trajectory, ``bifurc accuracy``).

The model's own measures and the engine's parts are in :mod:`maps.studykit`.
"""
from maps._lazy import lazy_exports

#: public name -> the module of ``bifurc`` that defines it
_LAZY = {
    "Finding": "findings", "write_text": "storage.files", "write_netcdf": "storage.files",
    "save_figure": "storage.files", "refuse_existing": "storage.files", "check_figure_output": "storage.files",
    "in_convention": "storage.load", "regime_categories": "plots.map", "attractor_count": "attractors.dataset",
    "no_contraction": "attractors.identify", "SPECIAL_KINDS": "storage.schema", "LOCATED_KINDS": "orbits.special_points",
    "BIRTH_NOTE": "orbits.special_points", "map_values": "run.executor", "available_cores": "run.executor",
    "estimate": "run.guard", "work_precision": "verification.accuracy",
}

__getattr__, __dir__ = lazy_exports("bifurc", _LAZY, globals())
