"""Decisive labels (anytime classification) against independent truths: a rotation number known in
closed form, the mechanical period where the current's sign alternates, an exponent computed here in
extended precision by another method, a constructed intermittent record, and the same dataset on any
number of workers."""
import math
import os
import subprocess
import sys
import textwrap

import numpy as np
import pytest

import bifurc
import maps
from bifurc.labels.codes import ClassCode
from bifurc.labels.anytime import Value, judge
from bifurc.labels.classify import classify_orbit
from bifurc.labels.evidence import (exponent_estimate, extent_drift, locked_lag, rotation_number, torus_evidence,
                                    zero_one_test)
from maps import HybridSystem, Parameter, PeriodicSwitch, State

RHO = (3 - math.sqrt(5)) / 2          # the golden mean's complement: far from every fraction a/b, b <= 100


def _rotating_oscillator():
    """x'' = -w0^2 x sampled every 1/f_sw: a rigid rotation by w0 / (2 pi f_sw) turns per sample, a torus
    (an invariant circle of the map) with exponent 0.  The switch only sets the clock."""
    return HybridSystem("rotation", states=[State("x", "m", "position"), State("v", "m s-1", "velocity")],
                        parameters=[Parameter("w0", "rad s-1", "angular frequency", 0, 100, low_open=True),
                                    Parameter("f_sw", "Hz", "sampling switch", 0, 100, low_open=True)],
                        flags={"P": 1.0}, rhs=lambda s: [s.v, -s.w0 * s.w0 * s.x],
                        switches=[PeriodicSwitch("P", "f_sw")])


def test_a_rigid_rotation_is_quasi_periodic_with_its_rotation_number():
    f = 2.0
    w0 = 2 * math.pi * f * (1 + RHO)            # 1 + rho turns per sample: rotation number rho (mod 1)
    ds = bifurc.sweep(_rotating_oscillator(), "f_sw", [f], params={"w0": w0, "f_sw": f}, x0={"x": 1.0},
                      transient=10, record=100, budget=2000, tol=1e-13, grazing=False, error_sample=0,
                      progress=False).isel(branch=0, f_sw=0)
    assert ClassCode(int(ds.class_code)) == ClassCode.QUASI_PERIODIC, str(ds.class_reason.values)
    n = int(ds.record_used)
    assert n >= 400 and int(ds.lyapunov_trajectories) == 4
    assert abs(float(ds.rotation_number) - RHO) <= 1.0 / n          # the mean turn over n samples
    assert abs(float(ds.zero_one_k)) < 0.1
    assert float(ds.lyapunov_low) <= 0.0 <= float(ds.lyapunov_high)


def test_the_torus_tests_on_closed_forms():
    k = np.arange(2000)
    circle = np.c_[np.cos(2 * math.pi * RHO * k), 0.5 * np.sin(2 * math.pi * RHO * k)]
    rho, drift = rotation_number(circle)
    assert abs(rho - RHO) < 1e-3 and drift < 1e-3
    x, chaos = 0.3, []
    for _ in range(2000):                      # the logistic map at r = 4: chaotic (exponent ln 2)
        x = 4 * x * (1 - x)
        chaos.append(x)
    assert zero_one_test(np.array(chaos)) > 0.9 and abs(zero_one_test(circle[:, 0])) < 0.1


def _turning(rho: float, r: float = 1.0, n: int = 1536) -> np.ndarray:
    """n samples r^k (cos 2 pi rho k, sin 2 pi rho k): a circle turned by rho per sample (r = 1) or a spiral."""
    k = np.arange(n)
    return (r ** k)[:, None] * np.c_[np.cos(2 * math.pi * rho * k), np.sin(2 * math.pi * rho * k)]


def test_a_spiral_is_no_torus_though_it_turns_steadily():
    """Samples r^k (cos 2 pi rho k, sin 2 pi rho k) at the golden-mean rotation: with r = 1 an invariant circle (a
    torus), with r = 0.997 a spiral onto a fixed point whose rotation number and 0-1 test are a circle's; its extent
    shrinks by r^(N/2) from one half of N = 1536 samples to the other: 1 - 0.997^768 = 0.90."""
    spiral = lambda r: _turning(RHO, r)  # noqa: E731
    torus, why, _, rho = torus_evidence(spiral(1.0), 16)
    assert torus and why == "" and abs(rho - RHO) < 1e-3
    assert extent_drift(spiral(1.0)) < 1e-3
    assert extent_drift(spiral(0.997)) == pytest.approx(1 - 0.997 ** 768, rel=0.05)
    torus, why, _, rho = torus_evidence(spiral(0.997), 16)
    assert not torus and "extent" in why
    assert abs(rotation_number(spiral(0.997))[0] - RHO) < 1e-3 and abs(zero_one_test(spiral(0.997)[:, 0])) < 0.25
    # near 1/6 each half of 768 samples sweeps six arcs of 768 x 1e-4 turns: the halves cover other parts of the
    # circle (gaps of 1/6 - 0.077 turns) and their extents are not compared
    assert math.isnan(extent_drift(_turning(1 / 6 + 1e-4)))


