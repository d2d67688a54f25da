"""python benchmarks/reports/attractors-lorenz84/why.py /tmp/lorenz84-100.nc <the docs page's scene block as a .py file>

For the values 4.94, 5.00, 5.20, 5.36 and 5.82 where the census lists a chaotic attractor: run 4 trajectories from its stored points 20000 samples
(10000 time units) on and say whether each is still chaotic at the end (its last 768 samples not repeating, their
exponent) or on the limit cycle."""
import sys, numpy as np, xarray as xr, maps
import importlib.util
spec = importlib.util.spec_from_file_location("scene", sys.argv[2]); mod = importlib.util.module_from_spec(spec); spec.loader.exec_module(mod)
from maps.poincare import StroboscopicMap
from bifurc.attractors.dataset import attractor_text
ds = xr.open_dataset(sys.argv[1])
pb = maps.problem(mod.LORENZ)
for i, a in enumerate(ds.a.values):
    if round(float(a), 2) not in (4.94, 5.0, 5.2, 5.36, 5.82):
        continue
    for j, lab in enumerate(ds.attractor_label.values):
        if not str(lab).startswith("A") or not ds.present.values[i, j]:
            continue
        if attractor_text(ds, i, j) != "chaotic attractor":
            continue
        sm = StroboscopicMap(pb.with_values(a=float(a)), tol=1e-10)
        n = int(min(ds.n_points.values[i, j], ds.sizes["node"]))
        pts = np.stack([ds[s].values[i, j, :n] for s in ("x", "y", "z")], axis=1)
        starts = [pts[k] for k in np.linspace(0, n - 1, 4).astype(int)]
        orb = sm.orbits([{}] * 4, starts, 20000, batch_size=4, tangent=True)
        out = []
        for o in orb:
            s = o.tangent_stretch()
            lam_end = float(np.nanmean(s[-4000:])) if s is not None else float("nan")
            out.append(f"{lam_end:+.3f}")
        print(f"a = {a:.2f} {lab}: exponent over the last 4000 of 20000 samples from 4 of its points: {', '.join(out)}", flush=True)
