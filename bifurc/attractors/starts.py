"""Ensembles of starts for the attractor census: a random box, a 2-D slice grid, the "switch-on" start.

A box names some states with their bounds [SI units] (``{"x": (0, 0.03), "v": (-1.5, 1.5)}`` or the
command line's ``x=0:0.03,v=-1.5:1.5``); the other states start at the scene's start.  Every start
is a row of an (N, d) array in the system's state order; :class:`Starts` says how it was made.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from maps.parameters import ParameterError

@dataclass
class Starts:
    """``points`` (N, d) [SI, state order]; ``kind``: box, slice or switch-on; ``box`` the bounds drawn
    from; ``shape`` (n1, n2) and ``slice_states`` for a slice grid (row-major: the second state fastest)."""

    points: np.ndarray
    kind: str
    box: dict = field(default_factory=dict)
    shape: tuple = ()
    slice_states: tuple = ()
    seed: int | None = None

    def __len__(self) -> int:
        return len(self.points)

    def describe(self) -> str:
        bounds = ",".join(f"{k}={lo:g}:{hi:g}" for k, (lo, hi) in self.box.items())
        if self.kind == "slice":
            return f"slice grid {self.shape[0]} x {self.shape[1]} over {bounds}"
        return f"{len(self)} {self.kind} starts over {bounds} (seed {self.seed})"


def parse_box(text: str, option: str = "--box") -> dict:
    """'x=0:0.03,v=-1.5:1.5' -> {'x': (0.0, 0.03), 'v': (-1.5, 1.5)} (checked against a system by :func:`check_box`)."""
    box = {}
    for item in (p.strip() for p in str(text).split(",")):
        if not item:
            continue
        name, sep, rng = item.partition("=")
        lo, sep2, hi = rng.partition(":")
        if not sep or not sep2 or not name.strip():
            raise ParameterError(f"{option} {item!r}: expected STATE=LOW:HIGH in SI units, e.g. x=0:0.03")
        try:
            box[name.strip()] = (float(lo), float(hi))
        except ValueError:
            raise ParameterError(f"{option} {item!r}: bounds of {name.strip()!r} are not numbers") from None
    if not box:
        raise ParameterError(f"{option} {text!r}: name at least one state, e.g. x=0:0.03")
    return box


def check_box(box: dict, system, option: str = "box") -> dict:
    """The box with float bounds, or a ParameterError naming the state and the allowed form."""
    if not isinstance(box, dict) or not box:
        raise ParameterError(f"{option}: a mapping state -> (low, high) [SI], e.g. {{'x': (0, 0.03)}}; got {box!r}")
    out = {}
    for name, bounds in box.items():
        if name not in system.state_names:
            raise ParameterError(f"{option}: unknown state {name!r}; the states of {system.name!r} are "
                                 f"{', '.join(system.state_names)}")
        try:
            lo, hi = (float(b) for b in bounds)
        except (TypeError, ValueError):
            raise ParameterError(f"{option}: the bounds of {name!r} must be two numbers (low, high); got {bounds!r}") \
                from None
        unit = system.states[system.state_names.index(name)].unit
        if not (math.isfinite(lo) and math.isfinite(hi)):
            raise ParameterError(f"{option}: the bounds of {name!r} must be finite numbers [{unit}]; got {lo:g}:{hi:g}")
        if not lo < hi:
            raise ParameterError(f"{option}: the bounds of {name!r} are reversed or empty ({lo:g}:{hi:g} {unit}); "
                                 f"need low < high")
        out[name] = (lo, hi)
    return out


def _base(pb, n: int) -> np.ndarray:
    return np.tile(pb.state_vector(), (n, 1)).astype(float)


def box_starts(pb, box: dict, n: int, seed: int = 0) -> Starts:
    """``n`` starts uniform in ``box`` (the scene's start elsewhere), from ``numpy.random.default_rng(seed)``."""
    box = check_box(box, pb.system)
    n = _count(n, "starts")
    rng = np.random.default_rng(seed)
    pts = _base(pb, n)
    for name in pb.system.state_names:       # state order: the same seed draws the same starts
        if name in box:
            lo, hi = box[name]
            pts[:, pb.system.state_names.index(name)] = rng.uniform(lo, hi, n)
    return Starts(pts, "box", box, seed=seed)


def slice_starts(pb, box: dict, shape) -> Starts:
    """A grid of ``shape`` = (n1, n2) cell centres on the slice of the box's two states (others: the scene's start)."""
    box = check_box(box, pb.system)
    if len(box) != 2:
        raise ParameterError(f"a slice grid varies exactly two states; the box names {len(box)}: {', '.join(box)}")
    n1, n2 = (_count(k, "grid points per side") for k in shape)
    (a, (alo, ahi)), (b, (blo, bhi)) = box.items()
    ga = alo + (np.arange(n1) + 0.5) * (ahi - alo) / n1
    gb = blo + (np.arange(n2) + 0.5) * (bhi - blo) / n2
    A, B = np.meshgrid(ga, gb, indexing="ij")
    pts = _base(pb, n1 * n2)
    pts[:, pb.system.state_names.index(a)] = A.ravel()
    pts[:, pb.system.state_names.index(b)] = B.ravel()
    return Starts(pts, "slice", box, shape=(n1, n2), slice_states=(a, b))


def switch_on_starts(pb, n: int, seed: int = 0, spread: dict | None = None) -> Starts:
    """The scene's "switch-on" distribution (``Scene.switch_on``: the thesis bar at rest on the stop, the
    circuit at rest, with a declared spread), or ``spread`` {state: (low, high)}: ``n`` uniform draws."""
    spread = spread if spread is not None else getattr(pb.scene, "switch_on", {})
    if not spread:
        raise ParameterError(f"scene {pb.name!r} declares no switch-on start; give a box (--box) instead")
    lows = {k: lo for k, (lo, hi) in spread.items()}
    wide = {k: v for k, v in spread.items() if v[1] > v[0]}
    pts = _base(pb, _count(n, "starts"))
    for k, lo in lows.items():
        pts[:, pb.system.state_names.index(k)] = lo
    if wide:
        drawn = box_starts(pb, wide, len(pts), seed).points
        for k in wide:
            j = pb.system.state_names.index(k)
            pts[:, j] = drawn[:, j]
    return Starts(pts, "switch-on", dict(spread), seed=seed)


def make_starts(pb, starts=None, *, n: int = 100, box: dict | None = None, seed: int = 0, shape=None) -> Starts:
    """The ensemble ``starts`` names: a :class:`Starts` or an (N, d) array as is; "box" (``box`` or the
    scene's declared one), "slice" (a ``shape`` grid over the box's two states) or "switch-on"."""
    if isinstance(starts, Starts):
        return starts
    if starts is not None and not isinstance(starts, str):
        pts = np.atleast_2d(np.asarray(starts, dtype=float))
        if pts.shape[0] < 1 or pts.shape[1] != len(pb.system.state_names) or not np.all(np.isfinite(pts)):
            raise ParameterError(f"starts: an (N, {len(pb.system.state_names)}) array of N >= 1 finite states "
                                 f"({', '.join(pb.system.state_names)}); got shape {pts.shape}")
        return Starts(pts, "given")
    kind = starts or "box"
    if kind == "switch-on":
        return switch_on_starts(pb, n, seed)
    box = box if box is not None else getattr(pb.scene, "box", {})
    if not box:
        raise ParameterError(f"scene {pb.name!r} declares no census box: give box={{state: (low, high)}} (--box)")
    if kind == "box":
        return box_starts(pb, box, n, seed)
    if kind == "slice":
        return slice_starts(pb, box, shape if shape is not None else (int(math.isqrt(n)),) * 2)
    raise ParameterError(f"starts {kind!r}; allowed: box, slice, switch-on, or an (N, d) array")


def _count(n, what: str) -> int:
    if isinstance(n, bool) or not float(n).is_integer() or not 1 <= n <= 10_000_000:
        raise ParameterError(f"{what} = {n!r}: a whole number from 1 to 10000000")
    return int(n)
