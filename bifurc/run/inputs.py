"""The three inputs of every analysis: what is integrated (a Problem), how (a method), where (a :class:`Run`).

An entry point takes ``problem, ..., method=None, *, run=None, **options``; :func:`analysis_inputs` resolves them:
``options`` (the keyword convenience) are shared out among the problem's keywords (:data:`maps.problem.KEYWORDS`),
the method's settings and the run's, and an unknown or misspelt name is one line naming the valid ones.
"""
from __future__ import annotations

from maps.parameters import ParameterError
from maps.problem import KEYWORDS, Problem, problem as make_problem

from .where import Run
from .settings import settle, split_options


def analysis_inputs(problem, method_cls, method, run, options: dict, runs: bool = True):
    """(Problem, method, Run) from an entry point's arguments: ``problem`` a :class:`maps.Problem` or a scene (name,
    Scene, HybridSystem); ``method`` an instance of ``method_cls`` or None (its defaults); ``run`` a :class:`Run` or
    None; ``options`` changes to any of them by name.  ``runs=False``: an analysis that runs here only (one orbit, a
    branch), whose options do not include the Run's (the Run returned is None)."""
    if method is not None and not isinstance(method, method_cls):
        raise ParameterError(f"method: expected a {method_cls.__name__} object, got {type(method).__name__} "
                             f"({method!r:.60})")
    if run is not None and not isinstance(run, Run):
        raise ParameterError(f"run: expected a bifurc.Run object, got {type(run).__name__} ({run!r:.60})")
    if runs:
        pk, mk, rk = split_options(options, KEYWORDS, method_cls, Run)
    else:
        (pk, mk), rk = split_options(options, KEYWORDS, method_cls), None
    m = settle(method_cls, method, mk)              # cheap checks first
    r = settle(Run, run, rk) if runs else None
    return resolve_problem(problem, pk), m, r


def resolve_problem(problem, keywords: dict) -> Problem:
    """:func:`maps.problem` of ``problem`` with the problem ``keywords`` (a Problem takes only params and x0)."""
    if isinstance(problem, Problem) and keywords:
        fixed = [k for k in keywords if k not in ("params", "x0", "flags0") and keywords[k] is not None]
        if fixed:
            raise ParameterError(f"{fixed[0]!r} cannot change a Problem (its options and preset are fixed): "
                                 f"build it with maps.problem(scene, {fixed[0]}=...)")
    return make_problem(problem, **keywords)
