"""One judge (issue 45 section 2): the same stored records judged through the diagram's anytime judge
(:func:`bifurc.labels.anytime.judge`) and the census' identification (:func:`bifurc.attractors.identify.identify`)
get the same labels, and those labels agree with independent truths: the logistic map at r = 4 (exponent ln 2 in
closed form: chaotic), a damped linear oscillator below its stop (its steady state in closed form: periodic, no
impact), an attracting invariant circle turned by the golden mean (quasi-periodic), and thesis-1dof records
(`matlab-listing`, 90 V) at 9 Hz (chaotic) and 8.5 Hz (periodic).  Where the census' Newton finds a stable orbit
from a record the judge leaves undecided (thesis-1dof at 4 and 5 Hz from 1000-period records), the census' own step
decides, as it should: the label is the judge's, the polishing the census'."""
import math
from types import SimpleNamespace

import numpy as np
import pytest

import maps
from bifurc.attractors.identify import Grid, identify
from bifurc.labels.anytime import Value, judge
from bifurc.labels.classify import candidate_periods, classify_orbit
from bifurc.labels.codes import ClassCode
from bifurc.labels.judge import MIN_WINDOW
from maps.hybrid import HybridState
from test_attractors import _limit_cycle

ATOL = 1e-9


def _scale(points):
    return np.maximum(np.nanmax(np.abs(points), axis=0), ATOL)


def _diagram(orbit, stretch, grid, q: int, *, can_extend: bool, max_period: int = 100):
    """The diagram's label of a stored record: its anytime judge on the record (one tangent trajectory, the
    census' evidence), with budget left to extend it or none."""
    v = Value(0.0, {}, q, orbit, start=0)
    v.stretch = stretch
    judge(v, classify=lambda o: classify_orbit(o.points, o.impacts_per_step, max_period=max_period, atol=ATOL,
                                              periods=candidate_periods(q, max_period)),
          stretch=lambda o: stretch[-o.n:], budget=v.end + (10 * orbit.n if can_extend else 0), record=orbit.n,
          lyapunov=True, observable=lambda o: grid.gridded(o.points), max_period=max_period, trajectories=1)
    return v.cls["label"], v


def _census(smap, orbit, grid, *, can_extend: bool, max_period: int = 100):
    """The census' label of the same record: identify's attractor's class, or not-converged (None)."""
    a = identify(smap, orbit, 0, grid, max_period=max_period, atol=ATOL, tried={}, last=not can_extend)
    return ("not-converged" if a is None else ClassCode(a.code).label), a


def _both(smap, orbit, stretch, grid, q, can_extend):
    d, v = _diagram(orbit, stretch, grid, q, can_extend=can_extend)
    c, a = _census(smap, orbit, grid, can_extend=can_extend)
    return d, c, v, a


def _record(points, stretch):
    """A stored record of a map without events: points, no impacts, the tangent stretch per step."""
    from maps.poincare import MapOrbit
    pts = np.asarray(points, dtype=float)
    n = len(pts) - 1
    z = np.zeros(n)
    o = MapOrbit(times=np.arange(n + 1.0), points=pts, impacts_per_step=np.zeros(n, np.int64),
                 min_clearance_per_step=z, min_impact_speed_per_step=z, impact_time=np.zeros(0),
                 impact_velocity=np.zeros(0), impact_phase=np.zeros(0), impact_penetration=np.zeros(0),
                 impact_duration=np.zeros(0), min_flight_clearance_per_step=np.full(n, np.inf), final_state=pts[-1])
    o.tangent_stretch = lambda scale=None: stretch
    o.state = lambda j: HybridState(pts[j].copy(), None)
    return o


