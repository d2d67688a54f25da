"""The electro-vibro-impact model (docs/model.md).

:func:`build_system` assembles a :class:`~maps.hybrid.HybridSystem` from
structural options.  It compiles only the states and terms a scene needs: a
DC-only scene has no circuit states, a scene without a stop has no contact
guards.  All coefficients are runtime parameters.

Sign conventions: x (1-DOF) or r = x1 - x2 (2-DOF) is the bar's distance above
(behind) the stop, + away from the stop toward the DC solenoid.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import heyoka as hy
import numpy as np

from .hybrid import Guard, HybridSystem, PeriodicSwitch, State
from .laws import COMPACTION, DC_LAWS, SOIL_LAWS  # noqa: F401 - maps.model.COMPACTION: the laws read here
from .parameters import Parameter

INF = math.inf
#: the table of every model parameter: name -> Parameter (``bifurc params`` lists them)
PARAMETERS = {p.name: p for p in [
    Parameter("m", "kg", "bar mass", 0, INF, low_open=True),
    Parameter("m1", "kg", "bar mass", 0, INF, low_open=True),
    Parameter("m2", "kg", "rig mass", 0, INF, low_open=True),
    Parameter("g", "m s-2", "gravitational acceleration", 0, 100),
    Parameter("k", "N m-1", "stop stiffness", 0, 1e14, low_open=True),
    Parameter("c", "N s m-1", "stop damping", 0, 1e7),
    Parameter("e", "m", "clearance of the stop", -0.01, 0.05),
    Parameter("R", "ohm", "circuit resistance", 0, 1e6, low_open=True),
    Parameter("C", "F", "circuit capacitance", 0, 100, low_open=True),
    Parameter("V", "V", "AC source amplitude", 0, 1e4),
    Parameter("f_mains", "Hz", "AC source frequency", 0, 1e4, low_open=True),
    Parameter("relay_hz", "Hz", "relay (SSR) switching frequency", 0, 1e3, low_open=True),
    Parameter("a1", "N m-1", "DC force cubic, linear coefficient"),
    Parameter("a2", "N m-2", "DC force cubic, quadratic coefficient"),
    Parameter("a3", "N m-3", "DC force cubic, cubic coefficient"),
    Parameter("d_dc", "m", "stop-to-DC-solenoid-centre offset (0: the law centred at the stop)", 0, 0.5),
    Parameter("d_ac", "m", "AC-solenoid-centre-to-stop offset", 0, 0.5, low_open=True),
    Parameter("L0", "H", "inductance fit, baseline", 0, 100, low_open=True),
    Parameter("A", "H", "inductance fit, amplitude", 0, 100),
    Parameter("B", "m", "inductance fit, width", 0, 1, low_open=True),
    Parameter("dc_scale", "1", "multiplier on the DC magnetic force (1 at 20 V DC)", 0, 100),
    Parameter("F_static", "N", "static force pushing the rig into the soil", -1e5, 1e5),
    Parameter("soil_c", "N s m-1", "viscous soil coefficient", 0, 1e7),
    Parameter("soil_friction", "N", "dry-friction limit of the soil", 0, 1e7),
    Parameter("k_s", "N m-1", "drift soil: stiffness of the visco-elastic element", 0, 1e12, low_open=True),
    Parameter("c_s", "N s m-1", "drift soil: damping of the visco-elastic element", 0, 1e7, low_open=True),
    Parameter("P_max", "N", "drift soil: threshold force of the plastic slider", 0, 1e7),
    Parameter("soil_depth_scale", "m", "compaction: depth over which the soil's resistance grows by its "
                                       "surface value", 0, 1e6, low_open=True),
    Parameter("F_dc_sat", "N", "catalogue DC law: plateau pull at 20 V DC", 0, 1e3, low_open=True),
    Parameter("u_dc", "m", "catalogue DC law: |xa| of the pull's steep rise", 0, 0.5, low_open=True),
    Parameter("s_dc", "m", "catalogue DC law: width of the pull's rise", 0, 0.5, low_open=True),
    Parameter("c_air", "N s m-1", "free-flight damping of the bar (air and guide friction)", 0, 1e4),
    Parameter("e_rear", "m", "rear stop (housing): bar position r where it begins", 0, 0.5, low_open=True),
    Parameter("tau_dc", "s", "DC coil time constant L/R (switching delay)", 0, 10, low_open=True),
]}

#: the bar is "escaped" beyond d_dc + ESCAPE_MARGIN above the stop, or deeper
#: than STOP_ESCAPE into it [m]: far outside the fitted force laws.
ESCAPE_MARGIN = 0.1
STOP_ESCAPE = 0.02
#: offset [m] of the contact/release surface while the bar is stuck (both guards inactive then)
STUCK_LIFT = 1e-3

#: |xa| beyond which the measured law is zero [m] (the last row of Table 4.1)
DC_EDGE = 0.029
#: lower/upper bound [m] of the two outer regions of the measured law: never reached (the
#: escape guard ends a run at xa = ESCAPE_MARGIN and 0.0625 + STOP_ESCAPE below the centre)
_DC_FAR = 1.0


@dataclass(frozen=True)
class ModelOptions:
    """Structural options of the model: each combination compiles once."""

    dof: int = 1                 # 1: vertical bar; 2: horizontal bar + rig
    dc: bool = True              # DC solenoid force
    ac: bool = True              # AC solenoid and its circuit
    stop: bool = True            # the impact stop
    relay: str = "ssr"           # "ssr": AC on for the first half period; "antiphase": DC on
                                 # while AC off (prototype); "none": AC always on
    circuit: str = "thesis"      # "thesis": eq 4.16 in (i, z); "kvl": charge form in (q, i)
    ac_sign: str = "physical"    # "physical" or "listing" (listing C.2 reverses the AC force)
    dc_law: str = "listing"      # DC force: "listing" (C.9), "fit" (eqs 4.6-4.7), "measured"
                                 # (Table 4.1 only, zero beyond 29 mm), "catalogue" or
                                 # "dynamics-script" (C.14's cubic, centred at the stop); see DC_LAWS
    soil: str = "viscous"        # 2-DOF: "viscous", "coulomb" or "drift" (SOIL_LAWS)
    compaction: bool = False     # coulomb and drift: the resistance grows with depth (COMPACTION)
    air_damping: bool = False    # free-flight damping -c_air dr/dt (ELEMENTS; c_air = 0: the same motion)
    rear_stop: bool = False      # rear stop (housing) at r = e_rear, contact law of the stop (ELEMENTS)
    dc_delay: bool = False       # antiphase relay: DC coil current with time constant tau_dc (ELEMENTS)
    energy: bool = False         # add quadrature states for the energy audit (1-DOF: source,
                                 # resistance, stop damping; 2-DOF drift soil: the soil's damper and slider)
    stick_speed: float = 1e-4    # [m/s] a contact onset slower than this while the net
                                 # non-contact force presses the bar on the stop ends chattering:
                                 # the bar sticks (x = e, v = 0; 2-DOF: r = e, bar and rig move
                                 # as one body) until that force pulls it away
    unstick_force: float = 1e-9  # [N] the stuck bar leaves when that force exceeds this: above the
                                 # noise of heyoka's event polynomials (~tol x force), so a force
                                 # that only touches zero (AC alone, i^2 -> 0) does not free it

    def __post_init__(self):
        from .parameters import ParameterError
        allowed = {"dof": (1, 2), "relay": ("ssr", "antiphase", "none"),
                   "circuit": ("thesis", "kvl"), "ac_sign": ("physical", "listing"),
                   "dc_law": tuple(DC_LAWS),
                   "soil": tuple(SOIL_LAWS)}
        for name, values in allowed.items():
            if getattr(self, name) not in values:
                raise ParameterError(f"option {name!r} = {getattr(self, name)!r}; "
                                     f"allowed: {', '.join(map(str, values))}")
        for name in ("dc", "ac", "stop", "energy", "compaction", "air_damping", "rear_stop", "dc_delay"):
            if not isinstance(getattr(self, name), bool):
                raise ParameterError(f"option {name!r} = {getattr(self, name)!r}; allowed: True, False")
        from .parameters import validate_value
        validate_value("stick_speed", self.stick_speed, 0.0, 1.0, unit="m s-1")
        validate_value("unstick_force", self.unstick_force, 0.0, 1e3, unit="N")
        if self.energy and (self.air_damping or self.rear_stop):
            raise ParameterError("option 'energy' does not audit air damping or the rear stop: switch them off")
        if self.compaction and not (self.dof == 2 and self.soil in ("coulomb", "drift")):
            raise ParameterError("option 'compaction' needs dof=2 and soil 'coulomb' or 'drift'")
        if self.rear_stop and not self.stop:
            raise ParameterError("option 'rear_stop' needs the stop (stop=True): it shares the stop's k and c")
        if self.dc_delay and not (self.dc and self.relay == "antiphase"):
            raise ParameterError("option 'dc_delay' needs the DC solenoid switched by the antiphase relay "
                                 "(scene prototype)")
        if self.relay != "none" and not self.ac:
            raise ParameterError("option 'relay' needs the AC solenoid (ac=True)")
        if self.energy and not (self.dof == 2 and self.soil == "drift") and (
                self.dof != 1 or (self.ac and self.circuit != "kvl")):
            raise ParameterError("option 'energy' needs dof=1 and, with the AC solenoid, circuit='kvl' "
                                 "(or dof=2 with soil='drift': the soil's dissipation)")

    def parameter_names(self) -> list[str]:
        soil = {"viscous": ["soil_c"], "coulomb": ["soil_friction"], "drift": ["k_s", "c_s", "P_max"]}
        names = ["m", "g"] if self.dof == 1 else ["m1", "m2", "F_static"] + soil[self.soil]
        if self.compaction:
            names += ["soil_depth_scale"]
        if self.stop:
            names += ["k", "c", "e"]
        if self.rear_stop:
            names += ["e_rear"]
        if self.air_damping:
            names += ["c_air"]
        if self.dc:
            law = {"measured": [], "catalogue": ["F_dc_sat", "u_dc", "s_dc"]}.get(self.dc_law, ["a1", "a2", "a3"])
            names += law + ["d_dc", "dc_scale"] + (["tau_dc"] if self.dc_delay else [])
        if self.ac:
            names += ["R", "C", "V", "f_mains", "d_ac", "L0", "A", "B"]
        if self.relay != "none":
            names += ["relay_hz"]
        return names

    def state_list(self) -> list[State]:
        if self.dof == 1:
            st = [State("x", "m", "bar position above the stop"),
                  State("v", "m s-1", "bar velocity")]
        else:
            st = [State("x1", "m", "bar position"), State("v1", "m s-1", "bar velocity"),
                  State("x2", "m", "rig position"), State("v2", "m s-1", "rig velocity")]
        if self.ac:
            if self.circuit == "thesis":
                st += [State("i", "A", "AC solenoid current"), State("z", "A s-1", "current rate di/dt")]
            else:
                st += [State("q", "C", "capacitor charge"), State("i", "A", "AC solenoid current")]
        if self.dc_delay:
            st += [State("j_dc", "1", "DC coil current over its steady value (switching delay)")]
        if self.drift:
            st += [State("d", "m", "soil slider position (the soil front; drift law)")]
        if self.energy and self.dof == 1:
            st += [State("W_src", "J", "work done by the AC source"),
                   State("E_R", "J", "energy dissipated in the resistance"),
                   State("E_c", "J", "energy dissipated by stop damping")]
        elif self.energy:
            st += [State("E_soil_damper", "J", "energy dissipated by the soil's damper c_s"),
                   State("E_soil_plastic", "J", "energy dissipated by the soil's plastic slider")]
        return st

    @property
    def drift(self) -> bool:
        """True for the 2-DOF drift soil (slider state d, soil flags soil_el / soil_pl)."""
        return self.dof == 2 and self.soil == "drift"

    def state_names(self) -> list[str]:
        return [st.name for st in self.state_list()]

    def key(self) -> tuple:
        return tuple(sorted(self.__dict__.items()))


def _pchip_slopes(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Fritsch-Carlson slopes of the monotone piecewise cubic through (x, y) (as scipy's PCHIP)."""
    h, d = np.diff(x), np.diff(y) / np.diff(x)
    m = np.zeros_like(y)
    for k in range(1, x.size - 1):
        if d[k - 1] * d[k] > 0:
            w1, w2 = 2 * h[k] + h[k - 1], h[k] + 2 * h[k - 1]
            m[k] = (w1 + w2) / (w1 / d[k - 1] + w2 / d[k])

    def end(h0, h1, d0, d1):
        e = ((2 * h0 + h1) * d0 - h0 * d1) / (h0 + h1)
        if np.sign(e) != np.sign(d0):
            return 0.0
        if np.sign(d0) != np.sign(d1) and abs(e) > 3 * abs(d0):
            return 3 * d0
        return e

    m[0] = end(h[0], h[1], d[0], d[1])
    m[-1] = end(h[-1], h[-2], d[-1], d[-2])
    return m


