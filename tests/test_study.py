"""The first study, its comparison report, the diagram/report commands and the notebook."""
from pathlib import Path

import numpy as np
import pytest

from bifurc.cli import main

ROOT = Path(__file__).resolve().parents[1]


def test_diagram_and_report_commands(tmp_path, capsys):
    nc, png, md = tmp_path / "d.nc", tmp_path / "d.png", tmp_path / "r.md"
    assert main(["diagram", "--scene", "thesis-1dof", "--preset", "matlab-listing", "--set", "V=90",
                 "--from", "5", "--to", "9", "--n", "3", "--transient", "10", "--record", "8", "--quiet",
                 "-o", str(nc), "--plot", str(png)]) == 0
    from bifurc.storage import load as storage
    ds = storage.read(nc)
    np.testing.assert_allclose(ds.relay_hz.values, [5, 7, 9])
    assert ds.class_code.dims == ("branch", "relay_hz") and (ds.class_code.values >= 0).all()
    assert png.stat().st_size > 20_000
    assert main(["report", str(nc), "-o", str(md)]) == 0
    text = md.read_text()
    assert "| 7 | independent |" in text and "Class counts" in text and "error estimate" in text
    assert main(["report", str(tmp_path / "missing.nc")]) == 2
    assert main(["diagram", "--from", "2", "--to", "3", "--n", "2", "--param", "bogus", "-o", str(tmp_path / "e.nc")]) == 2
    assert "bogus" in capsys.readouterr().err


def test_quick_study_compares_every_frequency(tmp_path):
    from bifurc.commands.study import run_study
    results = run_study("thesis-1dof-relay", tmp_path, quick=True, progress=False, cases=["thesis-text"])
    ds = results["thesis-text"]
    np.testing.assert_allclose(ds.relay_hz.values, np.arange(2, 11))
    # the forcing's own period in relay periods: smallest q with 50 q / W an integer
    assert list(ds.forcing_period.values[0]) == [1, 3, 2, 1, 3, 7, 4, 9, 1]
    text = (tmp_path / "comparison.md").read_text()
    for w in range(2, 11):
        assert f"\n| {w} |" in text
    # at the thesis' 25 V the AC pull brings the bar to the stop at 2 Hz only, and there only after the
    # first hundreds of periods (a quasi-periodic orbit judged on a longer window): said, not hidden
    n = ds.n_impacts.values[0]
    assert n[0] > 0 and int(n[1:].max()) == 0 and "does not reach the stop" in text
    for f in ("thesis-text.nc", "thesis-text.png", "thesis-text.md"):
        assert (tmp_path / f).exists()
    before = (tmp_path / "comparison.md").read_text()
    with pytest.raises(FileExistsError, match="not empty"):  # refused before any work
        run_study("thesis-1dof-relay", tmp_path, quick=True, progress=False, cases=["thesis-text"])
    assert (tmp_path / "comparison.md").read_text() == before


def _replay():
    import studies.thesis_replay as replay
    return replay


def test_replay_row_measures_the_dc_well_not_the_relay():
    """The thesis' own run (listing law, listing AC sign, start on the stop with i = 0.1 A) at 5 Hz
    and 90 V: x's spectrum peaks at the DC well's own frequency, not at 5 Hz, and x spans the whole
    well (about 2 x 62.5 mm), far beyond the thesis' +-5 mm; the DC force at the stop is C.9 at
    xa = -0.0625 m less its m g offset, typed here."""
    replay = _replay()
    r = replay.measure(5.0, 90.0, "listing", long_periods=20, long_window=10)
    assert r["status"] == "ok" and r["dc_law"] == "listing" and r["ac_sign"] == "listing"
    assert abs(r["fft_peak_3s_hz"] - 8.33) < 0.34            # one bin of a 3 s record
    well = replay.well_frequency("listing", seconds=12.0)
    assert abs(well - 8.37) < 0.1 and abs(r["fft_peak_3s_hz"] - well) < 0.34
    assert r["x_max_mm"] > 120.0 and r["x_min_mm"] < 0.0
    xa = -0.0625
    assert abs(r["F_dc_stop_N"] - (1.473e5 * 0.0625**3 - 1.652e-14 * xa**2 + 15.38 * 0.0625)) < 1e-9
    text = "\n".join(replay.disagreements(r, well))
    assert "8.33 Hz, not at the relay's 5 Hz" in text and "+-5 mm sensor" in text


@pytest.mark.slow
def test_quick_replay_study_writes_its_report_and_figure(tmp_path):
    """`bifurc study thesis-replay --quick`: every row names its DC law; under `measured` with the
    physical AC sign the bar never leaves the stop."""
    assert main(["study", "thesis-replay", "--quick", "-o", str(tmp_path)]) == 0
    text = (tmp_path / "report.md").read_text()
    for law in ("listing", "fit", "measured"):
        for w in (5, 6):
            assert f"\n| {w} | {law} |" in text
    assert "a bar at rest on the stop never leaves it" in text
    assert (tmp_path / "replay_90V.png").stat().st_size > 20_000
    assert (tmp_path / "replay.csv").read_text().count("\n") == 2 + 6