@pytest.mark.parametrize("n", [MIN_WINDOW // 2, 2000])
def test_the_logistic_map_at_r_4_is_chaotic_in_both_with_exponent_ln_2(n):
    """x -> 4 x (1 - x): Lyapunov exponent ln 2 per step (closed form, the conjugacy to the tent map), its stretch
    log |4 (1 - 2 x)|.  A record of 2000 steps is chaotic in both analyses, its exponent within its interval and
    0.1 of ln 2; one of 200 steps is shorter than the judge's minimum window: the diagram asks for a longer record
    while one can follow (the census calls it chaotic and tests the set's lifetime instead), and both call it
    chaotic when none will."""
    x = np.empty(n + 101)
    x[0] = 0.3
    for k in range(n + 100):
        x[k + 1] = 4.0 * x[k] * (1.0 - x[k])
    pts = x[100:, None]
    stretch = np.log(np.abs(4.0 * (1.0 - 2.0 * pts[:-1, 0])))
    o = _record(pts, stretch)
    smap = SimpleNamespace(forcing_period_steps=1, system=SimpleNamespace(mechanical_index=[0]))
    grid = Grid(np.zeros(1), np.full(1, 0.01))
    for can_extend in (True, False):
        d, c, v, a = _both(smap, o, stretch, grid, 1, can_extend)
        if n < MIN_WINDOW and can_extend:
            # the diagram extends a short window; the census calls the set chaotic and tests its lifetime itself
            # (bifurc.attractors.census._persists), the stricter test of a chaotic transient
            assert d == "not-converged" and v.action is not None and c == "chaotic"
            continue
        assert d == c == "chaotic"
        lam, lo, hi = v.lyap
        assert lo <= math.log(2.0) <= hi and abs(lam - math.log(2.0)) < 0.1
        assert a.lyapunov_interval[0] <= math.log(2.0) <= a.lyapunov_interval[1]


def test_a_damped_oscillator_below_its_stop_is_periodic_without_impact_in_both():
    """x'' + 2 zeta w0 x' + w0^2 x = F cos(Omega t) with the stop at e = -1 and |steady amplitude| =
    F / |w0^2 - Omega^2 + 2 i zeta w0 Omega| = 0.133: its strobe points converge to x = Re(F / (w0^2 - Omega^2 +
    2 i zeta w0 Omega)), v = Re(i Omega F / (...)) (closed form), period 1, no impact.  Both analyses call the
    record periodic-no-impact, period 1, and the census' polished node is the closed form to 1e-8."""
    osc = dict(w0=1.0, zeta=0.02, F=0.1, e=-1.0, r=0.8, Omega=0.5)
    smap = maps.StroboscopicMap(maps.problem("impact-oscillator", params=osc), tol=1e-13)
    o = smap.orbit({"x": 0.5, "v": 0.0}, 200, transient=1500, tangent=True)
    stretch = o.tangent_stretch(_scale(o.points))
    grid = Grid.over({"x": (-1.0, 2.0), "v": (-2.0, 2.0)}, smap.system, 100, o.points[0])
    h = osc["F"] / (osc["w0"] ** 2 - osc["Omega"] ** 2 + 2j * osc["zeta"] * osc["w0"] * osc["Omega"])
    truth = np.array([h.real, (1j * osc["Omega"] * h).real])
    for can_extend in (True, False):
        d, c, v, a = _both(smap, o, stretch, grid, smap.forcing_period_steps, can_extend)
        assert d == c == "periodic-no-impact"
        assert v.cls["period"] == a.period == 1 and a.impacts == 0
        assert np.allclose(a.points[0], truth, rtol=0, atol=1e-8)


def test_an_attracting_circle_turned_by_the_golden_mean_is_quasi_periodic_in_both():
    """The unit circle above, sampled at 2 Hz with 1 + (3 - sqrt 5) / 2 turns per sample: a record of 768 samples
    on it is quasi-periodic in both analyses, its exponent's interval holding 0 (the tangential exponent of a
    rotation); a record of 384 (under the judge's window floor, and too few samples for the torus test) is not yet,
    in both, whether or not a longer record can follow."""
    f = 2.0
    w0 = 2 * math.pi * f * (1 + (3 - math.sqrt(5)) / 2)
    smap = maps.StroboscopicMap(maps.problem(_limit_cycle(), params={"w0": w0, "f_sw": f}), tol=1e-13)
    grid = Grid.over({"x": (-1.5, 1.5), "v": (-1.5, 1.5)}, smap.system, 100, np.zeros(2))
    for n, want in ((768, "quasi-periodic"), (384, "not-converged")):
        o = smap.orbit({"x": 1.0, "v": 0.0}, n, transient=50, tangent=True)
        stretch = o.tangent_stretch(_scale(o.points))
        for can_extend in (True, False):
            d, c, v, a = _both(smap, o, stretch, grid, smap.forcing_period_steps, can_extend)
            assert d == c == want
        if want == "quasi-periodic":
            assert v.lyap[1] <= 0.0 <= v.lyap[2] and a.lyapunov_interval[0] <= 0.0 <= a.lyapunov_interval[1]


@pytest.mark.parametrize("hz, want", [(9.0, "chaotic"), (8.5, "periodic")])
def test_thesis_records_get_one_label_in_both(hz, want):
    """thesis-1dof (`matlab-listing`, 90 V): a 1000-period record after 300 at 9 Hz is chaotic in both analyses (the
    thesis' chaotic value; its exponent's interval above the threshold 2 ln(1000) / 1000); at 8.5 Hz periodic in
    both, with one period and impact count (the census' Newton-polished orbit is the record's recurrence), a period
    of q = 17 strobe periods (the relay's forcing repeats every 17 samples): beyond the census' former max_period 16,
    within the one default MAX_PERIOD."""
    from bifurc.labels.vocabulary import MAX_PERIOD
    pb = maps.problem("thesis-1dof", preset="matlab-listing", params={"V": 90.0, "relay_hz": hz})
    smap = maps.StroboscopicMap(pb, tol=1e-10)
    o = smap.orbit(pb.state_vector(), 1000, transient=300, flags=pb.flags0, tangent=True)
    stretch = o.tangent_stretch(_scale(o.points))
    box = {"x": (0.0, 0.03), "v": (-1.5, 1.5)}
    grid = Grid.over(box, pb.system, 100, pb.state_vector())
    d, c, v, a = _both(smap, o, stretch, grid, smap.forcing_period_steps, False)
    assert d == c == want
    if want == "chaotic":
        assert v.lyap[1] > 2 * math.log(1000) / 1000 and a.lyapunov_interval[0] > 0
    else:
        assert v.cls["period"] == a.period == smap.forcing_period_steps == 17 <= MAX_PERIOD
        assert v.cls["impacts_per_period"] == a.impacts


def test_diagram_map_and_attractors_show_one_budget_and_one_period_search(capsys):
    """`--budget` and `--max-period` have one default each in the three verbs' --help (issue 45 section 1), and the
    period search reaches the thesis map's forcing period at 8.5 Hz (q = 17 strobe periods, from the map itself),
    which the census' former 16 did not."""
    import re

    from bifurc.cli import main
    shown = {}
    for verb in ("diagram", "map", "attractors"):
        try:
            main([verb, "--help"])
        except SystemExit:
            pass
        text = " ".join(capsys.readouterr().out.split())
        shown[verb] = tuple(int(re.search(rf"--{name} [A-Z_]+ [^\[]*?\(default (\d+)\)", text).group(1))
                            for name in ("budget", "max-period"))
    assert len({b for b, _ in shown.values()}) == 1 and len({m for _, m in shown.values()}) == 1, shown
    pb = maps.problem("thesis-1dof", preset="matlab-listing", params={"V": 90.0, "relay_hz": 8.5})
    q = maps.StroboscopicMap(pb, tol=1e-10).forcing_period_steps
    assert q == 17 and shown["attractors"][1] >= q
