"""The label vocabulary, one floor below every analysis: codes, classification, exponents, evidence, the judge.

:mod:`.codes` (the class and status codes), :mod:`.classify` (a record's class from its samples), :mod:`.lyapunov`
(exponents and their intervals), :mod:`.evidence` (torus, decay and recurrence tests), :mod:`.anytime` (the judge:
a label decided on evidence within a budget).  The diagram, the regime map and the census read labels from here.

Public, to judge records of one's own (a study replaying the thesis' listing does): :func:`classify_orbit` (a
record's class, period and impacts from its stroboscopic samples), :func:`describe` (a class code as words),
:func:`lyapunov_threshold` (the exponent below which a record of n steps reads as regular),
:func:`torus_evidence` (the 0-1 test and rotation of a quasi-periodic record), :func:`lyapunov_along` (the
largest exponent along a recorded orbit of a map). Each is imported on first use, so worker processes load only
what they use.
"""
from maps._lazy import lazy_exports

#: public name -> the module of ``bifurc.labels`` that defines it
_LAZY = {"classify_orbit": "classify", "describe": "classify", "lyapunov_threshold": "classify",
         "torus_evidence": "evidence", "lyapunov_along": "lyapunov"}

__getattr__, __dir__ = lazy_exports(__name__, _LAZY, globals())
