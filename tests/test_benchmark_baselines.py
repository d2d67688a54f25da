"""The bare tangent-vector baseline of benchmarks/frequency_diagram.py integrates what the product does.

``BareBatchTangent`` (outside the package: event callbacks written inline, the saltation jump of a
compliant contact by hand, renormalisation every period) must give the exponents ``bifurc.sweep``
stores, or its timing compares different work.  Short runs: no time for round-off to grow.
"""
import importlib.util
import sys
from pathlib import Path

import numpy as np

import maps
from bifurc.sweeps.sweep import sweep

SCRIPT = Path(__file__).resolve().parents[1] / "benchmarks" / "frequency_diagram.py"


def _script():
    spec = importlib.util.spec_from_file_location("frequency_diagram", SCRIPT)
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module        # its dataclasses look their module up
    spec.loader.exec_module(module)
    return module


def test_bare_tangent_exponents_match_the_product():
    fd = _script()
    values = np.linspace(2.0, 10.0, 9)
    ds = sweep("thesis-1dof", "relay_hz", values, preset="matlab-listing", params={"V": 90.0}, transient=20,
               record=10, tol=1e-10, progress=False, workers=1, grazing=False, error_sample=0,
               budget=30)     # the fixed record the bare ensemble integrates: no anytime extension
    lyap = ds["lyapunov"].values.ravel()
    used = ds["record_used"].values.ravel()
    params = maps.get_scene("thesis-1dof").with_options(dc_law="listing").parameters(preset="matlab-listing", V=90.0)
    problem = fd.Problem(params, transient=20, record=10,
                         records=tuple((float(v), int(r)) for v, r in zip(values, used) if r != 10))
    assert problem.records                 # some records extended (3 q periods): those lengths are used
    baseline = fd.BareBatchTangent(problem)
    bare = np.array(baseline.run_many(list(values)), dtype=float)
    # it integrates the product's stick surface too, which never acts here (nor in the product:
    # no value sticks, so omitting the stick transition changes nothing)
    assert any(g.role == "stick" for g in baseline.record.system.guards)
    assert baseline.transient.rest_crossings == baseline.record.rest_crossings == 0
    both = np.isfinite(lyap)
    assert both.sum() >= 6                 # not periodic: the product stored an exponent
    # the product's norm (components scaled): the same numbers to round-off
    np.testing.assert_allclose(bare[both, 0], lyap[both], rtol=0, atol=1e-9)
    # the Euclidean norm's exponent differs by the boundary term only: a different number
    assert np.max(np.abs(bare[both, 1] - lyap[both])) > 1e-3
