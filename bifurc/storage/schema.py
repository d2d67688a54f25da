"""One table of stored variables: name, dims, dtype, fill value, units, long_name (CF attributes).

Dimension names in a row are literal except ``PARAM``, which stands for the swept
parameter's dimension (named after the parameter, e.g. ``relay_hz``).  The sweep
dataset (:mod:`bifurc.sweeps.dataset`) is assembled from :data:`SWEEP`, :data:`SWEEP_COORDS` and
:data:`GRAZING`; :data:`HISTORY` describes the time-history dataset of
:func:`maps.simulate.simulate` (which still writes its own attributes: ``maps`` never
imports ``bifurc``; the test suite checks the two agree).  :func:`param_attrs` is the one
writer of the ``param_<name>`` attributes.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..labels.codes import ClassCode, Status, flag_attrs

#: placeholder for the swept parameter's dimension
PARAM = "<param>"

#: an orbit grazes when its smallest clearance is below GRAZING_GAP [m] without contact,
#: or its slowest impact is below GRAZING_SPEED [m/s] (stored with every grid dataset)
GRAZING_GAP = 1e-6
GRAZING_SPEED = 1e-3


def grazing_flag(min_clearance, min_impact_speed):
    """1 where an orbit grazes: slowest impact < GRAZING_SPEED [m/s] or clearance in [0, GRAZING_GAP) [m]."""
    return (min_impact_speed < GRAZING_SPEED) | ((min_clearance >= 0) & (min_clearance < GRAZING_GAP))


@dataclass(frozen=True)
class Variable:
    """One stored variable: its dims (``PARAM``: the swept parameter), dtype, fill and CF attributes."""

    name: str
    dims: tuple
    dtype: type
    fill: object
    units: str
    long_name: str
    extra: tuple = ()        # further attributes, e.g. flag_values / flag_meanings, as (key, value) pairs

    def dims_for(self, param: str) -> tuple:
        return tuple(param if d == PARAM else d for d in self.dims)

    def attrs(self, **override) -> dict:
        return {"units": self.units, "long_name": self.long_name, **dict(self.extra), **override}

    def empty(self, sizes: dict, param: str) -> np.ndarray:
        """An array of this variable filled with ``fill``, shaped by ``sizes`` {dim: length} (strings:
        an object array, so that assigned texts keep their length; see :meth:`finish`)."""
        return np.full(tuple(sizes[d] for d in self.dims_for(param)), self.fill,
                       dtype=object if self.dtype is str else self.dtype)

    def finish(self, data: np.ndarray) -> np.ndarray:
        """The filled array in its stored dtype (texts as fixed-width strings of the longest)."""
        return data.astype(str) if self.dtype is str else data


def _flags(codes) -> tuple:
    return tuple(flag_attrs(codes).items())


def _yes_no(meanings: str) -> tuple:
    """CF flags of a 0/1 variable, ``meanings`` = "<0> <1>"."""
    return (("flag_values", np.array([0, 1], np.int8)), ("flag_meanings", meanings))


V = ("branch", PARAM)
#: per-value variables of a sweep; each is also a field of :class:`bifurc.sweeps.job.ValueResult`
SWEEP = [
    Variable("class_code", V, np.int8, -1, "1", "orbit class (-1: not computed)", _flags(ClassCode)),
    Variable("period", V, np.int16, -1, "1", "period n of the orbit in relay periods (0: not periodic)"),
    Variable("candidate_period", V, np.int16, -1, "1",
             "period in relay periods of the best recurrence candidate, at which recurrence and convergence_rate are measured "
             "(0: none)"),
    Variable("impacts_per_period", V, np.int16, -1, "1", "impacts per period m (-1: not periodic)"),
    Variable("recurrence", V, float, np.nan, "1",
             "max recurrence distance at the (candidate) period / (rtol*scale + atol)"),
    Variable("convergence_rate", V, float, np.nan, "1", "fitted per-period decay factor of the recurrence distance"),
    Variable("lyapunov", V, float, np.nan, "1",
             "largest Lyapunov exponent of the map, per relay period (NaN: not computed)"),
    Variable("lyapunov_low", V, float, np.nan, "1",
             "lower end of the exponent's 95 % interval, per relay period (lyapunov_interval_method; NaN: none)"),
    Variable("lyapunov_high", V, float, np.nan, "1",
             "upper end of the exponent's 95 % interval, per relay period (NaN: none)"),
    Variable("class_reason", V, str, "", "1", "why the value is not-converged, or what decided a chaotic label whose stored exponent interval reaches "
             "the chaos threshold (empty otherwise)"),
    Variable("budget_needed", V, np.int64, 0, "1",
             "relay periods per value that the evidence of a not-converged value suggests would decide it "
             "(0: decided; see --budget)"),
    Variable("period_mechanical", V, np.int16, -1, "1",
             "period of the mechanical states alone (positions, velocities), in relay periods (0: not periodic): "
             "the thesis' period-n"),
    Variable("impacts_per_period_mechanical", V, np.int16, -1, "1",
             "impacts per mechanical period (-1: not periodic)"),
    Variable("period_difference", V, str, "", "1",
             "why the mechanical period differs from the full state's (empty: it does not)"),
    Variable("lyapunov_spread", V, float, np.nan, "1",
             "standard deviation of the exponent between its tangent trajectories, per relay period (NaN: one)"),
    Variable("periods_integrated", V, np.int64, 0, "1",
             "relay periods integrated for the value: transient, record, extensions and the exponent's copies"),
    Variable("lyapunov_trajectories", V, np.int16, 0, "1",
             "tangent trajectories on the same attractor the exponent and its interval come from (0: none)"),
    Variable("lyapunov_window", V, np.int32, -1, "1",
             "relay periods each trajectory's exponent is measured over: the window the stored interval predicts "
             "another trajectory's exponent on (-1: none)"),
    Variable("rotation_number", V, float, np.nan, "1",
             "rotation number of a quasi-periodic orbit per relay period, in [0, 1/2] (NaN: none)"),
    Variable("zero_one_k", V, float, np.nan, "1",
             "Gottwald-Melbourne 0-1 test statistic K on the window (near 0 regular, near 1 chaotic; NaN: "
             "not tested)"),
    Variable("forcing_period", V, np.int32, 0, "1",
             "period of the forcing in relay periods (0: incommensurate)"),
    Variable("impacts_per_step", V + ("step",), np.int32, -1, "1",
             "contacts in each recorded relay period (-1: not reached)"),
    Variable("min_clearance_per_step", V + ("step",), float, np.nan, "m",
             "smallest gap to the stop in each recorded relay period (< 0: penetration)"),
    Variable("min_impact_speed_per_step", V + ("step",), float, np.nan, "m s-1",
             "slowest impact in each recorded relay period (inf: no impact)"),
    Variable("min_clearance", V, float, np.nan, "m", "smallest gap to the stop over the record (< 0: penetration)"),
    Variable("min_flight_clearance", V, float, np.nan, "m",
             "lowest free-flight minimum of the gap over the record (inf: none; NaN: no period recorded)"),
    Variable("min_impact_speed", V, float, np.nan, "m s-1",
             "slowest impact over the record (inf: no impact; NaN: no period recorded, see status)"),
    Variable("impact_time", V + ("impact",), float, np.nan, "s", "contact onset time"),
    Variable("impact_velocity", V + ("impact",), float, np.nan, "m s-1",
             "gap rate at contact onset (< 0: toward the stop)"),
    Variable("impact_phase", V + ("impact",), float, np.nan, "1", "relay phase of the contact onset, in [0, 1)"),
    Variable("impact_penetration", V + ("impact",), float, np.nan, "m", "maximum penetration of the contact"),
    Variable("impact_duration", V + ("impact",), float, np.nan, "s",
             "contact duration (NaN: padding, or still in contact at the record's end)"),
    Variable("n_impacts", V, np.int32, -1, "1", "contacts in the recorded window (may exceed the impact dimension)"),
    Variable("status", V, np.int8, -1, "1", "integration status (-1: not computed)", _flags(Status)),
    Variable("failure_time", V, float, np.nan, "s", "time of escape or failure (NaN: none)"),
    Variable("n_steps", V, np.int64, 0, "1", "Taylor steps"),
    Variable("record_used", V, np.int32, -1, "1",
             "relay periods in the window the class was judged on (the stationary part of the record: first "
             "extended up to max_record to hold three forcing periods, then while undecided up to the budget; "
             "fewer after an escape); the stored samples are its first record"),
    Variable("transient_used", V, np.int64, -1, "1",
             "relay periods before the judged window: the transient, and the record's parts found not stationary"),
    Variable("run_seconds", V, float, np.nan, "s",
             "time spent computing the value (a resumed value keeps the time of the run that computed it)"),
]
#: the per-value rows of the sweep schema: one number per cell of a regime map
CELL_VARIABLES = [v for v in SWEEP if v.dims == V]
#: derived from the per-value minima (grazing_flag), not a ValueResult field
GRAZING_FLAG = Variable("grazing_flag", V, np.int8, 0, "1",
                        f"orbit grazes: slowest impact < {GRAZING_SPEED} m/s or clearance < {GRAZING_GAP} m",
                        _yes_no("clear grazing"))

SWEEP_COORDS = [
    Variable("branch", ("branch",), str, "", "1", "sweep branch"),
    Variable("sample", ("sample",), np.int64, 0, "1", "stroboscopic sample k: t = (transient_used + k) / relay_hz"),
    Variable("step", ("step",), np.int64, 0, "1", "recorded relay period"),
    Variable("impact", ("impact",), np.int64, 0, "1", "contact in the record"),
]

G = ("grazing",)
#: located grazing values (units of the swept parameter written where PARAM units are known)
GRAZING = [
    Variable("grazing", G, np.int64, 0, "1", "located grazing"),
    Variable("grazing_value", G, float, np.nan, PARAM, "{param} at which the orbit grazes the stop (bisection)"),
    Variable("grazing_xtol", G, float, np.nan, PARAM, "width of the final bisection bracket"),
    Variable("grazing_impacts_below", G, np.int32, -1, "1", "contacts in the record at the lower neighbour"),
    Variable("grazing_impacts_above", G, np.int32, -1, "1", "contacts in the record at the upper neighbour"),
    Variable("grazing_clearance", G, float, np.nan, "m",
             "clearance of the orbit at the bracket's end with fewer impacts"),
    Variable("grazing_impact_speed", G, float, np.nan, "m s-1", "slowest impact at the bracket's end with more impacts"),
    Variable("grazing_confirmed", G, np.int8, 0, "1",
             "the clearance shrank with the bracket (1: a graze; 0: the branch with fewer impacts ends otherwise, "
             "a jump)", _yes_no("jump graze")),
    Variable("grazing_branch", G, str, "", "1", "sweep branch"),
]

N, MU, IMP = ("node",), ("multiplier",), ("impact",)
#: a periodic orbit (bifurc.orbits.orbit): its strobe nodes, multipliers and impacts; states and flags per node
#: come from state_variable / flag_variable with dims ("node",)
ORBIT = [
    Variable("multiplier_abs", MU, float, np.nan, "1", "modulus of the Floquet multiplier"),
    Variable("multiplier_arg", MU, float, np.nan, "rad", "argument of the Floquet multiplier"),
    Variable("signature", N, str, "", "1",
             "roles of the events in the strobe period starting at the node, in order (comma-separated)"),
    Variable("impact_time", IMP, float, np.nan, "s", "contact onset time within the orbit's period"),
    Variable("impact_velocity", IMP, float, np.nan, "m s-1", "gap rate at contact onset (< 0: toward the stop)"),
    Variable("impact_phase", IMP, float, np.nan, "1", "phase of the contact onset in the strobe period, in [0, 1)"),
]
ORBIT_SCALARS = [
    Variable("period", (), np.int32, 0, "1", "period of the orbit in strobe periods (relay periods for relay scenes)"),
    Variable("impacts_per_period", (), np.int32, -1, "1", "contacts in one period of the orbit"),
    Variable("stable", (), np.int8, -1, "1", "all Floquet multipliers inside the unit circle", _yes_no("unstable stable")),
    Variable("newton_residual", (), float, np.nan, "1",
             "largest shooting residual at the solution, scaled per state component by the orbit's magnitude"),
    Variable("multiplier_error", (), float, np.nan, "1",
             "largest change of a multiplier when the orbit is solved again at tol/100 (NaN: not measured)"),
    Variable("min_clearance", (), float, np.nan, "m",
             "smallest distance to the stop over the orbit (< 0: penetration of a compliant stop)"),
    Variable("min_flight_clearance", (), float, np.nan, "m", "lowest free-flight minimum of the gap (inf: none)"),
    Variable("run_seconds", (), float, np.nan, "s", "time spent finding the orbit"),
]

PT, PM, SP, SPM = ("point",), ("point", "multiplier"), ("special",), ("special", "multiplier")
#: the one vocabulary of special points (branches, two-parameter curves and their codimension-2 points),
#: in the order of their codes: codimension one on a branch (the first seven), then codimension two on a
#: two-parameter curve (a fold curve's cusp, a fold meeting a period doubling, a fold meeting a grazing,
#: two curves crossing, a Neimark-Sacker pair reaching +-1: strong resonances)
SPECIAL_KINDS = ("fold", "period_doubling", "neimark_sacker", "grazing", "impact_lost", "stick_onset",
                 "signature_change", "cusp", "fold_flip", "grazing_fold", "curve_crossing", "resonance")
#: a continued branch (bifurc.orbits.branch): one row per corrected point (states and flags per node from
#: state_variable / flag_variable with dims ("point", "node"); the parameter itself is a variable
#: named after it, dims ("point",))
BRANCH = [
    Variable("branch_id", PT, np.int16, -1, "1", "branch the point belongs to (branch_labels attribute)"),
    Variable("period", PT, np.int32, 0, "1", "period of the orbit in strobe periods (relay periods for relay scenes)"),
    Variable("multiplier_abs", PM, float, np.nan, "1", "modulus of the Floquet multiplier, by modulus"),
    Variable("multiplier_arg", PM, float, np.nan, "rad", "argument of the Floquet multiplier"),
    Variable("stable", PT, np.int8, -1, "1", "all Floquet multipliers inside the unit circle", _yes_no("unstable stable")),
    Variable("impacts_per_period", PT, np.int32, -1, "1", "contacts in one period of the orbit"),
    Variable("min_clearance", PT, float, np.nan, "m",
             "smallest gap to the stop at the nodes, impacts (0) and free-flight minima of the orbit"),
    Variable("min_flight_clearance", PT, float, np.nan, "m",
             "lowest free-flight minimum of the gap (the grazing test function; inf: none)"),
    Variable("signature", PT, str, "", "1",
             "roles of the events of each strobe period of the orbit (periods separated by ';')"),
    Variable("newton_iterations", PT, np.int16, -1, "1", "corrector iterations of the point"),
    Variable("newton_residual", PT, float, np.nan, "1",
             "largest shooting residual, scaled per state component by the orbit's magnitude"),
    Variable("section_phase", PT, float, np.nan, "1",
             "phase of the strobe section: node j is the state at t = (section_k0 + j + section_phase) T"),
    Variable("section_k0", PT, np.int64, -1, "1", "strobe sample index of node 0"),
]
SPECIAL = [
    Variable("special_kind", SP, np.int8, -1, "1", "kind of special point",
             (("flag_values", np.arange(len(SPECIAL_KINDS), dtype=np.int8)),
              ("flag_meanings", " ".join(SPECIAL_KINDS)))),
    Variable("special_value", SP, float, np.nan, PARAM, "located value of {param}"),
    Variable("special_tolerance", SP, float, np.nan, PARAM,
             "uncertainty of the value (with error estimates: a bound measured by re-locating it at tol/100; "
             "else the final bracket width or Newton update; for an event not located, the bracket between the "
             "branch's last point and the next; NaN: none)"),
    Variable("special_test_function", SP, str, "", "1", "test function whose zero locates the point"),
    Variable("special_test_value", SP, float, np.nan, "1", "the test function at the located point"),
    Variable("special_point", SP, np.int32, -1, "1", "index of the branch point after which it lies"),
    Variable("special_branch", SP, np.int16, -1, "1", "branch_id of the branch it lies on"),
    Variable("special_multiplier_abs", SPM, float, np.nan, "1", "Floquet multiplier moduli at the located point"),
    Variable("special_multiplier_arg", SPM, float, np.nan, "rad", "Floquet multiplier arguments at the located point"),
    Variable("special_multiplier_error", SP, float, np.nan, "1",
             "largest change of a multiplier when the located orbit is solved again at tol/100 (NaN: not measured)"),
    Variable("special_note", SP, str, "", "1", "what was found, or why it was not located"),
]

#: the special points a two-parameter curve continues (bifurc.orbits.curves); curve_kind is coded as special_kind
CURVE_KINDS = ("fold", "period_doubling", "neimark_sacker", "grazing")
CP, C = ("curve_point",), ("curve",)
#: two-parameter curves of a branch dataset: points along ``curve_point``, one row per curve along ``curve``
CURVE_COORDS = [
    Variable("curve_point", CP, np.int64, 0, "1", "point of a curve"),
    Variable("curve", C, np.int64, 0, "1", "two-parameter curve"),
]
CURVE = [
    Variable("curve_id", CP, np.int16, -1, "1", "curve the point belongs to"),
    Variable("curve_residual", CP, float, np.nan, "1", "largest scaled residual of the defining system"),
    Variable("curve_kind", C, np.int8, -1, "1", "what the curve continues",
             (("flag_values", np.arange(len(SPECIAL_KINDS), dtype=np.int8)),
              ("flag_meanings", " ".join(SPECIAL_KINDS)))),
    Variable("curve_special", C, np.int32, -1, "1", "the special point the curve starts from"),
    Variable("curve_stop_reason", C, str, "", "1", "why the curve stopped"),
]


def curve_parameter(name: str) -> Variable:
    """The row of one of a curve's two parameters along ``curve_point`` (units: the parameter's, PARAM)."""
    return Variable(f"curve_{name}", CP, float, np.nan, PARAM, f"{name} along the curve")


def advance_variable(state, dims) -> Variable:
    """The row of a translation-invariant orbit's shift of the anchor ``state`` over one period."""
    return Variable("advance_per_period", dims, float, np.nan, state.unit,
                    f"shift of {state.name} along the system's translation over one period of the orbit")


