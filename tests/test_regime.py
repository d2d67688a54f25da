"""Regime maps (bifurc.regime_map, `bifurc map`): every cell is a diagram value.

Independent truths: the one-parameter sweep (bifurc.sweep) along either axis for the class of
each cell, an uninterrupted run for a resume after SIGKILL, the local processes for a Dask
LocalCluster, netCDF4 for the stored attributes, simulated colour blindness for the palette.
"""
import itertools
import os
import sys
from pathlib import Path

import numpy as np

import maps
import pytest
import xarray as xr

from bifurc import regime_map, sweep
from bifurc.cli import main
from bifurc.labels.codes import ClassCode, Status
from bifurc.sweeps.regime import CellJob
from bifurc.storage.schema import CELL_VARIABLES
from conftest import kill_when_parts

ROOT = Path(__file__).resolve().parents[1]
W, V = np.array([3.0, 5.0, 7.0]), np.array([60.0, 90.0, 200.0])
KW = dict(preset="matlab-listing", dc_law="measured", transient=40, record=24, progress=False, error_sample=0)
COMPARED = ("class_code", "period", "impacts_per_period", "n_impacts", "status")


@pytest.fixture(scope="module")
def local():
    return regime_map("thesis-1dof", "relay_hz", W, "V", V, workers=1, **KW)


def test_a_cell_is_classified_as_the_one_parameter_diagrams_value(local):
    """Along relay_hz at each V and along V at each relay_hz: the same class, period, impacts,
    exponent and clearance as bifurc.sweep at the same values (the measured law: periodic with and
    without impacts, escaped and chaotic cells on this grid)."""
    codes = set(local.class_code.values.ravel().tolist())
    assert {ClassCode.PERIODIC_NO_IMPACT, ClassCode.ESCAPED} <= codes and len(codes) >= 3
    skw = dict(KW, grazing=False)
    for j, v in enumerate(V):
        d = sweep("thesis-1dof", "relay_hz", W, params={"V": v}, workers=1, **skw).isel(branch=0)
        for name in COMPARED:
            assert np.array_equal(local[name].values[:, j], d[name].values), (name, v)
        for name in ("lyapunov", "min_clearance", "recurrence"):
            np.testing.assert_allclose(local[name].values[:, j], d[name].values, rtol=1e-9, atol=1e-12,
                                       equal_nan=True, err_msg=name)
    d = sweep("thesis-1dof", "V", V, params={"relay_hz": W[1]}, workers=1, **skw).isel(branch=0)
    for name in COMPARED:
        assert np.array_equal(local[name].values[1, :], d[name].values), name


def test_the_dataset_has_both_parameters_as_dimensions_and_the_schema_rows(local):
    assert local.class_code.dims == ("relay_hz", "V") and local.sizes == {"relay_hz": 3, "V": 3}
    np.testing.assert_array_equal(local.V.values, V)
    assert local.relay_hz.attrs["units"] == "Hz" and local.V.attrs["units"] == "V"
    for var in CELL_VARIABLES:
        assert local[var.name].attrs["units"] == var.units and local[var.name].attrs["long_name"] == var.long_name
    # escaped cells carry the escape (the label claims no more than was measured)
    esc = local.class_code.values == ClassCode.ESCAPED
    assert np.all(local.status.values[esc] == Status.ESCAPED) and np.all(np.isfinite(local.failure_time.values[esc]))
    assert local.attrs["scene"] == "thesis-1dof" and local.attrs["swept_parameter2"] == "V" and "param_V" not in local.attrs and "param_k" in local.attrs


def test_a_cell_job_carries_both_values_row_major():
    job = CellJob(maps.problem("thesis-1dof"), "relay_hz", param2="V", values=(3.0, 5.0), values2=(60.0, 90.0, 200.0))
    assert [job.cell(k) for k in range(6)] == [(a, b) for a in (3.0, 5.0) for b in (60.0, 90.0, 200.0)]
    assert job.at(4) == dict(job.params, relay_hz=5.0, V=90.0)


def test_a_map_cell_and_a_census_point_of_one_index_are_the_same_point():
    """The row-major grid (``param2`` fastest) is one convention: the regime map's flat cell k and the census'
    point k of :func:`bifurc.grid_points` over the same two lists (review N7)."""
    from bifurc import grid_points
    a, b = (3.0, 5.0, 7.5), (60.0, 90.0)
    job = CellJob(maps.problem("thesis-1dof"), "relay_hz", param2="V", values=a, values2=b)
    assert [{k: job.at(i)[k] for k in ("relay_hz", "V")} for i in range(6)] == grid_points("relay_hz", a, "V", b)