def test_an_arc_is_not_shown_to_be_a_torus():
    """A circle turned by 1e-3 per sample: 400 samples sweep 0.4 turns of it, an arc (under one turn about the arc's
    own centre too: refused); 1536 samples sweep 1.5 turns (a torus, its rotation number 1e-3)."""
    torus, why, _, _ = torus_evidence(_turning(1e-3, n=400), 16)
    assert not torus and "no closed curve shown" in why
    torus, _, _, rho = torus_evidence(_turning(1e-3), 16)
    assert torus and rho == pytest.approx(1e-3, rel=0.1)


def test_a_circle_locked_near_a_resonance_is_not_shown_to_be_a_torus():
    """On a circle turned by rho per sample the lag-L distance of the samples reaches sin(pi ||L rho||) of their
    extent (the diameter): at the golden mean above 3.7e-3 for every L <= 384 (its closest return, ||377 rho|| =
    1.2e-3), far above LOCK_TOL; at rho = 7/24 + 1e-7 it is sin(pi 24e-7) = 7.5e-6 at lag 24, below it."""
    circle = _turning
    assert locked_lag(circle(RHO)) == (0, pytest.approx(math.nan, nan_ok=True))
    lag, close = locked_lag(circle(7 / 24 + 1e-7))
    assert lag == 24 and close == pytest.approx(math.sin(math.pi * 24e-7), rel=0.05)
    torus, why, _, _ = torus_evidence(circle(7 / 24 + 1e-7), 16)
    assert not torus and "lag 24" in why


def _island_chain(r: float, decay: float = 1.0, n: int = 1536) -> np.ndarray:
    """n samples e^(2 pi i k / 6) + r decay^k e^(2 pi i k rho / 6), rho the golden mean's complement: six small
    circles turned by rho per six samples about a period-6 orbit (decay = 1: an island chain, a torus), or six
    spirals onto it.  The lag-6 distance is 2 r decay^k sin(pi rho) (0.92 % of the extent 2 + 2 r at r = 0.01); the
    best lag-6m return within a quarter of the record (m = 55: ||55 rho|| = 8.1e-3) leaves 5e-4 of the extent."""
    k = np.arange(n)
    z = np.exp(2j * math.pi * k / 6) + r * decay ** k * np.exp(2j * math.pi * RHO * k / 6)
    return np.c_[z.real, z.imag]


def test_an_island_chain_is_a_torus_a_chain_of_spirals_is_not():
    """A small lag-6 distance (0.92 % of the extent) that does not decay is an island chain: thesis-1dof
    (`matlab-listing`, `listing`, 10 Hz, 95 V) has one, lag-6 distance 0.73 % steady over 6000 periods (it was
    "a period-6 orbit still converging").  Spirals decaying 0.997 per sample onto the same period-6 orbit are not."""
    torus, why, _, rho = torus_evidence(_island_chain(0.01), 16)
    assert torus and why == "" and abs(rho - 1 / 6) < 1e-4
    assert locked_lag(_island_chain(0.01))[0] == 0
    torus, why, _, _ = torus_evidence(_island_chain(0.01, 0.997), 16)
    assert not torus and "lag-6 distance decays (0.9970 per period)" in why


