"""The DC well: where the bar rests with the AC off, and setting the well by that rest point.

Every DC law (``maps.laws.DC_LAWS``) makes, with the weight, a potential well for the bar.  With
the AC solenoid off the net force on the bar at height x above the stop (x = r in 2 DOF) is

    N(x) = dc_scale * F1(x - d_dc) - W,     W = m g (1-DOF, laws "measured" and "catalogue"), else 0

(F1: the law at dc_scale 1; the cubic laws carry +m g, which cancels the weight; 2 DOF is
horizontal), and its potential is V(x) = -integral of N from the stop.  Derived here, in SI units:

- ``dc_rest`` [m]: the rest height: the global minimum of V over the model's domain [0, d_dc + 0.1 m]
  (:data:`maps.model.ESCAPE_MARGIN`); the stop (x = 0) is a candidate when N(0) <= 0 (the bar
  pressed on it stays).  Of two minima of equal depth (the ``fit`` law's double well, equal to
  1e-20 J) the one nearer the stop.
- ``dc_stiffness`` [N/m]: -dN/dx at the rest height (the well's, not the stop's).
- ``dc_depth`` [J]: V(0) - V(rest): the energy of the bar at rest on the stop above the well's bottom.
- ``dc_range`` [m]: the height above the rest where V regains V(0): the top of the undamped swing of
  a bar released at rest on the stop with the AC off (2 d_dc for the odd cubics); NaN when V stays
  below V(0) up to the domain's end (the bar escapes).
- ``dc_stop_force`` [N]: N(0), the net force on the bar at rest on the stop (<= 0: it stays there).

The inputs ``dc_rest`` and ``dc_stiffness`` set the well keeping the law's shape in xa: the
stiffness by ``dc_scale`` (which, where W > 0, also moves the equilibrium along the law), then the
rest height by shifting ``d_dc`` (:func:`place`).  :data:`WELL_INPUTS` declares them like any
parameter (name, unit, range); the model itself only ever sees d_dc and dc_scale.
"""
from __future__ import annotations

import math

import numpy as np

from .parameters import Parameter, ParameterError


#: the well's inputs (``--set dc_rest=0.005``, ``params={"dc_rest": 0.005}``): name -> Parameter
WELL_INPUTS = {p.name: p for p in [
    Parameter("dc_rest", "m", "DC well: rest height of the bar above the stop with the AC off (sets d_dc)", 0, 0.5),
    Parameter("dc_stiffness", "N m-1", "DC well: stiffness -dN/dx at the rest height (sets dc_scale)", 0, 1e6,
              low_open=True),
]}
#: the derived quantities (dataset attributes and ``bifurc params``): name -> (unit, meaning)
WELL_OUTPUTS = {
    "dc_rest": ("m", "rest height of the bar above the stop with the AC off (gravity included)"),
    "dc_stiffness": ("N m-1", "well stiffness -dN/dx at the rest height"),
    "dc_depth": ("J", "well depth: potential of the bar at rest on the stop above the rest point"),
    "dc_range": ("m", "top of the undamped swing from rest on the stop, AC off (NaN: escapes)"),
    "dc_stop_force": ("N", "net force on the bar at rest on the stop, AC off (<= 0: it stays on the stop)"),
}
WELL_DEFINITIONS = ("AC off, N(x) = dc_scale F_dc(x - d_dc) - W (W = m g for 1-DOF measured/catalogue, 0 where "
                    "the law's +m g cancels the weight or in 2 DOF), V = -int N dx from the stop; rest: global "
                    "minimum of V on [0, d_dc + 0.1 m] (the stop counts when N(0) <= 0); stiffness -dN/dx there; "
                    "depth V(0) - V(rest); range: where V regains V(0) above the rest (maps/well.py)")

_SHAPE = ("a1", "a2", "a3", "F_dc_sat", "u_dc", "s_dc")   # the law's shape (kept by dc_rest, dc_stiffness)


def _weight(options, values) -> float:
    """W [N]: the weight the DC force works against (0 where the law's +m g cancels it, and in 2 DOF)."""
    if options.dof == 1 and options.dc_law in ("measured", "catalogue"):
        return values["m"] * values["g"]
    return 0.0


def _lncosh(a):
    a = np.abs(a)
    return a + np.log1p(np.exp(-2.0 * a)) - math.log(2.0)


