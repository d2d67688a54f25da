"""The atlas study's _neutral_note with bifurc.Outcome against 396289d's with OUTCOMES, on the small census."""
import importlib.util, os, sys
import xarray as xr
REPO, BASE = os.environ["REPO"], os.environ["BASE"]    # this checkout; an export of 396289d


def load(path, name):
    spec = importlib.util.spec_from_file_location(name, path); m = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(m); return m
ds = xr.load_dataset("census-new.nc")
new = load(f"{REPO}/studies/attractor_atlas/__init__.py", "new_atlas")
old = load(f"{BASE}/studies/attractor_atlas/__init__.py", "old_atlas")
a, b = new._neutral_note(ds), old._neutral_note(ds)
assert a == b, (a, b)
print("same:", repr(a)[:200])