_REGIONS: list = []


def measured_dc_regions() -> list[tuple]:
    """The measured DC-force law (``dc_law="measured"``) as regions of xa, in increasing order.

    Each region is ``(lo, hi, c0, c1, c2, c3, u0)``: on lo <= xa < hi [m] the force along +x at
    dc_scale = 1 is ``F = c0 + c1 s + c2 s^2 + c3 s^3`` [N] with s = xa - lo, and its potential
    ``U = u0 - (c0 s + c1 s^2/2 + c2 s^3/3 + c3 s^4/4)`` [J] (U(0) = 0, continuous everywhere).
    Table 4.1 gives the pull magnitude T(|xa|) for 0 <= |xa| <= 0.029 m; T is the monotone
    piecewise cubic through its points, and F(xa) = -sign(xa) T(|xa|) (toward the centre,
    odd, C1 inside: F'(0) is even).  The two outer regions (|xa| > 0.029 m) have F = 0.
    """
    if _REGIONS:
        return _REGIONS
    from numpy.polynomial import Polynomial as Poly

    from .thesis_data import load_table
    tab = load_table("dc_force")
    x, T = tab["x_a_m"], tab["force_N"]
    if x[0] != 0.0 or abs(x[-1] - DC_EDGE) > 1e-15:
        raise ValueError("Table 4.1 must run from xa = 0 to 0.029 m")
    m = _pchip_slopes(x, T)
    pos = []                                  # T on [x_k, x_k+1] in s = |xa| - x_k
    for k in range(x.size - 1):
        h, dlt = x[k + 1] - x[k], (T[k + 1] - T[k]) / (x[k + 1] - x[k])
        pos.append(Poly([T[k], m[k], (3 * dlt - 2 * m[k] - m[k + 1]) / h, (m[k] + m[k + 1] - 2 * dlt) / h**2]))
    regions = []
    for k in reversed(range(x.size - 1)):     # xa in [-x_k+1, -x_k): F = +T(|xa|) = T_k(h - s)
        h = x[k + 1] - x[k]
        regions.append((-x[k + 1], -x[k], pos[k](Poly([h, -1.0]))))
    for k in range(x.size - 1):               # xa in [x_k, x_k+1): F = -T_k(s)
        regions.append((x[k], x[k + 1], -pos[k]))
    # potential at each lower bound, integrating F outward from U(0) = 0 (U is even)
    n0 = x.size - 1                           # index of the region starting at xa = 0
    u = [0.0] * len(regions)
    for j in range(n0 + 1, len(regions)):
        lo, hi, F = regions[j - 1]
        u[j] = u[j - 1] - F.integ()(hi - lo)
    for j in range(n0 - 1, -1, -1):
        lo, hi, F = regions[j]
        u[j] = u[j + 1] + F.integ()(hi - lo)   # U(lo_j) = U(hi_j) + integral of F over the region
    out = [(-_DC_FAR, -DC_EDGE, 0.0, 0.0, 0.0, 0.0, u[0])]
    for (lo, hi, F), u0 in zip(regions, u):
        c = np.zeros(4)
        c[:F.coef.size] = F.coef
        out.append((float(lo), float(hi), *map(float, c), float(u0)))
    lo, hi, F = regions[-1]
    out.append((DC_EDGE, _DC_FAR, 0.0, 0.0, 0.0, 0.0, float(u[-1] - F.integ()(hi - lo))))
    _REGIONS[:] = out
    return out