def test_netcdf_round_trip_keeps_values_and_cf_attributes(local, tmp_path):
    import netCDF4
    path = tmp_path / "m.nc"
    ds = regime_map("thesis-1dof", "relay_hz", W[:2], "V", V[:2], workers=1, path=path, **KW)
    back = xr.open_dataset(path).load()
    xr.testing.assert_identical(back.drop_vars("class_reason"), ds.drop_vars("class_reason"))
    assert list(back.class_reason.values.ravel()) == list(ds.class_reason.values.ravel())
    with netCDF4.Dataset(path) as nc:
        cc = nc["class_code"]
        assert list(cc.flag_values) == [int(c) for c in ClassCode]
        assert cc.flag_meanings.split() == [c.name.lower() for c in ClassCode]
        assert nc["V"].units == "V" and nc["lyapunov"].long_name.startswith("largest Lyapunov")
        assert "bifurc.regime_map(" in nc.history and nc.title.endswith("regime map over relay_hz and V")
    assert not Path(str(path) + ".parts").exists()


def test_a_map_file_is_its_own_kind(local, tmp_path, capsys):
    """ds.bifurc.plot() draws the map; `bifurc report` gives the map's report and refuses the diagram-only
    --at in one line."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    assert local.bifurc.kind == "map"
    ax = local.bifurc.plot()
    assert ax.get_title() == "regime"
    plt.close(ax.figure)
    path = tmp_path / "m.nc"
    local.to_netcdf(path)
    assert main(["report", str(path)]) == 0
    out = capsys.readouterr().out
    assert out.startswith("# Regime map report (map)") and f"{local.sizes[local.attrs['swept_parameter']]} values" in out
    assert main(["report", str(path), "--at", "5"]) == 2
    err = capsys.readouterr().err.strip()
    assert "holds a map dataset" in err and len(err.splitlines()) == 1


@pytest.fixture(scope="module")
def cluster():
    distributed = pytest.importorskip("dask.distributed")
    with distributed.LocalCluster(n_workers=2, processes=True, threads_per_worker=1, dashboard_address=None) as c:
        yield c


def test_dask_local_cluster_equals_local_processes(local, cluster):
    """Chunks of cells spread over two Dask workers: every stored number as in this process."""
    d = regime_map("thesis-1dof", "relay_hz", W, "V", V, scheduler=cluster.scheduler_address, chunk_size=4, **KW)
    assert d.attrs["workers"] == 0
    for name in local.data_vars:
        if name == "run_seconds":
            continue
        a, b = local[name].values, d[name].values
        if a.dtype.kind == "f":
            np.testing.assert_allclose(b, a, rtol=1e-12, atol=0, equal_nan=True, err_msg=name)
        else:
            assert np.array_equal(a, b), name


MAP = ["map", "--preset", "matlab-listing", "--dc-law", "measured", "--from", "3", "--to", "7", "--n", "3",
       "--from2", "60", "--to2", "200", "--n2", "3", "--transient", "150", "--record", "20", "--no-lyapunov",
       "--batch-size", "1", "--workers", "1", "--quiet"]


def test_resume_after_sigkill_of_bifurc_map_equals_an_uninterrupted_run(tmp_path):
    """SIGKILL a running `bifurc map` part-way; the rerun computes only the missing cells (one
    resume folder for the whole grid) and equals a run that was never interrupted."""
    path, parts = tmp_path / "k.nc", tmp_path / "k.nc.parts"
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    done = kill_when_parts([sys.executable, "-m", "bifurc", *MAP, "-o", str(path)], parts, timeout=90, env=env)
    if not 2 <= done < 9:
        pytest.skip(f"the kill came too late to test a resume ({done} cells done)")
    assert not path.exists() and sorted(p.name for p in parts.iterdir() if p.suffix == ".json") == ["manifest.json"]
    assert main([*MAP, "-o", str(path)]) == 0
    resumed = xr.open_dataset(path).load()
    assert resumed.attrs["resumed_values"] == done and not parts.exists()
    fresh = regime_map("thesis-1dof", "relay_hz", np.linspace(3, 7, 3), "V", np.linspace(60, 200, 3),
                       preset="matlab-listing", dc_law="measured", transient=150, record=20, lyapunov=False,
                       batch_size=1, workers=1, progress=False)
    for name in ("class_code", "period", "impacts_per_period", "n_impacts", "min_clearance", "recurrence", "n_steps"):
        np.testing.assert_allclose(resumed[name].values, fresh[name].values, rtol=0, atol=1e-12, equal_nan=True,
                                   err_msg=name)


@pytest.mark.parametrize("extra, words", [
    (["--n2", "0"], "--n2 0"),
    (["--param2", "relay_hz"], "param2 'relay_hz'"),
    (["--param2", "bogus"], "bogus"),
    (["--from2", "-5"], "V"),
    (["--transient", "-1"], "transient"),
])
def test_bad_arguments_fail_in_one_line_naming_the_parameter(tmp_path, capsys, extra, words):
    argv = ["map", "--from", "3", "--to", "5", "--n", "2", "--from2", "60", "--to2", "90", "--n2", "2",
            "--quiet", *extra, "-o", str(tmp_path / "e.nc")]
    assert main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("bifurc: error:") and len(err.splitlines()) == 1 and words in err, err
    assert not (tmp_path / "e.nc").exists()


def test_an_existing_output_is_refused_before_any_work(tmp_path, capsys):
    out = tmp_path / "m.nc"
    out.write_text("keep")
    assert main(["map", "--from", "3", "--to", "5", "--n", "2", "--from2", "60", "--to2", "90", "--n2", "2",
                 "-o", str(out)]) == 2
    assert "--force" in capsys.readouterr().err and out.read_text() == "keep"


def test_the_figure_names_every_regime_and_draws_given_curves(local, tmp_path):
    import matplotlib
    matplotlib.use("Agg")
    from bifurc.plots.map import plot_regime_map, regime_categories
    index, cats = regime_categories(local)
    texts = [t for t, _ in cats]
    code = local.class_code.values
    for i, (t, _) in enumerate(cats):   # every cell in exactly the category its class names
        cells = index == i
        assert cells.any()
        if t.startswith("period-"):
            n = int(t.split(",")[0].removeprefix("period-"))
            assert np.all(local.period.values[cells] == n)
            assert ("no impact" in t) == bool(np.all(code[cells] == ClassCode.PERIODIC_NO_IMPACT))
    assert "escaped" in texts and "period-1, no impact" in texts
    ax = plot_regime_map(local, tmp_path / "m.png", curves=[(W, np.full(3, 100.0), "a curve")])
    assert (tmp_path / "m.png").stat().st_size > 20_000
    assert [line.get_label() for line in ax.lines] == ["a curve"]


def test_periodic_categories_read_period_and_impacts(local):
    from bifurc.plots.map import regime_categories
    ds = local.copy(deep=True)
    ds["class_code"][:] = ClassCode.PERIODIC
    ds["period"][:] = [[1, 1, 2], [1, 2, 2], [1, 1, 1]]
    ds["impacts_per_period"][:] = [[1, 1, 2], [1, 2, 2], [1, 1, 1]]
    ds["class_code"][2, 2] = ClassCode.NOT_CONVERGED
    index, cats = regime_categories(ds)
    assert [t for t, _ in cats] == ["period-1, 1 impact", "period-2, 2 impacts", "not-converged"]
    assert np.bincount(index.ravel()).tolist() == [5, 3, 1]


def test_map_colours_stay_distinct_under_colour_blindness():
    """CIE76 difference >= 10 between every two colours a map can show (protan, deutan, tritan)."""
    from test_api import CVD, _lab

    from bifurc.plots.diagram import CLASS_COLOURS
    from bifurc.plots.map import MISSING, OTHER_PERIODIC, PERIODIC_COLOURS
    colours = list(PERIODIC_COLOURS) + [OTHER_PERIODIC[1], MISSING[1]] + [
        c for k, c in CLASS_COLOURS.items() if not ClassCode.of(k).periodic]
    for kind, matrix in CVD.items():
        for a, b in itertools.combinations(colours, 2):
            assert np.linalg.norm(_lab(a, matrix) - _lab(b, matrix)) >= 10, (kind, a, b)


def _check_study(out, size):
    import studies.regime_maps as study
    text = (out / "report.md").read_text()
    for case, (p1, _), (p2, _), law, _ in study.CASES:
        assert f"## {case}: {p1} x {p2}, dc_law {law}" in text and f"![{case}]({case}.png)" in text
        assert (out / f"{case}.png").stat().st_size > 20_000
        ds = xr.open_dataset(out / f"{case}.nc").load()
        assert ds.class_code.shape == (size["n"], size["n2"]) and ds.attrs["dc_law"] == law
        hammer = int(study.hammering(ds).sum())   # the report's answer is the cells' count
        assert (f"Periodic hammering (mechanical period-1, 1 impact per relay period) at {hammer} of" in text) == bool(hammer)
    return text


def test_regime_maps_study_writes_one_report_with_its_figures(tmp_path, monkeypatch):
    """The study on 2 x 3 cells per map (the full and --quick sizes run the same code)."""
    import studies.regime_maps as study
    small = dict(n=2, n2=3, transient=10, record=8)
    monkeypatch.setattr(study, "QUICK", small)
    assert main(["study", "regime-maps", "--quick", "-o", str(tmp_path)]) == 0
    _check_study(tmp_path, small)
    assert main(["study", "regime-maps", "--quick", "-o", str(tmp_path)]) == 2   # occupied: refused


@pytest.mark.slow
def test_regime_maps_quick_study_writes_its_report(tmp_path):
    """(Its duration, meant to be under two minutes, is benchmarks/wall_times.py --studies.)"""
    import studies.regime_maps as study
    assert main(["study", "regime-maps", "--quick", "-o", str(tmp_path)]) == 0
    _check_study(tmp_path, study.QUICK)


def test_periodic_hammering_keeps_its_own_colour_when_rare(local):
    """Ten periodic n:m on the map, "period-1, 1 impact" on one cell only: it still gets the first
    colour (the study's question), the rarest of the others share "periodic, other n:m"."""
    from bifurc.plots.map import OTHER_PERIODIC, PERIODIC_COLOURS, regime_categories
    ds = local.isel(relay_hz=[0, 1, 2, 0], V=[0, 1, 2, 0]).copy(deep=True)   # 16 cells
    ds["class_code"][:] = ClassCode.PERIODIC
    ds["period"][:] = 2
    ds["impacts_per_period"][:] = np.arange(16).reshape(4, 4) % 10 + 2   # ten n:m, 2:2 .. 2:11
    ds["period"][0, 0], ds["impacts_per_period"][0, 0] = 1, 1             # replaces one 2:2 cell
    index, cats = regime_categories(ds)
    assert cats[0] == ("period-1, 1 impact", PERIODIC_COLOURS[0]) and np.sum(index == 0) == 1
    assert OTHER_PERIODIC in cats and len(cats) == len(PERIODIC_COLOURS) + 1
    _, every = regime_categories(ds, colours=None)
    assert len(every) == 11 and all(c is None for _, c in every)


def test_the_map_summary_reads_label_colon_count(tmp_path, capsys):
    """F24: the summary's counts are 'label: count' separated by '; ' (a label such as 'period-2, 2
    impacts' holds a comma and a number of its own), and they add up to the cells."""
    import re
    argv = ["map", "--preset", "matlab-listing", "--from", "3", "--to", "5", "--n", "2", "--from2", "60", "--to2",
            "90", "--n2", "2", "--transient", "20", "--record", "10", "--no-lyapunov", "--workers", "1", "--quiet",
            "-o", str(tmp_path / "s.nc")]
    assert main(argv) == 0
    line = capsys.readouterr().out.splitlines()[0]
    counts = line.split("): ", 1)[1].split("; ")
    assert all(re.fullmatch(r"[a-z0-9 ,-]+: \d+", c) for c in counts), line
    assert sum(int(c.rsplit(": ", 1)[1]) for c in counts) == 4


def test_the_impacts_scale_gives_every_count_its_own_colour_and_the_titles_say_what_is_hatched(local):
    """G12: one 35-impact cell squeezed 2-9 impacts into one navy; the Lyapunov title said periodic cells are
    hatched while most periodic cells show an exponent."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.colors import to_rgb
    from bifurc.plots.map import OTHER_PERIODIC, PERIODIC_COLOURS, plot_regime_map
    from bifurc.plots.diagram import CLASS_COLOURS
    ds = local.copy(deep=True)
    ds["class_code"][:] = ClassCode.PERIODIC
    ds["period"][:] = 1
    ds["impacts_per_period"][:] = [[1, 2, 35], [1, 2, 3], [1, 1, 1]]
    ax = plot_regime_map(ds)
    fig = ax.figure
    fig.canvas.draw()
    panel = fig.axes[2]
    mesh = panel.collections[0]
    colours = {tuple(np.round(c, 6)) for c in mesh.get_facecolor()}
    assert len(colours) == 4                          # 1, 2, 3 and 35 impacts: four colours
    bar = fig.axes[-1]
    assert [t.get_text() for t in bar.get_yticklabels()] == ["1", "2", "3", "35"]
    assert fig.axes[1].get_title() == "Lyapunov exponent (hatched: exponent not computed)"
    plt.close(fig)
    greys = [c for c in list(PERIODIC_COLOURS) + [OTHER_PERIODIC[1]] if len(set(to_rgb(c))) == 1]
    assert not greys and CLASS_COLOURS["not-converged"] == "#666666"     # one grey on the map: not-converged
    def green(c):
        r, g, b = to_rgb(c)
        return g > r + 0.1 and g > b + 0.1
    assert green(CLASS_COLOURS["quasi-periodic"]) and not any(green(c) for c in PERIODIC_COLOURS)   # one green
