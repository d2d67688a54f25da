"""The rewritten label helpers against the old ones (396289d's benchmarks, on internals) on one small census."""
import importlib.util, os, sys
import numpy as np
REPO, BASE = os.environ["REPO"], os.environ["BASE"]    # this checkout; an export of 396289d


def load(path, name):
    spec = importlib.util.spec_from_file_location(name, path); m = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(m); return m
sys.path.insert(0, f"{REPO}/benchmarks")
new = {n: load(f"{REPO}/benchmarks/{n}.py", "new_" + n) for n in ("attractors", "attractors_apportion", "attractors_budget")}
old = {n: load(f"{BASE}/benchmarks/{n}.py", "old_" + n) for n in ("attractors", "attractors_apportion", "attractors_budget")}
ds, _, _ = new["attractors"].census(5, 30, link=False, workers=1)
half, _, _ = new["attractors"].census(5, 30, cells=200, link=False, workers=1)
assert new["attractors"].by_label(ds) == old["attractors"].by_label(ds)
assert new["attractors"].grid_change(ds, half) == old["attractors"].grid_change(ds, half), (new["attractors"].grid_change(ds, half), old["attractors"].grid_change(ds, half))
from bifurc.attractors.dataset import attractor_count
assert new["attractors"].attractor_count(ds) == attractor_count(ds)
assert new["attractors_apportion"].by_label(ds) == old["attractors_apportion"].by_label(ds)
assert new["attractors_apportion"].stable_orbits(ds) == old["attractors_apportion"].stable_orbits(ds)
for i in range(5):
    a, b = new["attractors_budget"].by_label(ds, i), old["attractors_budget"].by_label(ds, i)
    assert a.keys() == b.keys() and all(np.array_equal(a[k], b[k]) for k in a)
print("same:", new["attractors"].by_label(ds))
print(new["attractors"].grid_change(ds, half))