_REGION_FLAGS = ("dc_region", "dc_lo", "dc_hi", "dc_c0", "dc_c1", "dc_c2", "dc_c3", "dc_u0")
#: overlap [m] of neighbouring regions of the measured law: a region is left at dc_lo - DC_OVERLAP
#: or dc_hi + DC_OVERLAP (flags dc_glo, dc_ghi).  Entered exactly on a knot, the leaving surface
#: would start at 0, and heyoka misses a crossing that begins on its own zero (a bar entering a
#: region at its apex fell back through it with the region's cubic).  The cubic over the overlap
#: is C1-continuous with the neighbour's (an error ~|c2| 1e-24 N); at the 29 mm edge the force
#: jumps there 1e-12 m late (an energy error < 4e-12 J).
DC_OVERLAP = 1e-12


def _region_flags(k: int) -> dict:
    out = dict(zip(_REGION_FLAGS, (float(k),) + measured_dc_regions()[k]))
    out["dc_glo"], out["dc_ghi"] = out["dc_lo"] - DC_OVERLAP, out["dc_hi"] + DC_OVERLAP
    return out


def dc_region_flags(o: ModelOptions, y, params) -> dict:
    """The measured law's region flags consistent with the state ``y`` (empty for other laws).

    Applied at the start of every run and map step by :func:`start_flags`.  A bar exactly on a
    knot and moving down takes the region below (its crossing of the knot would not be
    detected from zero).
    """
    if not (o.dc and o.dc_law == "measured"):
        return {}
    y = np.asarray(y, dtype=float)
    r, rdot = (y[0], y[1]) if o.dof == 1 else (y[0] - y[2], y[1] - y[3])
    xa = r - params["d_dc"]
    bounds = [reg[0] for reg in measured_dc_regions()]
    k = int(np.searchsorted(bounds, xa, side="right")) - 1
    if k > 0 and xa == bounds[k] and rdot < 0:
        k -= 1
    return _region_flags(max(k, 0))