def test_the_mechanical_period_where_the_current_flips_sign():
    """4 Hz, 130 V, matlab-listing (listing law): the bar's position and speed repeat every relay period
    with one impact while the coil's current and charge flip sign: full period 2 with 2 impacts,
    mechanical period 1 with 1 impact (the thesis' period-1), checked here on the stored samples."""
    ds = bifurc.sweep("thesis-1dof", "V", [130.0], preset="matlab-listing", params={"relay_hz": 4.0},
                      grazing=False, error_sample=0, progress=False).isel(branch=0, V=0)
    assert int(ds.period) == 2 and int(ds.impacts_per_period) == 2
    assert int(ds.period_mechanical) == 1 and int(ds.impacts_per_period_mechanical) == 1
    assert "change sign" in str(ds.period_difference.values)
    x, i = ds.x.values, ds.i.values
    assert np.max(np.abs(np.diff(x))) < 1e-6 * np.max(np.abs(x))                     # x repeats every period
    assert np.max(np.abs(i[1:] + i[:-1])) < 1e-6 * np.max(np.abs(i))                 # i flips sign
    assert np.max(np.abs(i[2:] - i[:-2])) < 1e-6 * np.max(np.abs(i))                 # and repeats every 2
    assert set(ds.impacts_per_step.values.tolist()) == {1}


def test_the_chaotic_exponent_interval_holds_an_extended_precision_estimate():
    """The impact oscillator near resonance (Omega = 0.975) is chaotic; the stored interval covers the
    exponent of another trajectory computed here over the same number of periods by Benettin's
    two-trajectory method on the long double map (another method, another precision, another start)."""
    osc = dict(w0=1.0, zeta=0.02, F=0.1, e=-1.0, r=0.8, Omega=0.975)
    ds = bifurc.sweep("impact-oscillator", "Omega", [0.975], params=osc, transient=300, record=100,
                      tol=1e-12, grazing=False, error_sample=0, progress=False).isel(branch=0, Omega=0)
    assert ClassCode(int(ds.class_code)) == ClassCode.CHAOTIC
    lo, hi, m = float(ds.lyapunov_low), float(ds.lyapunov_high), int(ds.record_used)
    smap = maps.StroboscopicMap(maps.problem("impact-oscillator", params=osc), tol=1e-16, fp_type=np.longdouble)
    from bifurc.labels.lyapunov import largest_lyapunov
    start = smap.orbit({"x": 0.3, "v": 0.1}, 1, transient=400).state(0)      # another start, same attractor
    lam = largest_lyapunov(smap.step, start.y, min(m, 300), scale=np.array([1.0, 1.0]), k0=400)
    assert lo <= lam <= hi, (lo, lam, hi)
    assert hi - lo < 0.5                                           # an interval that says something


def _orbit_from(points, impacts):
    """A MapOrbit of given samples and contacts (no events, no tangent)."""
    from maps.poincare import MapOrbit
    n = len(impacts)
    z = np.zeros(n)
    return MapOrbit(times=np.arange(n + 1.0), points=np.asarray(points, float), impacts_per_step=np.asarray(impacts),
                    min_clearance_per_step=z, min_impact_speed_per_step=z, impact_time=np.zeros(0),
                    impact_velocity=np.zeros(0), impact_phase=np.zeros(0), impact_penetration=np.zeros(0),
                    impact_duration=np.zeros(0), min_flight_clearance_per_step=z, final_state=np.asarray(points[-1]))