def dc_force(law: str, xa, values) -> tuple:
    """(F1, dF1/dxa, U1) of DC law ``law`` at dc_scale 1: force [N] along +x at xa [m] (bar centre
    above the DC centre), its derivative [N/m] and its potential [J] (U1(0) = 0); numpy, as
    maps/model.py's ``_dc_law`` writes them."""
    xa = np.asarray(xa, dtype=float)
    if law in ("listing", "dynamics-script"):
        a1, a2, a3 = values["a1"], values["a2"], values["a3"]
        F = -a3 * xa**3 + a2 * xa**2 - a1 * xa
        dF = -3 * a3 * xa**2 + 2 * a2 * xa - a1
        U = a3 * xa**4 / 4 - a2 * xa**3 / 3 + a1 * xa**2 / 2
    elif law == "fit":
        a1, a2, a3 = values["a1"], values["a2"], values["a3"]
        F = -a3 * xa**3 - a2 * xa**2 + a1 * xa
        dF = -3 * a3 * xa**2 - 2 * a2 * xa + a1
        U = a3 * xa**4 / 4 + a2 * xa**3 / 3 - a1 * xa**2 / 2
    elif law == "catalogue":
        Fs, u, s = values["F_dc_sat"], values["u_dc"], values["s_dc"]
        a, b = (xa - u) / (2 * s), (xa + u) / (2 * s)
        F = -0.5 * Fs * (np.tanh(a) + np.tanh(b))
        dF = -Fs / (4 * s) * (1 / np.cosh(a)**2 + 1 / np.cosh(b)**2)
        U = Fs * s * (_lncosh(a) + _lncosh(b) - 2 * _lncosh(u / (2 * s)))
    elif law == "measured":
        from .model import measured_dc_regions
        regs = measured_dc_regions()
        lows = np.array([r[0] for r in regs])
        k = np.clip(np.searchsorted(lows, xa, side="right") - 1, 0, len(regs) - 1)
        c = np.array([r[2:6] for r in regs])[k]
        u0 = np.array([r[6] for r in regs])[k]
        sl = xa - lows[k]
        F = ((c[..., 3] * sl + c[..., 2]) * sl + c[..., 1]) * sl + c[..., 0]
        dF = (3 * c[..., 3] * sl + 2 * c[..., 2]) * sl + c[..., 1]
        U = u0 - (((c[..., 3] / 4 * sl + c[..., 2] / 3) * sl + c[..., 1] / 2) * sl + c[..., 0]) * sl
    else:
        raise ParameterError(f"option 'dc_law' = {law!r} has no DC well")
    return F, dF, U


def net_force(options, values, x) -> tuple:
    """(N, dN/dx) [N, N/m] on the bar at height ``x`` [m] above the stop, AC off."""
    F, dF, _ = dc_force(options.dc_law, np.asarray(x, float) - values["d_dc"], values)
    s = values["dc_scale"]
    return s * F - _weight(options, values), s * dF


def potential(options, values, x):
    """V(x) [J]: the potential of the net force, AC off, V(0) = 0."""
    s, d, W = values["dc_scale"], values["d_dc"], _weight(options, values)
    U = dc_force(options.dc_law, np.asarray(x, float) - d, values)[2]
    U0 = dc_force(options.dc_law, np.asarray(-d), values)[2]
    return s * (U - U0) + W * np.asarray(x, float)


def _stable_zeros(fun, lo, hi, n=20001) -> list:
    """The zeros of ``fun`` on [lo, hi] where it falls through 0 (a stable equilibrium), refined."""
    from scipy.optimize import brentq
    x = np.linspace(lo, hi, n)
    y = fun(x)
    out = []
    for k in np.nonzero((y[:-1] > 0) & (y[1:] <= 0))[0]:
        if y[k + 1] == 0:
            out.append(float(x[k + 1]))
        else:
            out.append(float(brentq(fun, x[k], x[k + 1], xtol=1e-15, rtol=1e-15)))
    return sorted(set(out))