def _dc_law(o: ModelOptions, s, xa):
    """The DC pull of the law ``o.dc_law`` at xa = r - d_dc [m]: (force [N], its potential U [J]), dc_scale applied."""
    # products, not xa**3 (heyoka's general pow recurrence divides by xa: NaN at xa = 0)
    if o.dc_law == "measured":
        # the region's cubic in the local coordinate sl = xa - dc_lo [m]; its coefficients are
        # flags set at every region change (guards "dc_down"/"dc_up", dc_region_flags at a start)
        sl = xa - s.dc_lo
        cubic = (((sl * s.dc_c3 + s.dc_c2) * sl + s.dc_c1) * sl + s.dc_c0) * s.dc_scale
        # U = dc_u0 - integral of F from dc_lo: continuous across every knot and the edge
        U = (s.dc_u0 - (((sl * s.dc_c3 * 0.25 + s.dc_c2 / 3.0) * sl + s.dc_c1 * 0.5) * sl + s.dc_c0) * sl) \
            * s.dc_scale
    elif o.dc_law == "catalogue":
        # -F_dc_sat/2 [tanh(a) + tanh(b)], a, b = (xa -+ u_dc)/(2 s_dc); U = F_dc_sat s_dc [ln cosh a
        # + ln cosh b] (dU/dxa = -F), offset so that U(0) = 0 (energy output only)
        a, b = (xa - s.u_dc) / s.s_dc * 0.5, (xa + s.u_dc) / s.s_dc * 0.5
        cubic = (hy.tanh(a) + hy.tanh(b)) * s.F_dc_sat * (-0.5) * s.dc_scale
        U0 = hy.log(hy.cosh(s.u_dc / s.s_dc * 0.5)) * 2.0
        U = (hy.log(hy.cosh(a)) + hy.log(hy.cosh(b)) - U0) * s.F_dc_sat * s.s_dc * s.dc_scale
    elif o.dc_law == "fit":
        xa2 = xa**2
        # dc_scale * (-a3 xa^3 - a2 xa^2 + a1 xa)  (eq 4.7 without its weight offset)
        cubic = (s.a1 - xa * s.a2 - xa2 * s.a3) * xa * s.dc_scale
        U = (xa2 * s.a3 * 0.25 + xa * s.a2 / 3.0 - s.a1 * 0.5) * xa2 * s.dc_scale
    else:   # "listing" and "dynamics-script" (the same form, C.14's coefficients and d_dc = 0)
        xa2 = xa**2
        # dc_scale * (-a3 xa^3 + a2 xa^2 - a1 xa)  (listing C.9 without its weight offset)
        cubic = (xa * s.a2 - xa2 * s.a3 - s.a1) * xa * s.dc_scale
        U = (xa2 * s.a3 * 0.25 - xa * s.a2 / 3.0 + s.a1 * 0.5) * xa2 * s.dc_scale
    return cubic, U


def _accelerations(o: ModelOptions, s, f: dict) -> None:
    """The accelerations from the forces in ``f`` (added to it): the bar's and, for 2 DOF, the rig's
    under the soil's law [m s-2]."""
    if o.dof == 2:
        # stuck_bar = 1: the bar rides the stop, bar and rig move as one body of mass m1 + m2
        # under the static force and the soil; stuck_bar = 0 gives the free equations exactly.
        sb = s.stuck_bar if o.stop else 0.0
        free, mass = 1.0 - sb, s.m2 + sb * s.m1
        F_mag = f["F_dc"] + f["F_ac"] + f["F_air"] if o.air_damping else f["F_dc"] + f["F_ac"]
        N_rig_free = -free * F_mag - s.F_static  # without the contact force
        f["N_rig"] = -free * f["F_bar"] - s.F_static  # net force on the rig (bar+rig if stuck) before the soil
        if o.soil != "viscous":     # the resistance (COMPACTION: growing with depth)
            R0, depth = (s.soil_friction, -s.x2) if o.soil == "coulomb" else (s.P_max, -s.d)
            f["R_soil"] = R0 + depth / s.soil_depth_scale * R0 if o.compaction else R0
        if o.soil in ("viscous", "drift"):
            if o.soil == "viscous":
                f["F_soil"] = -s.soil_c * s.v2
            else:
                # drift (SOIL_LAWS): delta = d - x2 >= 0 compresses the element (the soil lies toward -x);
                # elastic: F = k_s delta - c_s v2 (slider still); progression: F held at P_max
                f["soil_delta"] = s.d - s.x2
                f["F_element"] = f["soil_delta"] * s.k_s - s.v2 * s.c_s
                f["F_soil"] = f["F_element"] * s.soil_el + f["R_soil"] * s.soil_pl
                # the slider's rate in progression: k_s delta + c_s (dd/dt - v2) = P_max
                f["d_rate"] = (s.v2 + (f["R_soil"] - f["soil_delta"] * s.k_s) / s.c_s) * s.soil_pl
            f["a2"] = (f["N_rig"] + f["F_soil"]) / mass
            a2_free = (N_rig_free + f["F_soil"]) / mass
        else:
            f["a2"] = (1.0 - s.stuck) * (f["N_rig"] - s.slip_dir * f["R_soil"]) / mass
            a2_free = (1.0 - s.stuck) * (N_rig_free - s.slip_dir * f["R_soil"]) / mass
        f["a1"] = free * f["F_bar"] / s.m1 + sb * f["a2"]
        # m1 x the bar's acceleration relative to the rig without contact force (> 0: pulls it off the stop)
        f["N_bar"] = F_mag - s.m1 * a2_free
        f["rddot"] = f["a1"] - f["a2"]
    else:
        # listing C.9 and eq 4.7: F_dc carries +m g, which cancels the weight; the measured law
        # (Table 4.1) has no weight offset: the weight acts as it is
        cancels = o.dc and o.dc_law not in ("measured", "catalogue")
        if cancels:
            f["N_bar"] = f["F_dc"] + f["F_ac"]                   # net force without the stop
        else:
            f["N_bar"] = (f["F_dc"] + f["F_ac"] if o.dc else f["F_ac"]) - s.m * s.g
        if o.air_damping:
            f["N_bar"] = f["N_bar"] + f["F_air"]
        if o.rear_stop:
            f["N_bar"] = f["N_bar"] + f["F_rear"]
        acc = (f["N_bar"] + f["F_c"]) / s.m
        f["a1"] = acc - acc * s.stuck_bar if o.stop else acc        # (1 - stuck_bar) * acc
        f["rddot"] = f["a1"]


