"""`bifurc study sensitivity --quick`: runs, writes the tornado and Sobol tables, and resumes."""
import json
import math

import numpy as np

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
