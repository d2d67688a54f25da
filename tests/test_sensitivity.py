"""The sensitivity study (issue 46 section 3): its distance to the regime against closed forms, its placement of
the well against the cubic law's own formula, one sample against the dc-well study's map, and (slow) the quick
form's run, tables and resume."""
import json
import math

import numpy as np
import pytest

from studies.sensitivity.measures import FEW_MM, regime_gap

T = 0.25          # [s] a 4 Hz relay period


def test_gap_is_zero_exactly_in_the_regime_and_each_part_has_its_closed_form():
    n, t0, phase = 10, 3.0, 0.3
    one = t0 + T * (np.arange(n) + phase)                       # one impact per period, one phase
    g = regime_gap(one, T, t0, n, stroke_mm=4.0)
    assert g["gap"] == pytest.approx(0.0, abs=1e-12) and g["off_count"] == 0.0
    # impacts before the window do not count; a stroke of 2 FEW_MM adds (2F - F) / 2F = 1/2 to its part
    g = regime_gap(np.concatenate([[0.1, 0.2], one]), T, t0, n, stroke_mm=2 * FEW_MM)
    assert g["stroke_excess"] == pytest.approx(0.5) and g["gap"] == pytest.approx(0.5 / 3)
    # two impacts per period at phases 0.1 and 0.6 (opposite): every period off, circular variance 1 - |cos(pi/2)|
    two = np.sort(np.concatenate([t0 + T * (np.arange(n) + 0.1), t0 + T * (np.arange(n) + 0.6)]))
    g = regime_gap(two, T, t0, n, stroke_mm=3.0)
    assert g["off_count"] == 1.0 and g["phase_spread"] == pytest.approx(1.0, abs=1e-12)
    # period 2 with one impact every other period: half the periods off; phases 0.2 and 0.45 -> 1 - cos(pi/4)
    k = np.arange(0, 8, 2)
    alt = t0 + T * (k + np.where(k % 4 == 0, 0.2, 0.45))
    g = regime_gap(alt, T, t0, 8, stroke_mm=1.0)
    assert g["off_count"] == 0.5 and g["phase_spread"] == pytest.approx(1 - math.cos(math.pi / 4), rel=1e-12)
    # no impact: every part at its top but the stroke's; an escaped run (NaN stroke): all three at 1
    assert regime_gap([], T, t0, n, 50.0)["gap"] == pytest.approx((1 + 1 + 40 / 50) / 3)
    assert regime_gap([], T, t0, n, math.nan)["gap"] == 1.0


def test_a_sample_places_the_cubic_well_by_its_own_formula():
    """listing C.9's law, F = dc_scale (-a3 xa^3 + a2 xa^2 - a1 xa) + m g - m g: rest at xa = 0, i.e. x = d_dc, and
    stiffness dc_scale a1 there (closed form), for the sampled rest height and stiffness factor."""
    import maps
    from studies.sensitivity import PRESET, SCENE, configure
    s = dict(log10_rest_mm=math.log10(4.0), log2_stiffness=-0.5, law=0.2, ac_sign=1.7, c_air=0.1, V=50.0,
             relay_hz=3.0, start=0.5)
    cfg = configure(s, SCENE)
    assert (cfg["dc_law"], cfg["ac_sign"]) == ("listing", "listing")
    pb = maps.problem(SCENE, PRESET, cfg["params"], x0=cfg["x0"], dc_law=cfg["dc_law"], ac_sign=cfg["ac_sign"])
    own = maps.problem(SCENE, PRESET, dc_law="listing").values
    assert pb.values["d_dc"] == pytest.approx(4e-3, abs=1e-12)
    assert pb.values["a1"] * pb.values["dc_scale"] == pytest.approx(own["a1"] * own["dc_scale"] * 2 ** -0.5, rel=1e-9)
    assert pb.x0["x"] == pytest.approx(2e-3, abs=1e-12)


def test_a_sample_in_the_dc_well_map_regime_reads_gap_zero_and_its_stroke():
    """The dc-well study's full map (studies/dc_well/report.md, listing-25V) reads rest 3 mm, 2 Hz: P1, 1 impact,
    x -0.0..4.2 mm, on the batch engine over 300 + 100 periods; the study's scalar run from the same start over
    150 + 10 periods must read gap 0 and a 4.2 mm stroke."""
    from studies.sensitivity import one_dof
    s = dict(log10_rest_mm=math.log10(3.0), log2_stiffness=0.0, law=0.5, ac_sign=0.5, c_air=0.0, V=25.0,
             relay_hz=2.0, start=0.0)
    g = one_dof(s, dict(transient=150, record=10))
    assert g["gap"] < 1e-9 and g["in_regime"] == 1.0
    assert g["stroke_mm"] == pytest.approx(4.2, abs=0.05)


@pytest.mark.slow
def test_quick_sensitivity_writes_its_tables_and_resumes(tmp_path):
    from bifurc.commands.study import run_study
    from studies.sensitivity import INPUTS, LAWS, findings
    out = tmp_path / "sens"
    res = run_study("sensitivity", out, quick=True, progress=False)
    text = (out / "report.md").read_text()
    assert "## Total indices" in text and "## Per law" in text and "Made by" in text
    data = json.loads((out / "samples.json").read_text())
    assert data["inputs"] == list(INPUTS) and len(data["rows"]) == 4 * (len(INPUTS) + 2)
    gap = np.array(data["outputs"]["gap"])
    assert np.all((gap >= 0) & (gap <= 1))
    assert set(res["per_law"]) == set(LAWS)
    again = run_study("sensitivity", out, quick=True, progress=False, overwrite=True)
    assert "(0 run now)" in (out / "report.md").read_text()
    assert np.array_equal(again["outputs_per_sample"]["gap"], res["outputs_per_sample"]["gap"])
    stated = {f.name: f for f in findings(res, True)}
    assert stated["mean gap over samples"].value == pytest.approx(float(np.mean(gap)), abs=1e-4)


def test_the_leading_inputs_are_those_the_samples_cannot_order_below_the_first():
    """An input leads alone only where its interval's lower bound lies above every other input's upper bound."""
    from studies.sensitivity import leaders

    def result(values):
        idx = {k: {"value": v, "conf": c} for k, (v, c) in values.items()}
        return {"sobol": {"gap": {"converged": False, "indices": idx}},
                "delta": {"gap": {"converged": True, "indices": idx}}}
    alone = result({"a": (0.279, 0.014), "b": (0.187, 0.008), "c": (0.183, 0.007)})
    assert leaders(alone, "gap") == ["a"]
    tied = result({"a": (0.116, 0.011), "b": (0.110, 0.011), "c": (0.109, 0.012), "d": (0.097, 0.007)})
    assert leaders(tied, "gap") == ["a", "b", "c"]          # d: 0.104 < 0.105, the leader's lower bound