def _forces(o: ModelOptions, s):
    """Symbolic forces and geometry shared by the rhs, guards and outputs.

    Written for heyoka's Taylor recurrences: a parameter only ever multiplies, divides or offsets
    an expression of the state or time (``(x - d) * a2``, ``acc * stuck_bar``), never another
    parameter.  A parameter-only subexpression (``m*g``, ``1 - stuck_bar``, ``-a3``, ``2*pi*f``)
    is a separate Taylor variable, and its product with a state expression costs a full
    convolution at every order instead of one multiplication (about 1.6x the step cost here).
    """
    f = {}
    if o.dof == 1:
        r, rdot = s.x, s.v
    else:
        r, rdot = s.x1 - s.x2, s.v1 - s.v2
    f["r"], f["rdot"] = r, rdot
    zero = hy.expression(0.0)
    P = s.P if o.ac else None
    if o.dc:
        xa = r - s.d_dc
        f["xa"] = xa
        cubic, U = _dc_law(o, s, xa)
        if o.dc_delay:          # the coil's current j_dc lags the gate (1 - P); force ~ current^2
            f["F_dc"], f["U_dc"] = cubic * s.j_dc**2, U * s.j_dc**2
        else:
            f["F_dc"] = cubic - cubic * P if o.relay == "antiphase" else cubic       # gate (1 - P)
            f["U_dc"] = U - U * P if o.relay == "antiphase" else U
    else:
        f["F_dc"] = zero
    if o.ac:
        q = (r + s.d_ac) / s.B                             # xb / B
        gA = hy.exp(-2.0 * q**2) * s.A / s.B               # (A / B) exp(-2 (xb/B)^2)
        c0 = 1.0 / math.sqrt(math.pi / 2)
        f["L"] = gA * c0 + s.L0
        f["dL"] = gA * q / s.B * (-4.0 * c0)
        f["ddL"] = gA * (1.0 - 4.0 * q**2) / s.B / s.B * (-4.0 * c0)
        sign = 1.0 if o.ac_sign == "physical" else -1.0
        f["F_ac"] = f["dL"] * s.i**2 * (0.5 * sign)
        phase = s.t * s.f_mains * (2.0 * math.pi)
        f["u"] = hy.sin(phase) * s.V * P
        f["du"] = hy.cos(phase) * s.V * s.f_mains * P * (2.0 * math.pi)
    else:
        f["F_ac"] = zero
    if o.stop:
        f["F_c"] = -((r - s.e) * s.k + rdot * s.c) * s.contact
    else:
        f["F_c"] = zero
    f["F_air"] = -rdot * s.c_air if o.air_damping else zero        # free-flight damping (ELEMENTS)
    if o.rear_stop:         # the housing: the stop's contact law beyond r = e_rear (flag "rear")
        f["F_rear"] = -((r - s.e_rear) * s.k + rdot * s.c) * s.rear
    f["F_bar"] = f["F_dc"] + f["F_ac"] + f["F_c"]  # magnetic + contact force on the bar
    if o.air_damping:
        f["F_bar"] = f["F_bar"] + f["F_air"]
    if o.rear_stop:
        f["F_bar"] = f["F_bar"] + f["F_rear"]
    _accelerations(o, s, f)
    return f


def _rhs(o: ModelOptions, s):
    f = _forces(o, s)
    if o.dof == 1:
        out = [s.v - s.v * s.stuck_bar if o.stop else s.v, f["a1"]]
    else:
        out = [s.v1, f["a1"], s.v2, f["a2"]]
    if o.ac:
        L, dL, ddL, rdot, i = f["L"], f["dL"], f["ddL"], f["rdot"], s.i
        if o.circuit == "thesis":  # eq 4.16
            out += [s.z, (f["du"] - (dL * rdot * 2.0 + s.R) * s.z
                          - ((ddL * rdot**2 + dL * f["rddot"]) * i + i / s.C)) / L]
        else:  # d(L i)/dt + R i + q/C = u
            out += [i, (f["u"] - i * s.R - s.q / s.C - dL * rdot * i) / L]
    if o.dc_delay:
        out += [(1.0 - s.P - s.j_dc) / s.tau_dc]      # dj/dt = (gate - j)/tau, gate 1 - P (DC on, AC off)
    if o.drift:
        out += [f["d_rate"]]
    if o.energy and o.drift:
        # damper power c_s (d(delta)/dt)^2: elastic d(delta)/dt = -v2; progression (P_max - k_s delta)/c_s
        rel = (f["R_soil"] - f["soil_delta"] * s.k_s) / s.c_s
        out += [s.v2 ** 2 * s.c_s * s.soil_el + rel ** 2 * s.c_s * s.soil_pl,
                -f["d_rate"] * f["R_soil"]]
    elif o.energy:
        out += [f["u"] * s.i if o.ac else hy.expression(0.0),
                s.i**2 * s.R if o.ac else hy.expression(0.0),
                f["rdot"]**2 * s.c * s.contact if o.stop else hy.expression(0.0)]
    return out