PA, A_ = (PARAM, "attractor"), ("attractor",)
#: what became of an attractor between the previous value and this one (attractors dataset: bifurc.attractors)
ATTRACTOR_EVENTS = ("none", "appeared", "disappeared")
#: the attractor census (bifurc.attractors): one row per (value, attractor); every outcome is an attractor entry
#: (escaped, not_converged, failed, neutral, transient too), so basin_fraction sums to 1 at every value
ATTRACTOR = [
    Variable("basin_fraction", PA, float, np.nan, "1", "fraction of the fresh starts that reach the attractor"),
    Variable("basin_fraction_low", PA, float, np.nan, "1", "lower end of the 95 % Wilson interval of basin_fraction"),
    Variable("basin_fraction_high", PA, float, np.nan, "1", "upper end of the 95 % Wilson interval of basin_fraction"),
    Variable("basin_count", PA, np.int32, 0, "1", "fresh starts that reach the attractor"),
    Variable("eventual_fraction", PA, float, np.nan, "1",
             "basin_fraction with the starts still on a chaotic saddle at the budget (transient) apportioned by where "
             "the starts that left the same saddle went (bifurc.attractors.eventual)"),
    Variable("eventual_fraction_low", PA, float, np.nan, "1",
             "lower end of eventual_fraction's 95 % interval (two 97.5 % Wilson intervals: the exits' shares, the "
             "count)"),
    Variable("eventual_fraction_high", PA, float, np.nan, "1", "upper end of eventual_fraction's 95 % interval"),
    Variable("present", PA, np.int8, 0, "1", "the attractor exists at this value", _yes_no("absent present")),
    Variable("class_code", PA, np.int8, -1, "1", "class of the attractor (-1: absent)", _flags(ClassCode)),
    Variable("period", PA, np.int16, -1, "1", "period in strobe periods (0: not periodic, -1: absent)"),
    Variable("period_mechanical", PA, np.int16, -1, "1", "period of the mechanical states alone in strobe periods"),
    Variable("impacts_per_period", PA, np.int16, -1, "1", "contacts in one period (-1: not periodic or absent)"),
    Variable("impacts_per_period_mechanical", PA, np.int16, -1, "1", "contacts in one mechanical period"),
    Variable("lyapunov", PA, float, np.nan, "1",
             "largest Lyapunov exponent per strobe period (periodic: log of the largest |Floquet multiplier| / period)"),
    Variable("lyapunov_low", PA, float, np.nan, "1", "lower end of the exponent's 95 % interval (NaN: exact)"),
    Variable("lyapunov_high", PA, float, np.nan, "1", "upper end of the exponent's 95 % interval (NaN: exact)"),
    Variable("max_multiplier", PA, float, np.nan, "1", "largest |Floquet multiplier| of the polished orbit"),
    Variable("newton_residual", PA, float, np.nan, "1", "scaled shooting residual of the polished orbit"),
    Variable("lifetime", PA, float, np.nan, "1",
             "non-periodic attractor: mean lifetime on the set in strobe (relay) periods, from perturbed copies "
             "(inf: none fell onto a period; the transient entry: that of the saddle most of its starts are on; "
             "NaN: periodic or another outcome)"),
    Variable("lifetime_low", PA, float, np.nan, "1", "lower end of the lifetime's 95 % interval [strobe periods]"),
    Variable("lifetime_high", PA, float, np.nan, "1", "upper end of the lifetime's 95 % interval [strobe periods]"),
    Variable("area_rate", PA, float, np.nan, "1",
             "non-periodic attractor: sum of the two leading Lyapunov exponents per strobe period (below 0: the set "
             "contracts areas; about 0: no contraction, as on an area-preserving map's invariant tori; NaN: periodic)"),
    Variable("area_rate_low", PA, float, np.nan, "1", "lower end of the area rate's 95 % interval"),
    Variable("lifetime_verdict", PA, np.int8, 0, "1",
             "non-periodic set: its lifetime's interval against the census' horizon (attractor: surely above; "
             "long_lived: it reaches the horizon; saddle: surely below; the transient entry: that of the saddle most "
             "of its starts are on; none: periodic, not estimated, or another outcome)",
             (("flag_values", np.arange(4, dtype=np.int8)), ("flag_meanings", "none attractor long_lived saddle"))),
    Variable("area_rate_high", PA, float, np.nan, "1", "upper end of the area rate's 95 % interval"),
    Variable("cycle_period", PA, float, np.nan, "s",
             "autonomous flow (sample_step): a limit cycle's period, sample_step / the rotation number of its samples "
             "about their centre (a cycle winding once about its centre, sampled more than twice a period; NaN: "
             "not a limit cycle or not an autonomous flow)"),
    Variable("n_points", PA, np.int32, 0, "1", "stored strobe states of the attractor (its period, or recorded points)"),
    Variable("match_distance", PA, float, np.nan, "1",
             "state-space distance in grid cells to the attractor it continues at the previous value (NaN: none)"),
    Variable("event", PA, np.int8, 0, "1", "appearance or disappearance between the previous value and this one",
             (("flag_values", np.arange(len(ATTRACTOR_EVENTS), dtype=np.int8)),
              ("flag_meanings", " ".join(ATTRACTOR_EVENTS)))),
    Variable("event_link", PA, str, "", "1",
             "the local event the appearance or disappearance is linked to (fold, period_doubling, neimark_sacker, "
             "grazing, impact_lost, stick_onset) or global"),
    Variable("event_evidence", PA, str, "", "1", "what links the event, or why it is flagged global"),
]
#: the verdicts of :data:`ATTRACTOR`'s lifetime_verdict (bifurc.attractors.lifetime.Lifetime.verdict's words)
LIFETIME_VERDICTS = ("none", "attractor", "long-lived", "saddle")
PAM = (PARAM, "attractor", "multiplier")
#: a periodic attractor's Floquet multipliers (the orbit solver's periodic Schur product, bifurc.orbits.floquet)
ATTRACTOR_MULTIPLIERS = [
    Variable("multiplier_abs", PAM, float, np.nan, "1",
             "modulus of the polished periodic attractor's Floquet multiplier, largest first (NaN: not periodic, not "
             "polished, or fewer multipliers)"),
    Variable("multiplier_arg", PAM, float, np.nan, "rad",
             "argument of the polished periodic attractor's Floquet multiplier, in (-pi, pi]"),
]
ATTRACTOR_COORDS = [
    Variable("attractor", A_, np.int32, 0, "1", "attractor id, matched across values (outcomes last)"),
    Variable("attractor_label", A_, str, "", "1", "attractor name (A0, A1, ... or an outcome: escaped, "
             "not_converged, failed, neutral, transient)"),
    Variable("multiplier", ("multiplier",), np.int32, 0, "1", "Floquet multiplier of an attractor, by modulus"),
]