def well(options, values) -> dict:
    """The derived quantities of the DC well (:data:`WELL_OUTPUTS`) for a scene's ``options`` and
    parameter ``values``; empty for a scene without a DC solenoid."""
    if options is None or not options.dc:
        return {}
    from .model import ESCAPE_MARGIN
    top = values["d_dc"] + ESCAPE_MARGIN
    N = lambda x: net_force(options, values, x)[0]       # noqa: E731
    V = lambda x: potential(options, values, x)           # noqa: E731
    cands = [x for x in _stable_zeros(N, 0.0, top) if x > 0.0]
    N0 = float(N(0.0))
    if N0 <= 1e-10:          # pressed on the stop, or a rest exactly on it (to rounding)
        cands = [0.0] + cands
    if not cands:          # pushed off the stop and never held: no rest in the domain
        return {"dc_rest": math.nan, "dc_stiffness": math.nan, "dc_depth": math.nan, "dc_range": math.nan,
                "dc_stop_force": N0}
    Vs = np.array([float(V(x)) for x in cands])
    tie = 1e-12 * max(1.0, float(np.max(np.abs(Vs))))
    rest = cands[int(np.nonzero(Vs <= Vs.min() + tie)[0][0])]     # ties: the one nearest the stop
    K = -float(net_force(options, values, rest)[1])
    depth = -float(V(rest))
    rng = 0.0 if rest == 0.0 else math.nan
    if rest > 0.0:
        from scipy.optimize import brentq
        x = np.linspace(rest, top, 20001)
        up = np.nonzero(V(x) >= 0.0)[0]
        if up.size:
            j = up[0]
            rng = float(brentq(V, x[j - 1], x[j], xtol=1e-15, rtol=1e-15)) if j > 0 else float(x[0])
    return {"dc_rest": float(rest) + 0.0, "dc_stiffness": K + 0.0, "dc_depth": depth + 0.0, "dc_range": rng + 0.0,
            "dc_stop_force": N0 + 0.0}


def _xa_rest(law, values, W, s) -> float:
    """xa [m] of the law's own stable equilibrium at dc_scale ``s`` (s F1(xa) = W), ignoring the
    stop: of several, the one of lowest potential, ties to the lowest xa.  NaN if none."""
    fun = lambda xa: s * dc_force(law, xa, values)[0] - W      # noqa: E731
    zs = _stable_zeros(fun, -0.5, 0.5, 40001)
    if not zs:
        return math.nan
    Us = np.array([s * float(dc_force(law, z, values)[2]) + W * z for z in zs])
    return zs[int(np.nonzero(Us <= Us.min() + 1e-12 * max(1.0, float(np.max(np.abs(Us)))))[0][0])]


def place(options, values, rest=None, stiffness=None) -> dict:
    """{"d_dc", "dc_scale"} that put the well's rest at height ``rest`` [m] with stiffness
    ``stiffness`` [N/m] (either may be None: kept), the law's shape in xa unchanged.

    The stiffness sets dc_scale (for W > 0 the equilibrium then slides along the law: s F1(xa*) = W),
    the rest height sets d_dc = rest - xa*.  Raises :class:`ParameterError` (one line, with the
    allowed range) when the law cannot place the well so.
    """
    from .model import PARAMETERS
    law, W = options.dc_law, _weight(options, values)
    s = values["dc_scale"]
    P_s, P_d = PARAMETERS["dc_scale"], PARAMETERS["d_dc"]
    if stiffness is not None:
        K = WELL_INPUTS["dc_stiffness"].validate(stiffness)
        if W == 0.0:
            xa = _xa_rest(law, values, 0.0, 1.0)
            K1 = -float(dc_force(law, xa, values)[1]) if not math.isnan(xa) else math.nan
            if not K1 > 0:
                raise ParameterError(f"parameter 'dc_stiffness': dc_law {law} has no stable well to scale")
            s = K / K1
            lo, hi = 0.0, P_s.high * K1
        else:
            # on the law's stable branch, s(xa) = W / F1(xa) and K(xa) = -W F1'(xa) / F1(xa)
            xa = np.linspace(-0.5, 0.0, 200001)[:-1]
            F, dF, _ = dc_force(law, xa, values)
            ok = (F > W / P_s.high) & (dF < 0)
            if not ok.any():
                raise ParameterError(f"parameter 'dc_stiffness': dc_law {law} cannot hold the weight within "
                                     f"dc_scale {P_s.range_text()}")
            Ks = np.where(ok, -W * dF / np.where(ok, F, 1.0), np.nan)
            lo, hi = float(np.nanmin(Ks)), float(np.nanmax(Ks))
            if not lo <= K <= hi:
                raise ParameterError(f"parameter 'dc_stiffness' = {K:g} N m-1 is outside the range dc_law {law} can "
                                     f"give with dc_scale {P_s.range_text()}: [{lo:.6g}, {hi:.6g}] N m-1")
            from scipy.optimize import brentq
            j = np.nonzero(ok)[0]
            seg = j[np.nonzero(np.diff(np.sign(Ks[j] - K)))[0]]      # bracketing grid points
            if seg.size == 0:
                k = j[int(np.nanargmin(np.abs(Ks[j] - K)))]
                x_star = float(xa[k])
            else:
                k = seg[-1]                                        # the branch nearest the centre
                g = lambda z: -W * dc_force(law, z, values)[1] / dc_force(law, z, values)[0] - K  # noqa: E731
                x_star = float(brentq(g, xa[k], xa[k + 1], xtol=1e-15, rtol=1e-15))
            s = W / float(dc_force(law, x_star, values)[0])
        if not lo < K <= hi * (1 + 1e-12) or not P_s.low <= s <= P_s.high:
            raise ParameterError(f"parameter 'dc_stiffness' = {K:g} N m-1 is outside the range dc_law {law} can give "
                                 f"with dc_scale {P_s.range_text()}: ({lo:.6g}, {hi:.6g}] N m-1")
    xa_star = _xa_rest(law, values, W, s)
    if math.isnan(xa_star):
        raise ParameterError(f"parameter 'dc_rest': dc_law {law} at dc_scale {s:g} has no stable equilibrium")
    h = values["d_dc"] + xa_star if rest is None else WELL_INPUTS["dc_rest"].validate(rest)
    d = h - xa_star
    if not P_d.low <= d <= P_d.high:
        raise ParameterError(f"parameter 'dc_rest' = {h:g} m is outside the range dc_law {law} can give with d_dc "
                             f"{P_d.range_text()} m: [{max(0.0, P_d.low + xa_star):.6g}, {P_d.high + xa_star:.6g}] m")
    return {"d_dc": float(d), "dc_scale": float(s)}