def test_an_intermittent_record_is_judged_on_its_stationary_part():
    """A record whose first half is irregular (random states and contacts) and second half exactly
    period-2 with one impact per period: the first half is discarded as a transient and the value is
    periodic, period 2, with the window starting where the regular part does."""
    rng = np.random.default_rng(3)
    half = 200
    wild = rng.normal(size=(half, 2))
    tame = np.array([[1.0, 0.5], [-1.0, 0.25]] * (half // 2 + 1))[:half + 1]
    points = np.vstack([wild, tame])
    impacts = np.r_[rng.integers(0, 3, half), np.tile([1, 0], half // 2)]
    v = Value(5.0, {}, 1, _orbit_from(points, impacts), start=300)
    judge(v, classify=lambda o: classify_orbit(o.points, o.impacts_per_step, max_period=10),
          stretch=lambda o: None, budget=10_000, record=100, lyapunov=False, observable=lambda o: o.points)
    assert v.cls["label"] == "periodic" and v.cls["period"] == 2 and v.cls["impacts_per_period"] == 1
    assert v.start == 300 + half and v.orbit.n == half and v.action is None


def test_an_exponent_interval_is_a_prediction_for_another_trajectory():
    """exponent_estimate on K trajectories whose means differ: the interval is at least the Student-t
    prediction interval of their spread, which covers a further trajectory drawn alike."""
    rng = np.random.default_rng(7)
    rows = [rng.normal(mu, 0.5, 400) for mu in (0.10, 0.14, 0.08, 0.12)]
    mean, lo, hi, spread = exponent_estimate(np.vstack(rows))
    means = [r.mean() for r in rows]
    assert mean == pytest.approx(np.mean(means)) and spread == pytest.approx(np.std(means, ddof=1))
    assert hi - mean >= 3.182 * spread * math.sqrt(1.25) - 1e-12


@pytest.mark.slow
def test_same_dataset_on_any_number_of_workers(tmp_path):
    """Each value's extensions depend on its own record only: 1 and 2 workers give the same classes,
    exponents and windows (bit for bit)."""
    script = tmp_path / "run.py"
    script.write_text(textwrap.dedent("""
        import sys, numpy as np, bifurc
        if __name__ == "__main__":
            d = bifurc.sweep("thesis-1dof", "relay_hz", np.linspace(5.0, 9.0, 9), preset="matlab-listing",
                             params={"V": 90}, budget=1200, progress=False, workers=int(sys.argv[1]), error_sample=0)
            d.to_netcdf(sys.argv[2])
    """))
    for w in (1, 2):
        subprocess.run([sys.executable, str(script), str(w), str(tmp_path / f"w{w}.nc")], check=True,
                       env=dict(os.environ, MPLBACKEND="Agg"))
    import xarray as xr
    a, b = xr.open_dataset(tmp_path / "w1.nc"), xr.open_dataset(tmp_path / "w2.nc")
    for name in ("class_code", "period", "lyapunov", "lyapunov_low", "record_used", "transient_used", "x"):
        np.testing.assert_array_equal(a[name].values, b[name].values, err_msg=name)


@pytest.mark.slow
def test_the_stored_interval_covers_other_trajectories_of_the_same_attractor():
    """9 Hz, 90 V, matlab-listing: chaotic with intermittency (two trajectories of 4000 periods gave 0.073
    and 0.099).  20 trajectories from other starts, on the scalar engine, each measured over the stored
    window's length: at least 19 of 20 fall inside the stored 95 % interval, whose half-width is at most
    1.5 times the 95 % range of those 20 estimates (an interval that passes by being wide fails)."""
    ds = bifurc.sweep("thesis-1dof", "relay_hz", [9.0], preset="matlab-listing", params={"V": 90.0},
                      grazing=False, error_sample=0, progress=False).isel(branch=0, relay_hz=0)
    assert ClassCode(int(ds.class_code)) == ClassCode.CHAOTIC
    lo, hi, m = float(ds.lyapunov_low), float(ds.lyapunov_high), int(ds.record_used)
    p = maps.problem("thesis-1dof", preset="matlab-listing", params={"V": 90.0, "relay_hz": 9.0})
    smap = maps.StroboscopicMap(p, tol=1e-10)
    estimates = []
    for j in range(20):
        start = dict(p.x0, x=1e-3 * (1 + 0.37 * j))           # other starts above the stop
        o = smap.orbit(start, m, transient=600, tangent=True)
        scale = np.maximum(np.abs(o.points).max(axis=0), 1e-9)
        estimates.append(float(np.mean(o.tangent_stretch(scale))))
    est = np.array(estimates)
    inside = int(np.sum((est >= lo) & (est <= hi)))
    spread95 = float(np.percentile(est, 97.5) - np.percentile(est, 2.5))
    print(f"stored [{lo:.4f}, {hi:.4f}] over {m}; 20 estimates {est.min():.4f}..{est.max():.4f}, {inside} inside")
    assert inside >= 19
    assert (hi - lo) / 2 <= 1.5 * spread95


@pytest.mark.slow
@pytest.mark.xfail(reason="issue 27's 95 % is not met: 68 of 75 decided values (91 %) on 2026-11-26 (budget 6000, "
                          "restarted from a stored sample of the judged window); every periodic label holds; 4 chaotic "
                          "labels become periodic on the 24000-period re-run (chaotic transients of about 10^4 relay "
                          "periods: at 3.4 Hz the scene's start lands on a period-34 orbit after 20,500 periods; 2.9 and "
                          "3.5 Hz on none within 24,000) and 3 weakly chaotic ones become undecided", strict=False)
def test_decided_labels_are_stable_on_a_longer_record_from_another_start():
    """The main job's grid: every decided value re-run from a stored sample of its judged window
    perturbed by 1e-7 (another start on the attractor its label describes; a state recomputed from the
    scene's start on the other engine would not be: chaotic transients amplify round-off) with a 4x
    longer first record keeps its class in at least 95 % of cases."""
    from bifurc.sweeps.job import ValueJob
    values = np.linspace(2, 10, 81)
    d = bifurc.sweep("thesis-1dof", "relay_hz", values, preset="matlab-listing", params={"V": 90.0},
                     grazing=False, error_sample=0, progress=False, batch_size=1, workers=1)
    p = maps.problem("thesis-1dof", preset="matlab-listing", params={"V": 90.0})
    job = ValueJob(p, "relay_hz", transient=100, record=400, tol=1e-10, budget=24_000)
    smap = job.warm()
    states = [st.name for st in smap.system.states]
    flag_names = list(smap.system.flag_names)
    decided = same = 0
    changed = []
    for i, w in enumerate(values):
        code = ClassCode(int(d.class_code.values[0, i]))
        if code in (ClassCode.NOT_CONVERGED, ClassCode.ESCAPED, ClassCode.FAILED):
            continue
        smap.set_params(**job.at(w))
        q = smap.forcing_period_steps
        j = (-int(d.transient_used.values[0, i])) % q if q else -1   # a stored sample at the phase of t = 0
        if q == 0 or j > int(d.attrs["recorded_periods"]):
            continue
        y = np.array([float(d[s].values[0, i, j]) for s in states])
        flags = {f: float(d[f"flag_{f}"].values[0, i, j]) for f in flag_names}
        start = (y * (1 + 1e-7), flags)
        decided += 1
        again = job(w, start)
        same += ClassCode(int(again.class_code)) == code
        if ClassCode(int(again.class_code)) != code:
            changed.append(f"{w:.1f} Hz {code.name} -> {ClassCode(int(again.class_code)).name} ({again.class_reason[:60]})")
    print(f"{same} of {decided} decided values keep their class; changed: " + "; ".join(changed))
    assert decided >= 70 and same >= 0.95 * decided


def test_both_period_conventions_in_report_and_figure(tmp_path):
    """4 Hz, 130 and 135 V: the report and the class strip read the full state's period (2:2) or the
    mechanical one (1:1), and say which."""
    import matplotlib
    matplotlib.use("Agg")
    from bifurc.storage.load import in_convention
    d = bifurc.sweep("thesis-1dof", "V", [130.0, 135.0], preset="matlab-listing", params={"relay_hz": 4.0},
                     grazing=False, error_sample=0, progress=False)
    full, mech = bifurc.classification_report(d, at=[130]), bifurc.classification_report(d, at=[130],
                                                                                         period_of="mechanical")
    assert "period-2, 2 impacts" in full and "reads the **full** one" in full
    assert "period-1, 1 impact" in mech and "reads the **mechanical** one" in mech
    assert "differ at 2 value(s)" in full
    ax = bifurc.plot_diagram(d, period_of="mechanical")
    strip = ax.figure.axes[1]
    assert "mechanical" in strip.get_ylabel() and any(t.get_text() == "1:1" for t in strip.texts)
    assert list(in_convention(d, "mechanical").period.values[0]) == [1, 1]
    with pytest.raises(maps.ParameterError, match="period_of"):
        in_convention(d, "electrical")


def test_a_chaotic_label_and_its_stored_interval_agree_or_the_label_says_what_decided():
    """The impact oscillator near resonance is chaotic.  With 4 and with 6 tangent trajectories
    (Diagram(trajectories=...)), the stored interval is over ``lyapunov_window`` periods and either lies above
    the chaos threshold of that window (2 ln(n)/n, at least 2e-3: the rule the dataset states) or the reason
    names the evidence that decided; the trajectories the interval came from are the method's."""
    osc = dict(w0=1.0, zeta=0.02, F=0.1, e=-1.0, r=0.8, Omega=0.975)
    pb = maps.problem("impact-oscillator", params=osc)
    for k in (4, 6):
        ds = bifurc.sweep(pb, "Omega", [0.975], bifurc.Diagram(record=100, tol=1e-12, grazing=False, error_sample=0,
                                                               trajectories=k),
                          run=bifurc.Run(progress=False)).isel(branch=0, Omega=0)
        assert ClassCode(int(ds.class_code)) == ClassCode.CHAOTIC
        assert int(ds.lyapunov_trajectories) == k and ds.attrs["lyapunov_trajectories"] == k
        n = int(ds.lyapunov_window)
        assert 400 <= n <= int(ds.record_used)
        threshold = max(2 * math.log(n) / n, 2e-3)
        reason = str(ds.class_reason.values)
        if float(ds.lyapunov_low) > threshold:
            assert reason == ""
        else:
            assert reason.startswith("chaotic on the evidence of") and f"{threshold:.3g}" in reason, reason
