"""What a newcomer meets first (docs/newcomer-answers.md, part A): lookups by value that refuse values
off the grid, API defaults equal to the command line's, plot functions that refuse the wrong
dataset in one line and return their main Axes, figures that do not mislead (the time window's
impacts only, a "not computed" unlike any colour, branch lines broken where the section moves,
labels that do not overlap, every marker in the legend)."""
import inspect
import warnings

import matplotlib
import matplotlib.pyplot as plt
import numpy as np
import pytest

import bifurc
import maps
from bifurc.cli import build_parser, main
from bifurc.storage.grid import OffGridWarning, nearest_index
from test_periodic import BASE, closed_form_1_1

matplotlib.use("Agg")


@pytest.fixture(scope="module")
def diagram():
    """41 values of 2-10 Hz (step 0.2 Hz), as the README's notebook sweep, in short form."""
    return bifurc.sweep("thesis-1dof", "relay_hz", np.linspace(2, 10, 41), preset="matlab-listing",
                        params={"V": 90}, transient=5, record=4, error_sample=0, grazing=False, progress=False,
                        workers=1)


@pytest.fixture(scope="module")
def history():
    return maps.simulate("thesis-1dof", periods=30, preset="matlab-listing", params={"V": 90, "relay_hz": 9})


def test_a_value_outside_the_grid_is_refused_and_one_between_grid_values_warned(diagram, tmp_path, capsys):
    with pytest.raises(maps.ParameterError, match=r"relay_hz = 1000 Hz is outside the grid \(41 values from 2 to 10"):
        diagram.bifurc.class_at(1000.0)
    with pytest.raises(maps.ParameterError, match="outside the grid"):
        bifurc.sweep_point(diagram, 100.0)
    with pytest.warns(OffGridWarning, match=r"relay_hz = 8.5 Hz is not on the grid \(step 0.2 Hz\); using the "
                                            r"nearest grid value 8.4 Hz"):
        start, k = bifurc.sweep_point(diagram, 8.5)     # halfway between 8.4 and 8.6
    assert k == 5 + diagram.sizes["sample"] - 1       # transient + the last recorded sample
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert diagram.bifurc.class_at(6.0)["value"] == pytest.approx(6.0, abs=1e-12)   # on the grid: silent
        assert bifurc.class_at(diagram, 6.05)["value"] == pytest.approx(6.0, abs=1e-12)  # a quarter step: silent
        diagram.bifurc.report()          # the report's own values (the integers): silent
    with pytest.raises(maps.ParameterError, match=r"sample = 10: the sweep recorded 5 samples per value"):
        bifurc.sweep_point(diagram, 6.0, sample=10)
    path = tmp_path / "d.nc"
    diagram.to_netcdf(path)
    assert main(["report", str(path), "--at", "50"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err == ["bifurc: error: relay_hz = 50 Hz is outside the grid (41 values from 2 to 10 Hz); choose a "
                   "value in that range"]


def test_the_off_grid_rule_on_an_uneven_grid():
    grid = [0.0, 1.0, 2.0, 3.0, 10.0]                           # step (median spacing) 1, a hole over 3-10
    assert nearest_index(grid, 10.0 + 1e-9, "p") == 4          # round-off at an end is on the grid
    with pytest.warns(OffGridWarning, match=r"p = 6.5 is not on the grid \(step 1\); using the nearest grid value 3"):
        assert nearest_index(grid, 6.5, "p") == 3               # 3.5 steps from 3 and from 10
    with pytest.warns(OffGridWarning):
        nearest_index(grid, 1.5, "p")                           # a tie
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert nearest_index(grid, 1.4, "p") == 1 and nearest_index(grid, 9.6, "p") == 4


def test_the_api_orbit_uses_the_command_lines_transient_and_finds_the_closed_form_orbit():
    """F21: bifurc.periodic_orbit("impact-oscillator") failed (transient 0: singular Jacobian) where
    `bifurc orbit` worked (transient 300)."""
    sub = build_parser()._subparsers._group_actions[0].choices["orbit"]
    cli = {a.dest: a.default for a in sub._actions}
    api = bifurc.Shooting()                  # the method object names the API's defaults
    assert api.transient == cli["transient"] == 300 and api.tol == cli["tol"]
    o = bifurc.periodic_orbit("impact-oscillator")
    stable = [c for c in closed_form_1_1(**BASE) if np.max(np.abs(c[3])) < 1][0]
    assert int(o.period) == 1 and abs(float(o.impact_velocity[0]) - stable[1]) < 1e-8


def test_plot_functions_refuse_another_kind_in_one_line_and_return_their_main_axes(diagram, history):
    for plot, kind in ((bifurc.plot_diagram, "diagram"), (bifurc.plot_regime_map, "map"),
                       (bifurc.plot_branch, "branch"), (bifurc.plot_orbit, "orbit")):
        with pytest.raises(maps.ParameterError, match=f"{plot.__name__} needs an? {kind} dataset .* this is a "
                                                      "history dataset"):
            plot(history)
    with pytest.raises(maps.ParameterError, match="plot_time_history needs a history dataset"):
        bifurc.plot_time_history(diagram)
    with pytest.raises(maps.ParameterError, match="classification_report needs a diagram dataset"):
        bifurc.classification_report(history)
    for ds in (diagram, history):
        ax = ds.bifurc.plot()
        assert isinstance(ax, matplotlib.axes.Axes) and ax is ax.figure.axes[0] and len(ax.figure.axes) >= 2
        plt.close(ax.figure)


def test_a_time_slice_marks_only_its_own_impacts_on_its_own_time_axis(history):
    """F6: the notebook's last 10 periods were squeezed into a 0-3.3 s axis by impacts before the slice."""
    t = history.t.values
    tail = history.sel(t=slice(t[-1] - 10 / 9, None))
    inside = [ti for ti in history.impact_time.values if tail.t.values[0] <= ti <= tail.t.values[-1]]
    assert 0 < len(inside) < history.sizes["impact"]
    ax = tail.bifurc.plot()
    marks = [line for line in ax.lines if line.get_marker() == "v"]
    assert len(marks) == 1 and sorted(marks[0].get_xdata()) == sorted(inside)
    assert ax.get_xlim() == pytest.approx((tail.t.values[0], tail.t.values[-1]))
    assert f"impacts ({len(inside)})" in [text.get_text() for text in ax.get_legend().get_texts()]
    plt.close(ax.figure)


def test_not_computed_map_cells_are_hatched_unlike_the_exponents_white():
    """F9: a periodic cell (no exponent) and lambda = 0 were both white."""
    ds = bifurc.regime_map("thesis-1dof", "relay_hz", [5.0, 9.0], "V", [90.0, 100.0], preset="matlab-listing",
                           transient=5, record=4, error_sample=0, progress=False, workers=1)
    ds["lyapunov"][:] = [[np.nan, 0.0], [0.0, np.nan]]      # two cells not computed, two exactly zero
    ax = ds.bifurc.plot()
    fig = ax.figure
    fig.canvas.draw()
    image = np.asarray(fig.canvas.buffer_rgba())[..., :3].astype(int)
    panel = fig.axes[1]
    assert "not computed" in panel.get_title()
    spread = {}
    for i, x in enumerate(ds.relay_hz.values):
        for j, y in enumerate(ds.V.values):
            px, py = panel.transData.transform((x, y))
            block = image[image.shape[0] - int(py) - 8:image.shape[0] - int(py) + 8, int(px) - 8:int(px) + 8]
            spread[i, j] = np.ptp(block.reshape(-1, 3).sum(axis=1))
    assert spread[0, 0] > 100 and spread[1, 1] > 100          # hatched: light and dark pixels
    assert spread[0, 1] < 10 and spread[1, 0] < 10            # lambda = 0: one flat colour
    plt.close(fig)


def test_the_branch_plot_breaks_at_section_moves_spreads_its_labels_and_explains_its_markers():
    """F10: the impact oscillator's branch in e; the strobe section moves on the way (section_phase
    0 -> 0.49), which was drawn as a vertical branch segment; PD and LP labels overlapped."""
    ds = bifurc.continue_orbit("impact-oscillator", "e", (0.2, -0.2), branch_switch=True)
    ax = bifurc.plot_branch(ds)
    fig = ax.figure
    phase, par = ds.section_phase.values, ds.e.values
    moves = [k for k in range(ds.sizes["point"] - 1) if ds.branch_id.values[k] == ds.branch_id.values[k + 1]
             and phase[k] != phase[k + 1]]
    assert moves, "the branch should cross a section move"
    drawn = {tuple(np.round(line.get_xdata(), 12)) for line in ax.lines if len(line.get_xdata()) == 2}
    for k in moves:
        assert tuple(np.round(par[k:k + 2], 12)) not in drawn
    assert "section moves" in ax.get_ylabel()
    fig.canvas.draw()
    boxes = [t.get_window_extent() for t in ax.texts]
    assert len(boxes) == ds.sizes["special"] >= 2
    assert not any(a.overlaps(b) for i, a in enumerate(boxes) for b in boxes[i + 1:])
    # G13: no label on a marker (LP -0.10586 sat on the PD diamond) or across the frame, the legend beside
    frame = ax.get_window_extent()
    assert all(frame.x0 <= b.x0 and b.x1 <= frame.x1 and frame.y0 <= b.y0 and b.y1 <= frame.y1 for b in boxes)
    marks = [line for line in ax.lines if line.get_gid() == "special-marker"]
    assert len(marks) == ds.sizes["special"]
    for line in marks:
        px, py = ax.transData.transform((line.get_xdata()[0], line.get_ydata()[0]))
        half = 0.5 * line.get_markersize() * fig.dpi / 72
        assert not any(b.x0 < px + half and px - half < b.x1 and b.y0 < py + half and py - half < b.y1
                       for b in boxes), (line.get_marker(), px, py)
    assert not ax.get_legend().get_window_extent().overlaps(frame)
    legend = [t.get_text() for t in ax.get_legend().get_texts()]
    for kind in {int(k) for k in ds.special_kind.values}:
        from bifurc.plots.branch import SPECIAL_LABELS
        from bifurc.storage.schema import SPECIAL_KINDS
        assert any(text.startswith(SPECIAL_LABELS[SPECIAL_KINDS[kind]] + ":") for text in legend), legend
    plt.close(fig)


def test_a_branch_far_smaller_than_its_diagram_gets_a_magnified_inset_in_mm():
    """G13: the thesis branch over its diagram was flat at x = 0 (its orbits 0-0.6 mm, the diagram to 94 mm, both
    in m). Lengths are drawn in mm, as in the diagram's figure, and a branch under a tenth of the Axes' height is
    repeated in an inset whose window holds every branch point and is at most twice the branch's height (the
    impact oscillator's branch in e over a stand-in diagram 100 times taller); a branch alone gets no inset."""
    import xarray as xr
    ds = bifurc.continue_orbit("impact-oscillator", "e", (0.2, -0.2), branch_switch=True)
    x = ds.x.values[:, 0]
    e = np.linspace(-0.2, 0.2, 9)
    tall = 100 * (np.nanmax(x) - np.nanmin(x))
    diagram = xr.Dataset({"x": (("e", "sample"), np.linspace(0, tall, 9 * 4).reshape(9, 4))}, coords={"e": e},
                         attrs={"swept_parameter": "e"})
    alone = bifurc.plot_branch(ds)
    assert alone.get_ylabel().startswith("x at strobe node 0 [mm]") and not alone.child_axes
    drawn = np.concatenate([ln.get_ydata() for ln in alone.lines if ln.get_gid() is None and len(ln.get_ydata())])
    assert np.nanmin(drawn) == pytest.approx(1e3 * np.nanmin(x), rel=1e-12)
    assert np.nanmax(drawn) == pytest.approx(1e3 * np.nanmax(x), rel=1e-12)
    plt.close(alone.figure)
    ax = bifurc.plot_branch(ds, diagram=diagram)
    assert len(ax.child_axes) == 1
    inset = ax.child_axes[0]
    low, high = inset.get_ylim()
    span = 1e3 * (np.nanmax(x) - np.nanmin(x))
    assert low <= 1e3 * np.nanmin(x) and 1e3 * np.nanmax(x) <= high and high - low <= 2 * span
    ax.figure.canvas.draw()
    box = inset.get_window_extent()
    assert not any(box.overlaps(t.get_window_extent()) for t in ax.texts if t.get_gid() == "special-label")
    plt.close(ax.figure)


def test_report_wording_and_the_table_gives_the_reason_of_not_converged(diagram):
    """F24: "dc_scale = 1 1" (a value and the unit "1"); F1's remedy needs the reason where a user looks."""
    text = diagram.bifurc.report()
    assert "dc_scale = 1," in text and "dc_scale = 1 1" not in text
    table = diagram.bifurc.table()
    grey = table[table["class"] == "not-converged"]
    assert len(grey) and (grey.class_reason.str.len() > 0).all()
    from bifurc.storage.build import KINDS
    assert KINDS["branch"].startswith("`bifurc continue`")


def test_located_points_print_signed_multipliers():
    """F24: a period doubling's critical multiplier reads -1 and a fold's +1 (moduli alone cannot tell
    them apart); a complex pair is printed once, as modulus and argument."""
    import math
    from bifurc.commands.branch import multipliers_text
    assert multipliers_text([1.0, 0.381106], [math.pi, -math.pi]) == "-1, -0.381106"
    assert multipliers_text([1.0, 0.25, float("nan")], [0.0, 0.0, float("nan")]) == "+1, +0.25"
    assert multipliers_text([0.98, 0.98], [1.2345, -1.2345]) == "0.98 e^(+-1.234 i)"