def _guards(o: ModelOptions, s, owner: dict):
    """The model's guards; ``owner["system"]`` is the system they belong to (set once it is
    built; the "stick" transition evaluates the system's N_bar)."""
    f = _forces(o, s)
    r, rdot = f["r"], f["rdot"]
    gs = []
    if o.stop:
        # while stuck the bar sits at r = e exactly: an identically zero surface stops heyoka at
        # every step (both its guards are inactive then), so it is lifted by STUCK_LIFT [m]
        gap = r - s.e + s.stuck_bar * STUCK_LIFT
        gs += [Guard("contact", gap, -1, when={"contact": 0, "stuck_bar": 0}, then={"contact": 1}, role="impact"),
               Guard("lowest", rdot, +1, when={"contact": 0, "stuck_bar": 0}, role="flight_minimum"),
               Guard("deepest", rdot, +1, when={"contact": 1}, role="deepest"),
               Guard("release", gap, +1, when={"contact": 1}, then={"contact": 0}, role="release"),
               # the contact oscillation dies out: the bar sticks (a transition of its own, so
               # that no engine's choice of observed points changes where a bar comes to rest)
               Guard("stick", _at_rest_surface(o, s, f), -1, when={"contact": 1, "stuck_bar": 0},
                     then=_stick_if_pressed(owner, o), role="stick")]
        # Escape and unstick share one surface (every event costs ~5 % of a step, see
        # docs/model.md "Guards"), chosen by the stuck_bar flag:
        # - free bar: positive between STOP_ESCAPE into the stop and ESCAPE_MARGIN beyond the
        #   DC centre (both ends of the domain), crossed downward when the bar leaves it;
        # - stuck bar (it rides the stop, so it cannot escape): the force pulling it off the
        #   stop over k [m], crossed upward when that force exceeds unstick_force.
        # heyoka sizes its steps on the event functions too, hence metres, not newtons.
        far = (r - s.d_dc if o.dc else r) - ESCAPE_MARGIN
        escape = (r - s.e + STOP_ESCAPE) * -far
        surface = escape - escape * s.stuck_bar + (f["N_bar"] - o.unstick_force) / s.k * s.stuck_bar
        gs += [Guard("escape", surface, -1, when={"stuck_bar": 0}, then={"escaped": 1}, role="escape"),
               Guard("unstick", surface, +1, when={"stuck_bar": 1}, then={"stuck_bar": 0}, role="unstick")]
    else:
        centre = -s.d_ac if o.ac else 0.0
        gs += [Guard("escape", (r - centre) ** 2 - (0.2) ** 2, +1, then={"escaped": 1}, role="escape")]
    if o.rear_stop:     # the housing (role "other": not the impacts of the stop)
        rear = r - s.e_rear
        gs += [Guard("rear_contact", rear, +1, when={"rear": 0}, then={"rear": 1}, role="other"),
               Guard("rear_release", rear, -1, when={"rear": 1}, then={"rear": 0}, role="other")]
    if o.dc and o.dc_law == "measured":
        # region changes of the measured DC law: two surfaces whose bounds are flags (each
        # heyoka event costs ~5 % of a step), one guard per region on each; xa in metres
        n = len(measured_dc_regions())
        xa = f["xa"]
        gs += [Guard("dc_down", xa - s.dc_glo, -1, when={"dc_region": float(k)}, then=_region_flags(k - 1),
                     role="other")
               for k in range(1, n)]
        gs += [Guard("dc_up", xa - s.dc_ghi, +1, when={"dc_region": float(k)}, then=_region_flags(k + 1),
                     role="other")
               for k in range(n - 1)]
    if o.dof == 2 and o.soil == "coulomb":
        iv2 = 3  # index of v2 in the state

        def zero_v2(y, params):
            y = y.copy()
            y[iv2] = 0.0
            return y

        # force surfaces over k (metres), as "unstick": they enter heyoka's step-size norm
        per_k = (lambda F: F / s.k) if o.stop else (lambda F: F)
        gs += [Guard("rig_stop", s.v2, 0, when={"stuck": 0}, then=None, reset=zero_v2, role="stick"),
               Guard("rig_slip_back", per_k(f["N_rig"] - f["R_soil"]), +1, when={"stuck": 1},
                     then={"stuck": 0, "slip_dir": 1.0}, role="slip"),
               Guard("rig_slip_fwd", per_k(f["N_rig"] + f["R_soil"]), -1, when={"stuck": 1},
                     then={"stuck": 0, "slip_dir": -1.0}, role="slip")]
    if o.drift:
        # touch/leave the soil front (delta = d - x2 = 0) and yield/hold (element force = P_max),
        # each one surface [m]; in progression the yield surface is -c_s dd/dt / k_s (>= 0)
        touch = f["soil_delta"]
        yield_ = (f["F_element"] - f["R_soil"]) / s.k_s
        gs += [Guard("soil_touch", touch, +1, when={"soil_el": 0, "soil_pl": 0}, then=_soil_touch(o),
                     role="other"),
               Guard("soil_leave", touch, -1, when={"soil_el": 1}, then={"soil_el": 0}, role="other"),
               Guard("soil_yield", yield_, +1, when={"soil_el": 1}, then={"soil_el": 0, "soil_pl": 1},
                     role="other"),
               Guard("soil_hold", yield_, -1, when={"soil_pl": 1}, then={"soil_el": 1, "soil_pl": 0},
                     role="other")]
    return gs


_IX2, _IV2 = 2, 3   # indices of the rig's position and velocity in a 2-DOF state


def soil_flags(o: ModelOptions, y, params) -> dict:
    """The drift soil's mode for a state ``y`` (empty for other laws): in contact with the soil
    front when compressed (delta = d - x2 > 0) or on it and moving into it; then progressing when
    the element force k_s delta - c_s v2 exceeds P_max, else elastic.  A rig at rest exactly on
    the front is taken as touching it (the net force is not known here; an elastic element at
    zero compression exerts no force, so the motion is the same)."""
    if not o.drift:
        return {}
    y = np.asarray(y, dtype=float)
    x2, v2, d = y[_IX2], y[_IV2], y[o.state_names().index("d")]
    delta = d - x2
    if delta < 0 or (delta == 0 and v2 > 0):
        return {"soil_el": 0.0, "soil_pl": 0.0}
    if delta * params["k_s"] - v2 * params["c_s"] > soil_resistance(o, y, params):
        return {"soil_el": 0.0, "soil_pl": 1.0}
    return {"soil_el": 1.0, "soil_pl": 0.0}


def soil_resistance(o: ModelOptions, y, params) -> float:
    """The soil's resistance [N] in state ``y``: the friction limit (coulomb) or the slider's
    threshold (drift), grown with depth under the compaction option (:data:`COMPACTION`)."""
    R0 = params["soil_friction"] if o.soil == "coulomb" else params["P_max"]
    if not o.compaction:
        return R0
    depth = -y[_IX2] if o.soil == "coulomb" else -y[o.state_names().index("d")]
    return R0 + depth / params["soil_depth_scale"] * R0


def _soil_touch(o: ModelOptions):
    """Contact with the soil front begins: elastic, or at once progression when the element's
    damper alone (-c_s v2 at zero compression) exceeds the threshold."""
    def then(t, y, flags, params):
        pl = -y[_IV2] * params["c_s"] > soil_resistance(o, y, params)
        return {"soil_el": 0.0, "soil_pl": 1.0} if pl else {"soil_el": 1.0}
    return then


