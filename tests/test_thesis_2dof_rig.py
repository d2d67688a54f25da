"""`bifurc study thesis-2dof-rig`: the horizontal rig's progression under each soil law against the static
force's own rate (closed forms), its answer and its refusal to overwrite."""
import pytest

from studies import thesis_2dof_rig as study

TINY = dict(freqs=(10.0,), volts=(0.0, 90.0), transient=6, record=6)


def test_static_rates_are_the_closed_forms():
    p = {"F_static": 31.1, "soil_c": 135.0, "soil_friction": 1000.0, "P_max": 60.0}
    assert study.static_rate("viscous", p) == pytest.approx(1e3 * 31.1 / 135.0)
    assert study.static_rate("coulomb", p) == 0.0 and study.static_rate("drift", p) == 0.0
    assert study.static_rate("drift", dict(p, P_max=20.0)) != study.static_rate("drift", dict(p, P_max=20.0))  # NaN


def test_tiny_study_reports_each_soil_and_dc_law(tmp_path, monkeypatch):
    monkeypatch.setattr(study, "QUICK", TINY)
    res = study.run(tmp_path, quick=True, progress=False)
    text = (tmp_path / "report.md").read_text()
    assert "## Answer" in text and "Made by `bifurc study thesis-2dof-rig --quick -o DIR`" in text
    for law in study.LAWS:
        for dc in study.DC_LAWS:
            assert f"## {law} soil, DC law {dc}" in text
    # viscous soil: the rig moves at F_static / soil_c (230.4 mm/s) within 1 %, whatever the bar does
    rate = res["measured"][("viscous", "listing")]["rate"]
    assert rate == pytest.approx(1e3 * 31.1 / 135.0, rel=0.01)
    names = [f.name for f in study.findings(res, True)]
    assert "drift, catalogue: impacts advance the rig" in names
    with pytest.raises(FileExistsError):
        study.run(tmp_path, quick=True, progress=False)
