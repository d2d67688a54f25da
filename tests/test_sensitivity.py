"""`bifurc study sensitivity --quick`: runs, writes the tornado and Sobol tables, and resumes."""
import json
import math

import numpy as np
import pytest

from bifurc.commands.study import run_study


def test_quick_sensitivity_writes_sobol_table_and_resumes(tmp_path):
    out = tmp_path / "sens"
    res = run_study("sensitivity", out, quick=True, progress=False)
    text = (out / "report.md").read_text()
    assert "## Sobol indices" in text and "| output | input | S1 | S1 95 % | ST | ST 95 % |" in text
    assert "## One at a time (tornado)" in text and "at commit" in text
    data = json.loads((out / "samples.json").read_text())
    assert data["inputs"] == ["F_dc_sat", "c_air", "v_factor"] and len(data["rows"]) == 7 + 4 * 5
    share = np.array(data["outputs"]["share_p1"])
    assert np.all((share >= 0) & (share <= 1))
    rate = np.array(data["outputs"]["rate_mm_s"])
    assert np.isfinite(rate).all()
    # a rerun into the same folder resumes: every sample is read back, none run again
    again = run_study("sensitivity", out, quick=True, progress=False, overwrite=True)
    assert "(0 run now)" in (out / "report.md").read_text()
    assert again["base"]["rate_mm_s"] == res["base"]["rate_mm_s"] or math.isnan(res["base"]["rate_mm_s"])
    # the findings the quick report states: shares within one cell of the 3 x 3 grid, labels exact
    from studies.sensitivity import findings
    stated = {f.name: f for f in findings(res, True)}
    assert stated["share_p1 at mid-range"].tolerance == pytest.approx(1 / 9)
    assert stated["share_p1 mean over samples"].value == pytest.approx(float(np.mean(share)), abs=1e-6)
    assert stated["largest one-at-a-time swing of rate_mm_s"].value in ("F_dc_sat", "c_air", "v_factor", "none")


def test_stroke_equals_the_range_of_maps_simulate_time_history():
    """The stroke's cheap path (a bare scalar run sampled in the last relay period only) against the x range
    of maps.simulate's full time history at tol 1e-12 (another tolerance, another path) on a hammering cell."""
    import maps
    from studies.sensitivity import LAW, PRESET, SCENE, stroke
    p = {"F_dc_sat": 4.9459, "c_air": 0.0075478, "dc_scale": 1.15118, "R": 28.1337, "C": 2.8914e-4,
         "k": 858606.1, "c": 473.709, "relay_hz": 4.0, "V": 62.283}    # a P1-1 cell of the full design's row 65
    total = 100
    h = maps.simulate(SCENE, periods=total, preset=PRESET, dc_law=LAW, params=p, dt=1e-3 / 4.0)
    ref = float(np.ptp(h.x.values[h.time.values >= (total - 1) / 4.0]))
    assert h.sizes["impact"] > 10 and ref > 1e-3                     # it hammers: a stroke of millimetres
    assert stroke(p, total) == pytest.approx(ref, abs=1e-7)
