"""How a census is done: the :class:`Census` method, the samplers of starts and the matcher.

As in Attractors.jl, the three roles are objects a user can swap: a sampler (:class:`Box`, :class:`Slice`,
:class:`SwitchOn`, :class:`Given`) draws the fresh starts, the mapper (:class:`Census`: recurrence on a grid, Newton
polishing, lifetimes) says where each goes, and the matcher (:class:`ByDistance`) continues the attractors from one
parameter point to the next.
"""
from __future__ import annotations

from dataclasses import dataclass

from maps.parameters import ParameterError

from ..labels.vocabulary import BUDGET, MAX_PERIOD
from ..run.settings import Settings, setting

#: the largest number of starts per point
MAX_STARTS = 10_000_000
#: seeds numpy's default_rng takes (non-negative, below 2**63)
MAX_SEED = 2 ** 63 - 1


@dataclass(frozen=True)
class Census(Settings):
    """The attractor census at each parameter point: every start followed on a state-space grid until it lands on
    a known attractor, recurs in its own cells (then identified: periodic orbits polished by Newton, chaotic and
    quasi-periodic sets judged on their exponent interval and lifetime), escapes, or spends the budget."""

    cells: int = setting(100, "recurrence grid cells per box side", low=2, high=1e6, whole=True)
    budget: int = setting(BUDGET, "periods per start after which it is transient (on a chaotic saddle) or "
                          "not_converged", unit="strobe periods", low=1, high=1e9, whole=True)
    max_period: int = setting(MAX_PERIOD, "longest period Newton tries from a start's record (a contracting record that "
                              "repeats at a longer lag, up to a quarter of its length, is polished at that lag)",
                              unit="strobe periods", low=1, high=1e4, whole=True)
    tol: float = setting(1e-10, "heyoka tolerance", low=0.0, high=1e-2, low_open=True)
    chunk: int = setting(40, "periods per batch call", unit="strobe periods", low=1, high=1e6, whole=True, cli="")
    land: int = setting(6, "consecutive points in one attractor's cells to land on it", low=1, high=1e6, whole=True,
                        cli="")
    recur: int = setting(20, "consecutive revisits of a start's own cells to call an attractor found", low=1,
                         high=1e6, whole=True, cli="")
    locate: int = setting(48, "periods of a start's first record to identify it (doubled at each undecided one)",
                          unit="strobe periods", low=4, high=1e7, whole=True, cli="")
    link: bool = setting(True, "continue each appearing or disappearing periodic orbit across the step to link the "
                         "change to a located fold, period doubling, torus, grazing or stick onset",
                         flag="--no-link")
    n_node: int = setting(16, "polished strobe states stored per attractor", low=1, high=1e5, whole=True, cli="")
    batch_size: int = setting(4, "starts integrated together in heyoka's batch mode (SIMD lanes)", low=1, high=64,
                              whole=True)
    apportion: bool = setting(False, "stop a start that enters a chaotic saddle whose exits its lifetime copies "
                              "measured, and apportion it by them (basin intervals carry both sampling errors)")

    def settings(self):
        """The census engine's own settings (:class:`bifurc.attractors.census.Settings`)."""
        from .census import Settings as EngineSettings
        return EngineSettings(chunk=self.chunk, land=self.land, recur=self.recur, locate=self.locate,
                              max_periods=self.budget, max_period=self.max_period, batch_size=self.batch_size,
                              apportion=self.apportion)


@dataclass(frozen=True)
class ByDistance(Settings):
    """Match an attractor to one of the previous point's by state-space distance (like with like; periodic orbits
    by their polished nodes at the best phase, confirmed by Newton where impacts differ)."""

    threshold: float = setting(20.0, "largest distance at which an attractor continues one of the previous "
                               "point's", unit="grid cells", low=0, high=1e9, cli="--match-threshold")


