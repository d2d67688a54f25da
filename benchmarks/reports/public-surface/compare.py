"""Compare the small census before (396289d) and after: identical but for run times, provenance and the new fields."""
import sys
import xarray as xr
a, b = (xr.load_dataset(p) for p in sys.argv[1:3])
new_vars = sorted(set(b.data_vars) - set(a.data_vars))
new_attrs = sorted(set(b.attrs) - set(a.attrs))
print("new variables:", new_vars, "new attrs:", new_attrs)
timing = [k for k in a.attrs if k.endswith("_seconds") or k in ("history", "bifurc_version")]
for ds in (a, b):
    for k in timing + new_attrs:
        ds.attrs.pop(k, None)
b = b.drop_vars(new_vars)
xr.testing.assert_identical(a, b)
print("identical after dropping", timing, new_vars, new_attrs)
