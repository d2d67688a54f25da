"""How a diagram value (or a regime-map cell) is integrated and judged: the :class:`Diagram` method."""
from __future__ import annotations

from dataclasses import dataclass

from maps.parameters import ParameterError

from ..labels.vocabulary import BUDGET, MAX_PERIOD, METHODS, TRAJECTORIES
from ..run.settings import MODES, Settings, setting


#: default cap of the record extension, in multiples of ``record`` (3 x 100 periods holds three forcing
#: periods of every q up to the default max_period of 100)
RECORD_FACTOR = 3
#: whole forcing periods q the record must hold before the period search (two for the recurrence
#: test of period q, one more for its decay fit); a shorter record is extended up to ``max_record``
FORCING_PERIODS = 3


def record_cap(record: int, max_record: int | None) -> int:
    """The longest record of a value [strobe periods]: ``max_record``, else RECORD_FACTOR x ``record``."""
    return max_record if max_record is not None else RECORD_FACTOR * record


def record_length(record: int, q: int, max_period: int, record_cap: int) -> int:
    """Strobe periods to record at a value whose forcing repeats every ``q`` periods: ``record``, extended to
    FORCING_PERIODS x q (never beyond ``record_cap``) when the period search has candidates (0 < q <=
    ``max_period``) and the record holds fewer than FORCING_PERIODS of them."""
    if 0 < q <= max_period and record < FORCING_PERIODS * q:
        return max(record, min(FORCING_PERIODS * q, record_cap))
    return record


@dataclass(frozen=True)
class Diagram(Settings):
    """A brute-force bifurcation diagram: each value integrated, recorded and labelled on evidence.

    Every value runs ``transient`` then ``record`` strobe periods (relay periods of the thesis scenes); an
    undecided value is extended by the anytime judge (:mod:`bifurc.labels.anytime`) up to ``budget`` periods,
    transient included.  The same method classifies a regime map's cells.
    """

    mode: str = setting("independent", "independent: every value from the start state; follow: each value from the "
                        "previous one's final state, swept up then down", choices=tuple(MODES))
    transient: int = setting(300, "periods discarded per value", unit="strobe periods", low=0, high=1e7, whole=True)
    record: int = setting(100, "periods recorded per value before it is first judged; an undecided value is "
                          "extended up to --budget", unit="strobe periods", low=3, high=1e7, whole=True)
    budget: int | None = setting(None, f"periods per value, transient included, that an undecided value may be "
                                 f"extended to (default {BUDGET}); a value still undecided then is not-converged with "
                                 f"its reason", unit="strobe periods", low=3, high=1e9, whole=True, optional=True,
                                 kind=int)
    max_period: int = setting(MAX_PERIOD, "cap of the period search: candidates are the multiples of the forcing period q "
                              "that fit twice in the record", unit="strobe periods", low=1, high=1e6, whole=True)
    max_record: int | None = setting(None, "extend a record whose forcing period q exceeds record/3 to 3 q periods, "
                                     "at most this many (default 3 x record)", unit="strobe periods", low=3, high=1e7,
                                     whole=True, optional=True, kind=int)
    max_transient: int | None = setting(None, "(superseded by budget) extend values still converging up to this "
                                        "many periods: the budget is at least this plus record",
                                        unit="strobe periods", low=0, high=1e8, whole=True, optional=True, kind=int)
    tol: float = setting(1e-10, "heyoka tolerance", low=0.0, high=1e-2,
                         low_open=True)
    rtol: float = setting(1e-6, "relative tolerance of the period test", low=0, high=1, cli="")
    atol: float = setting(1e-9, "absolute tolerance of the period test", low=0, high=1, cli="")
    lyapunov: bool = setting(True, "the largest Lyapunov exponent where the orbit is not periodic",
                             flag="--no-lyapunov")
    lyapunov_method: str = setting("tangent", "how the exponent is integrated", choices=tuple(METHODS), cli="")
    trajectories: int = setting(TRAJECTORIES, "tangent trajectories on the same attractor (the value's own and "
                                "perturbed copies of its state) the exponent and its interval come from: more "
                                "narrow the interval and cost periods", low=2, high=64, whole=True)
    grazing: bool = setting(True, "locate grazing values where neighbours change between impacting and not",
                            flag="--no-grazing")
    grazing_xtol: float | None = setting(None, "tolerance of the located grazing value (default: a fraction of the "
                                         "grid step)", low=0, high=1e9, optional=True, cli="", kind=float)
    error_sample: int = setting(3, "values re-run at tol/100 for the error estimate (0: none)", low=0, high=1e6,
                                whole=True, cli="")
    batch_size: int = setting(4, "values integrated together in heyoka's batch mode (SIMD lanes; 1: one at a "
                              "time); results agree to round-off", low=1, high=64, whole=True)

    def record_for(self, q: int) -> int:
        """Strobe periods recorded at a value whose forcing repeats every ``q`` periods before it is first judged:
        ``record``, extended to hold three forcing periods where the period search needs them, at most
        ``max_record`` (default 3 x ``record``)."""
        return record_length(self.record, q, self.max_period, record_cap(self.record, self.max_record))

    def _check(self) -> None:
        if self.budget is not None and self.budget < self.transient + self.record:
            raise ParameterError(f"budget = {self.budget} is below transient + record = {self.transient + self.record}"
                                 f"; allowed: budget >= {self.transient + self.record}")
        if self.max_record is not None and self.max_record < self.record:
            raise ParameterError(f"max_record = {self.max_record} is below record = {self.record}")
        if self.max_transient is not None and self.max_transient < self.transient:
            raise ParameterError(f"max_transient = {self.max_transient} is below transient = {self.transient}")