# ----- samplers -------------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Box(Settings):
    """``n`` starts uniform in ``box`` {state: (low, high)} [SI] (default: the scene's declared box), the other
    states at the scene's start, drawn by ``numpy.random.default_rng(seed)``."""

    n: int = setting(200, "fresh starts per point", low=1, high=MAX_STARTS, whole=True, cli="--starts")
    box: object = setting(None, "{state: (low, high)} [SI]; default the scene's declared box", optional=True, cli="")
    seed: int = setting(0, "random seed of the starts", low=0, high=MAX_SEED, whole=True)

    def draw(self, pb):
        from .starts import box_starts
        box = self.box if self.box is not None else getattr(pb.scene, "box", {})
        if not box:
            raise ParameterError(f"scene {pb.name!r} declares no census box: give Box(box={{state: (low, high)}}) "
                                 f"(--box)")
        return box_starts(pb, dict(box), self.n, self.seed)


@dataclass(frozen=True)
class Slice(Settings):
    """A ``shape`` = (n1, n2) grid of cell centres on the slice of the box's two states (others: the scene's
    start)."""

    shape: tuple = setting((14, 14), "grid points per side of the slice", cli="")
    box: object = setting(None, "{state: (low, high)} [SI] naming two states; default the scene's declared box",
                          optional=True, cli="")

    def draw(self, pb):
        from .starts import slice_starts
        box = self.box if self.box is not None else getattr(pb.scene, "box", {})
        if not box:
            raise ParameterError(f"scene {pb.name!r} declares no census box: give Slice(box=...) naming two states")
        return slice_starts(pb, dict(box), self.shape)


@dataclass(frozen=True)
class SwitchOn(Settings):
    """The scene's declared switch-on distribution (thesis: the bar at rest on the stop, the circuit at rest, a
    declared spread): ``n`` draws with ``seed``."""

    n: int = setting(200, "fresh starts per point", low=1, high=MAX_STARTS, whole=True, cli="--starts")
    seed: int = setting(0, "random seed of the starts", low=0, high=MAX_SEED, whole=True)

    def draw(self, pb):
        from .starts import switch_on_starts
        return switch_on_starts(pb, self.n, self.seed)


class Given:
    """Starts given as an (N, d) array [SI, the system's state order]."""

    def __init__(self, points):
        import numpy as np
        self.points = np.atleast_2d(np.asarray(points, dtype=float))

    def draw(self, pb):
        from .starts import make_starts
        return make_starts(pb, self.points)

    def __repr__(self):
        return f"Given({self.points.shape[0]} starts)"


SAMPLERS = (Box, Slice, SwitchOn, Given)


def sampler_of(starts, options: dict):
    """The sampler of ``starts`` (a sampler object; "box", "slice", "switch-on"; a Starts or an (N, d) array), with
    the keyword forms ``n_starts``, ``box``, ``seed``, ``shape`` of ``options`` applied."""
    from .starts import Starts
    kw = {k: options.pop(k) for k in ("n_starts", "box", "seed", "shape") if k in options}
    if "n_starts" in kw:
        kw["n"] = kw.pop("n_starts")
    if isinstance(starts, SAMPLERS[:3]):
        return starts.replace(**kw) if kw else starts
    if isinstance(starts, Given):
        return starts
    if isinstance(starts, Starts):
        return _Fixed(starts)
    if starts is None or (isinstance(starts, str) and starts == "box"):
        return Box(**{k: v for k, v in kw.items() if k != "shape"})
    if isinstance(starts, str) and starts == "slice":
        if "shape" not in kw and "n" in kw:
            import math
            kw["shape"] = (int(math.isqrt(int(kw["n"]))),) * 2
        return Slice(**{k: v for k, v in kw.items() if k in ("shape", "box")})
    if isinstance(starts, str) and starts == "switch-on":
        return SwitchOn(**{k: v for k, v in kw.items() if k in ("n", "seed")})
    if isinstance(starts, str):
        raise ParameterError(f"starts {starts!r}; allowed: box, slice, switch-on, a sampler (bifurc.Box, "
                             f"bifurc.Slice, bifurc.SwitchOn) or an (N, d) array")
    return Given(starts)


class _Fixed:
    """A :class:`~bifurc.attractors.starts.Starts` already drawn."""

    def __init__(self, starts):
        self.starts = starts

    def draw(self, pb):
        return self.starts
