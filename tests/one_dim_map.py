"""A 1-D map with the stroboscopic map's ``orbits`` interface (strobe points only), for the census' tests of
chaotic sets and their lifetimes (closed-form maps standing in for a hybrid system's stroboscopic map)."""
from types import SimpleNamespace

import numpy as np

from maps.hybrid import HybridState


class OneDimMap:
    """x -> f(x), iterated in float64; ``orbits`` returns what :meth:`maps.StroboscopicMap.orbits` does."""

    forcing_period_steps = 1

    def __init__(self, f):
        self.f = f

    def orbits(self, overrides, x0, n, *, k0=0, batch_size=4, events=True):
        out = []
        for s in x0:
            x = np.empty(n + 1)
            x[0] = float(np.asarray(getattr(s, "y", s), dtype=float)[0])
            for k in range(n):
                x[k + 1] = self.f(x[k])
            out.append(SimpleNamespace(points=x[:, None], status="ok", final=HybridState(x[-1:].copy(), None),
                                       state=lambda j, x=x: HybridState(x[j:j + 1].copy(), None)))
        return out
