"""The census' period-1, 3-impact orbit of thesis-1dof (`measured`, 10 Hz) at 158 V continued by Newton in 0.5 V
steps up to 175 V and down to 140 V, its multipliers printed: where it loses stability, beside the thesis-orbits
study's 1:3 orbit "stable in [140.31062 (period doubling), 174.49314 (period doubling)]".  Under the scene's default
preset (before 2026-11-26 15:00) it period-doubled at 158.5-159 V: another model's orbit.

    python benchmarks/reports/attractors-recovery/one_to_three.py > one_to_three.txt
"""
import numpy as np

import bifurc
import maps
from bifurc.labels.codes import OUTCOMES
from bifurc.orbits.periodic import find_periodic_orbit
from maps.hybrid import HybridState
from maps.poincare import StroboscopicMap

#: the thesis-orbits study's preset (before 2026-11-26 15:00 this ran under the scene's default, `thesis-text`: another
#: model than the one whose 1:3 orbit it was compared with)
PRESET = "matlab-listing"


def main():
    ds = bifurc.attractors("thesis-1dof", "V", [158.0, 159.0], preset=PRESET, params={"relay_hz": 10.0}, dc_law="measured",
                           box={"x": (0.0, 0.03), "v": (-1.5, 1.5)}, n_starts=200, seed=1, progress=False, link=False,
                           workers=1)
    for i, v in enumerate(ds["V"].values):
        print(f"census at {v:g} V (200 box starts, seed 1): " + "; ".join(
            f"{int(ds.period.values[i, j])}:{int(ds.impacts_per_period.values[i, j])} at x = "
            f"{ds.x.values[i, j, 0] * 1e3:.3f} mm, fraction {ds.basin_fraction.values[i, j]:.3f}"
            for j in range(ds.sizes["attractor"] - len(OUTCOMES)) if ds.present.values[i, j]))
    pb = maps.problem("thesis-1dof", preset=PRESET, params={"relay_hz": 10.0, "V": 158.0}, dc_law="measured")
    j = [j for j in range(ds.sizes["attractor"] - len(OUTCOMES)) if ds.present.values[0, j]
         and ds.period.values[0, j] == 1 and ds.impacts_per_period.values[0, j] == 3][0]
    start = HybridState(np.array([ds[n].values[0, j, 0] for n in pb.system.state_names]), None)
    k0 = int(ds.attractor_k0.values[0, j])
    smap = StroboscopicMap(pb, tol=1e-10)
    for stop in (175.0, 140.0):
        state = start
        for v in np.arange(158.0, stop + np.sign(stop - 158.0) * 0.01, np.sign(stop - 158.0) * 0.5):
            smap = smap.at(dict(V=float(v)))
            po = find_periodic_orbit(smap, state, 1, k0=k0, tol=1e-10)
            print(f"{v:.1f} V: impacts {po.impacts_per_period}, x {po.nodes[0].y[0] * 1e3:.4f} mm, multipliers "
                  f"{np.round(po.multipliers, 4)}, stable {po.stable}", flush=True)
            state = po.nodes[0]


if __name__ == "__main__":
    main()