T = ("t",)
I = ("impact",)  # noqa: E741
#: the time-history dataset of maps.simulate (states: their own units and long names, see state_variable)
HISTORY = [
    Variable("t", T, float, np.nan, "s", "time", (("comment", "elapsed time from the start of the integration"),)),
    Variable("relay", T, np.int8, 0, "1", "relay state (1: AC solenoid powered)", _yes_no("off on")),
    Variable("contact", T, np.int8, 0, "1", "bar in contact with the stop", _yes_no("off on")),
    Variable("rig_stuck", T, np.int8, 0, "1", "rig stuck in the soil", _yes_no("slipping stuck")),
    Variable("soil_mode", T, np.int8, 0, "1", "drift soil mode",
             (("flag_values", np.array([0, 1, 2], np.int8)), ("flag_meanings", "clear elastic progression"))),
    Variable("impact", I, np.int64, 0, "1", "contact number in time order"),
    Variable("impact_time", I, float, np.nan, "s", "contact onset time"),
    Variable("impact_velocity", I, float, np.nan, "m s-1", "bar velocity relative to the stop at contact onset"),
    Variable("impact_penetration", I, float, np.nan, "m", "maximum penetration into the stop"),
    Variable("impact_duration", I, float, np.nan, "s", "contact duration (NaN: still in contact at the end)"),
    Variable("progression", T, float, np.nan, "m", "forward progression into the soil x2(0) - x2(t)"),
    # 2-DOF scenes: the progression measures (maps.progression.MEASURES) over the window
    # progression_window [s] (the run's second half unless a transient is given)
    Variable("progression_rate", (), float, np.nan, "m s-1",
             "mean rate of forward progression into the soil over the window"),
    Variable("progression_per_period", (), float, np.nan, "m", "forward progression per relay period over the window"),
    Variable("time_to_depth", (), float, np.nan, "s", "time to progress 0.2 m into the soil (NaN: not reached)"),
    Variable("impact_energy_per_period", (), float, np.nan, "J",
             "kinetic energy of the bar relative to the rig at contact onset, summed per relay period over the window"),
    Variable("stuck_fraction", (), float, np.nan, "1", "fraction of the window in which the soil holds the rig"),
]