def apply_inputs(options, table: dict, inputs: dict) -> dict:
    """``table`` {name: (value, provenance)} with the well ``inputs`` ({"dc_rest": ..,
    "dc_stiffness": ..}) turned into d_dc and dc_scale (:func:`place`), their provenance saying so;
    checks that the placed rest is the well's rest (:func:`well`)."""
    if not inputs:
        return table
    name = next(iter(inputs))
    if options is None or not options.dc:
        raise ParameterError(f"parameter {name!r} sets the DC well: this scene has no DC solenoid")
    for k in inputs:
        WELL_INPUTS[k].validate(inputs[k])
    values = {k: v for k, (v, _) in table.items()}
    new = place(options, values, inputs.get("dc_rest"), inputs.get("dc_stiffness"))
    what = ", ".join(f"{k} = {inputs[k]:g} {WELL_INPUTS[k].unit}" for k in inputs)
    out = dict(table)
    src = (f"set by user through {what} (maps/well.py place: the law's shape kept, dc_scale sets the "
           f"stiffness, d_dc shifts the law so that the rest sits at its height)")
    if "dc_stiffness" in inputs:
        out["dc_scale"] = (new["dc_scale"], src)
    out["d_dc"] = (new["d_dc"], src)
    values.update(new)
    got = well(options, values)
    if "dc_rest" in inputs and not abs(got["dc_rest"] - inputs["dc_rest"]) <= 1e-9:
        def holds(h):
            v = dict(values, **place(options, values, h, inputs.get("dc_stiffness")))
            return abs(well(options, v)["dc_rest"] - h) <= 1e-9
        lo, hi = 0.0, float(inputs["dc_rest"])
        for _ in range(40):     # the highest rest the law holds above the stop
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if holds(mid) else (lo, mid)
        raise ParameterError(f"parameter 'dc_rest' = {inputs['dc_rest']:g} m is outside the range dc_law "
                             f"{options.dc_law} can give (higher, the bar rests lower, at {got['dc_rest']:g} m; "
                             f"0: on the stop): [0, {lo:.4g}] m")
    return out


def check_inputs(inputs: dict, others, scene: str) -> None:
    """Refuse a well input given with the parameter it sets (dc_rest with d_dc, dc_stiffness with dc_scale)."""
    for k, par in (("dc_rest", "d_dc"), ("dc_stiffness", "dc_scale")):
        if k in inputs and par in others:
            raise ParameterError(f"parameter {k!r} sets {par!r}: give one of them, not both (scene {scene!r})")