def _outputs(o: ModelOptions, s):
    f = _forces(o, s)
    out = {k: f[k] for k in ("F_dc", "F_ac", "F_c", "r", "rdot") if k in f}
    if o.dof == 2:
        out["N_rig"] = f["N_rig"]
        if o.drift:
            out.update({k: f[k] for k in ("F_soil", "F_element", "soil_delta", "d_rate")})
        if "N_bar" in f:
            out["N_bar"] = f["N_bar"]
    else:
        out["N_bar"] = f["N_bar"]
    if o.energy and o.dof == 1:
        E = 0.5 * s.m * s.v**2 + 0.5 * s.contact * s.k * (s.x - s.e) ** 2 if o.stop else 0.5 * s.m * s.v**2
        if o.dc:
            E = E + f["U_dc"]
        if not o.dc or o.dc_law in ("measured", "catalogue"):   # the weight's potential (cancelled by the cubics' + m g)
            E = E + s.m * s.g * s.x
        if o.ac:
            E = E + 0.5 * f["L"] * s.i**2 + 0.5 * s.q**2 / s.C
        out["E_mech_el"] = E
    return out


def _settle_coulomb(owner: dict, o: ModelOptions):
    """Stick/slip consistency after any transition (relay switch, contact, rig stop);
    ``owner["system"]``: the system (set once it is built)."""

    def settle(t, y, flags, params):
        N = float(owner["system"].evaluate(["N_rig"], y, params, flags, t)[0])
        Ff = soil_resistance(o, y, params)
        v2 = y[3]
        if flags["stuck"] == 1:
            if abs(N) > Ff:
                return {"stuck": 0, "slip_dir": math.copysign(1.0, N)}
            return None
        if abs(v2) <= 1e-12:
            if abs(N) <= Ff:
                return {"stuck": 1}
            return {"slip_dir": math.copysign(1.0, N)}
        return {"slip_dir": math.copysign(1.0, v2)} if math.copysign(1.0, v2) != flags["slip_dir"] else None

    return settle


def _gap(o: ModelOptions):
    """Signed distance to the stop and its rate, (r - e, dr/dt), from a state array."""
    if o.dof == 1:
        return lambda y, p, t=0.0: (y[0] - p.get("e", 0.0), y[1])
    return lambda y, p, t=0.0: (y[0] - y[2] - p.get("e", 0.0), y[1] - y[3])


def _stick_projection(o: ModelOptions):
    """The stick transition's state projection as expressions (for exact Jacobians): 1-DOF
    x = e, v = 0; 2-DOF r = e with bar and rig at their common momentum velocity (the rig's
    own velocity if the soil holds it).  The circuit is untouched."""

    def projection(s, flags):
        rows = list(s.state_vars)
        if o.dof == 1:
            rows[0], rows[1] = s.e, hy.expression(0.0)
        else:
            v = s.v2 if flags.get("stuck") == 1 else (s.v1 * s.m1 + s.v2 * s.m2) / (s.m1 + s.m2)
            rows[0], rows[1], rows[3] = s.x2 + s.e, v, v
        return rows

    return projection


def _reduced(o: ModelOptions, masses, N):
    """(mass, force on it) of the motion relative to the stop, from ``masses`` (the bar's m, or
    m1 and m2) and the net non-contact force on the bar N_bar: 1-DOF (m, N_bar); 2-DOF the
    reduced mass mu = m1 m2 / (m1 + m2) and N_bar mu / m1.  Numbers or heyoka expressions."""
    if o.dof == 1:
        return masses[0], N
    m1, m2 = masses
    mu = m1 * m2 / (m1 + m2)
    return mu, N * mu / m1


def _on_the_stop(o: ModelOptions, y, params, flags):
    """The stuck bar's state: x = e, v = 0 (1-DOF); 2-DOF the bar at x2 + e, bar and rig at
    their common momentum velocity (the rig's velocity if the soil holds the rig)."""
    y = np.array(y, dtype=float)
    e = params["e"]
    if o.dof == 1:
        y[0], y[1] = e, 0.0
    else:
        m1, m2 = params["m1"], params["m2"]
        v_common = y[3] if flags.get("stuck") == 1 else (m1 * y[1] + m2 * y[3]) / (m1 + m2)
        y[0], y[1], y[3] = y[2] + e, v_common, v_common
    return y


def _at_rest_surface(o: ModelOptions, s, f):
    """[m^2] (m/k) rdot^2 + (r - r_s)^2 - (m/k) stick_speed^2: negative while the contact
    oscillation about its static point r_s = e + N/k has a speed amplitude
    sqrt(rdot^2 + k/m (r - r_s)^2) below ``stick_speed`` (m, N as :func:`_reduced`)."""
    m, N = _reduced(o, (s.m,) if o.dof == 1 else (s.m1, s.m2), f["N_bar"])
    y = f["r"] - s.e - N / s.k
    # squares (x**2), not products: heyoka's square series costs half a product's (measured: the
    # surface adds 3 % to a 1-DOF sweep's CPU this way, 6.5 % with products)
    return m / s.k * (f["rdot"] ** 2 - o.stick_speed * o.stick_speed) + y ** 2


def _stick_if_pressed(owner: dict, o: ModelOptions):
    """The "stick" guard's transition: the contact oscillation's speed amplitude fell to
    ``stick_speed``; a bar pressed on the stop (N <= 0) sticks on it (:func:`_on_the_stop`),
    one pulled off it stays in contact (it is about to leave).  ``owner["system"]``: the system."""

    def then(t, y, flags, params):
        if float(owner["system"].evaluate(["N_bar"], y, params, flags, t)[0]) <= 0.0:
            return {"contact": 0.0, "stuck_bar": 1.0}, _on_the_stop(o, y, params, flags)
        return None

    return then


def _settle_stick(owner: dict, o: ModelOptions):
    """End chattering: the bar sticks on the stop (x = e, v = 0) while pressed on it, when
    a contact begins slower than ``stick_speed`` (the Zeno cascade of ever shorter bounces), or
    when, in contact at a relay switch, the oscillation about the static point x_s = e + N/k has
    a speed amplitude sqrt(v^2 + k/m (x - x_s)^2) below ``stick_speed``.  Between transitions
    the "stick" guard acts where that amplitude falls to ``stick_speed`` (a bar settling on the
    Kelvin-Voigt stop, whose turning points would otherwise fire for ever at noise level).

    The projection moves the bar by its static penetration |N|/k (micrometres here).
    2-DOF: x is r = x1 - x2, m and N as :func:`_reduced`; the state as :func:`_on_the_stop`.
    ``owner["system"]``: the system (set once it is built).
    """
    gap = _gap(o)

    def settle(t, y, flags, params):
        system = owner["system"]
        if flags.get("contact") == 1 and flags.get("stuck_bar") == 0:
            x, v = gap(y, params)
            e = params["e"]
            x = x + e
            if abs(v) < o.stick_speed:
                m, N = _reduced(o, (params["m"],) if o.dof == 1 else (params["m1"], params["m2"]),
                                float(system.evaluate(["N_bar"], y, params, flags, t)[0]))
                x_s = e + N / params["k"]
                amp = abs(v) if abs(x - e) < 1e-12 else math.hypot(v, math.sqrt(params["k"] / m) * (x - x_s))
                if N <= 0.0 and amp < o.stick_speed:
                    return {"contact": 0.0, "stuck_bar": 1.0}, _on_the_stop(o, y, params, flags)
        if flags.get("stuck_bar") == 1:
            N = float(system.evaluate(["N_bar"], y, params, flags, t)[0])
            if N > o.unstick_force:
                return {"stuck_bar": 0.0}
        return None

    return settle