#: 2-DOF sweeps: the progression measures of each value over its recorded window (bifurc.sweeps.dataset
#: computes them from the stored samples and contacts with maps.progression)
PROGRESSION = [
    Variable("progression_rate", V, float, np.nan, "m s-1",
             "mean rate of forward progression into the soil over the recorded window"),
    Variable("progression_per_period", V, float, np.nan, "m",
             "forward progression per relay period over the recorded window"),
    Variable("time_to_depth", V, float, np.nan, "s",
             "time to progress 0.2 m into the soil from the start, linear between relay-period samples (NaN: not "
             "reached by the record's end, reached in the unrecorded transient, or a follow sweep)"),
    Variable("impact_energy_per_period", V, float, np.nan, "J",
             "kinetic energy of the bar relative to the rig at contact onset, summed per relay period over the "
             "recorded window (NaN: more contacts than the impact dimension holds)"),
    Variable("stuck_fraction", V, float, np.nan, "1",
             "fraction of the recorded relay-period samples at which the soil holds the rig (sampled once per "
             "relay period, not time-weighted)"),
]


def state_variable(state, dims, suffix="") -> Variable:
    """The row of a state component (its own unit and long name), e.g. stroboscopic samples."""
    return Variable(state.name, dims, float, np.nan, state.unit, state.long_name + suffix)


def flag_variable(flag: str, dims) -> Variable:
    """The row of a mode flag at each sample (``flag_<name>``): with the states, the exact
    hybrid state a map step restarts from."""
    return Variable(f"flag_{flag}", dims, float, np.nan, "1",
                    f"mode flag {flag!r} at the stroboscopic sample (NaN: not reached)")


def param_attrs(table, system, skip=()) -> dict:
    """``param_<name>``, ``param_<name>_units`` and ``param_<name>_source`` attributes of the
    parameter values ``table`` {name: (value, provenance)} of ``system``, except ``skip``."""
    attrs = {}
    for k, (v, src) in table.items():
        if k not in skip:
            attrs[f"param_{k}"] = v
            attrs[f"param_{k}_units"] = system.parameter(k).unit
            attrs[f"param_{k}_source"] = src
    return attrs