def _chain(first, second):
    """Two settle functions in turn: the second sees the first's flags and projected state."""

    def settle(t, y, flags, params):
        out = first(t, y, flags, params)
        projected = isinstance(out, tuple)
        new, y = out if projected else (out or {}, y)
        more = second(t, y, dict(flags, **new), params)
        if isinstance(more, tuple):
            (more, y), projected = more, True
        new = dict(new, **(more or {}))
        return (new, y) if projected else (new or None)

    return settle


def start_flags(system: HybridSystem, o: ModelOptions, y, params, flags, given=()) -> dict:
    """Flags that follow from the state at the start of a run: THE one rule, installed as
    ``system.mode_rule`` and applied by :func:`maps.transitions.start_flags` at every run start of
    every engine (simulate, run_scene, StroboscopicMap step/orbit/orbits, the batch lanes).

    - the measured DC law's region flags (:func:`dc_region_flags`), always;
    - the drift soil's mode (:func:`soil_flags`), always;
    - the stop, unless the caller gave ``stuck_bar`` (``given``): a bar inside the stop, or exactly
      on it and moving into it, or at rest on it while the net non-contact force presses it on
      (N_bar <= 0), starts in contact (then ``settle`` may stick it), even where the caller inferred
      contact = 0 from the gap alone (StroboscopicMap).  A contact guard cannot fire from a start on
      its own zero, so without this a bar resting on the stop under its weight fell through it.

    """
    y = np.asarray(y, dtype=float)
    out = dc_region_flags(o, y, params)
    out.update(soil_flags(o, y, params))
    if o.rear_stop:     # in the housing's contact where the bar starts beyond e_rear
        r = y[0] if o.dof == 1 else y[0] - y[2]
        out["rear"] = 1.0 if r > params["e_rear"] else 0.0
    if o.stop and "stuck_bar" not in given and flags.get("contact") != 1.0:
        gap, rate = system.gap(y, params)
        if gap < 0 or (gap == 0 and rate < 0):
            out["contact"] = 1.0
        elif gap == 0 and rate == 0:
            fl = dict(flags, **out)
            if float(system.evaluate(["N_bar"], y, params, fl)[0]) <= 0.0:
                out["contact"] = 1.0
    return out


_SYSTEMS: dict = {}


def build_system(options: ModelOptions | None = None, **kw) -> HybridSystem:
    """The hybrid system for one set of structural options (built once, then cached)."""
    o = options if options is not None else ModelOptions(**kw)
    if o.key() in _SYSTEMS:
        return _SYSTEMS[o.key()]
    flags = {"P": 1.0} if o.ac else {}
    if o.stop:
        flags["contact"] = 0.0
    if o.stop:
        flags["stuck_bar"] = 0.0
    flags["escaped"] = 0.0
    if o.rear_stop:
        flags["rear"] = 0.0
    if o.dof == 2 and o.soil == "coulomb":
        flags.update(stuck=0.0, slip_dir=1.0)
    if o.drift:     # drift soil: elastic contact / progression (both 0: clear of the soil front)
        flags.update(soil_el=0.0, soil_pl=0.0)
    if o.dc and o.dc_law == "measured":      # defaults: the region of a bar on the stop; a run's
        flags.update(_region_flags(0))       # start takes them from its state (dc_region_flags)
    switches = [PeriodicSwitch("P", "relay_hz")] if o.relay != "none" else []
    params = [PARAMETERS[n] for n in o.parameter_names()]
    owner: dict = {}     # the system, for the rules below that evaluate its forces
    settle = _settle_coulomb(owner, o) if o.dof == 2 and o.soil == "coulomb" else None
    stick_decl = {}
    if o.stop:
        stick = _settle_stick(owner, o)
        settle = stick if settle is None else _chain(stick, settle)
        stick_decl = dict(settle_events={"stuck_bar": {1.0: "stick", 0.0: "unstick"}},  # logged as events
                          projections={"stick": _stick_projection(o)},                    # their Jacobians
                          mode_projections={("stuck_bar", 1.0): "stick"})                  # the stuck bar's set
        if settle is stick:   # sticking acts only stuck, or in contact below stick_speed
            # (Coulomb slip: always); the gap rate as _settle_stick reads it
            gap, speed = _gap(o), o.stick_speed
            stick_decl["settle_if"] = lambda flags, y, params: flags["stuck_bar"] == 1 or (
                flags["contact"] == 1 and abs(gap(y, params)[1]) < speed)
    # bar and rig shifted together: the same motion (no force depends on x1 + x2; compaction's
    # resistance depends on the depth: no such symmetry)
    translation = {"x1": 1.0, "x2": 1.0, **({"d": 1.0} if o.drift else {})} \
        if o.dof == 2 and not o.compaction else None
    system = HybridSystem(
        name="electro-vibro-impact", states=o.state_list(), parameters=params,
        flags=flags, rhs=lambda s: _rhs(o, s), guards=lambda s: _guards(o, s, owner),
        switches=switches, outputs=lambda s: _outputs(o, s), structure=o.key(),
        halt_flags=("escaped",), gap=_gap(o), settle=settle,
        mode_rule=lambda y, params, flags, given=(): start_flags(owner["system"], o, y, params, flags, given),
        translation=translation, forcing=("f_mains",) if o.ac else None, options=o,
        mechanical=[st.name for st in o.state_list() if st.name not in ("i", "z", "q", "j_dc")], **stick_decl)
    owner["system"] = system
    _SYSTEMS[o.key()] = system
    return system
