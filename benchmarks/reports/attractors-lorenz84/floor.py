"""The floor of the Lorenz-84 census: a bare heyoka batch ensemble of the census' own starts over the samples each ran.

    python benchmarks/reports/attractors-lorenz84/floor.py /tmp/lorenz84-1000.nc [tol]

Reads the dataset ``benchmarks/attractors_lorenz84.py`` wrote (each start's state ``start_x/y/z`` and the samples
``start_periods`` its census path ran, per value of a) and integrates every start that many samples of 0.5 with
``taylor_adaptive_batch`` (4 lanes, compact_mode=False, tol 1e-10 as the census), sampled by ``propagate_grid``, the
sign flag of |z| flipped at z = 0 by two terminal events whose callbacks only write the flag: no census, no map, no
Python per sample.  Prints its CPU seconds beside the census' own (the dataset's ``fresh_cpu_seconds_*``), in one
process on the same machine (the census' CPU summed over its worker processes)."""
import sys
import time

import heyoka as hy
import numpy as np
import xarray as xr

ds = xr.open_dataset(sys.argv[1])
tol = float(sys.argv[2]) if len(sys.argv) > 2 else 1e-10
B, STEP, b = 4, 0.5, 0.1
x, y, z = hy.make_vars("x", "y", "z")


class Flip:
    def __init__(self, new):
        self.new = new

    def __call__(self, ta, d_sgn, j):
        ta.pars[2, j] = self.new
        return True

    def __deepcopy__(self, memo):
        return self


ev = [hy.t_event_batch(z, direction=hy.event_direction.negative, callback=Flip(-1.0), cooldown=1e-10),
      hy.t_event_batch(z, direction=hy.event_direction.positive, callback=Flip(1.0), cooldown=1e-10)]
ta = hy.taylor_adaptive_batch([(x, y - x), (y, -x * z + hy.par[1] * hy.par[2] * z), (z, x * y - hy.par[0])],
                              np.zeros((3, B)), tol=tol, t_events=ev, compact_mode=False)
starts = np.stack([ds[f"start_{s}"].values for s in "xyz"], axis=-1)       # (start, 3): the same at every value
periods = ds.start_periods.values.astype(int)
clock, samples = time.process_time(), 0
for i, a in enumerate(ds.a.values):
    order = np.argsort(periods[i])     # 4 starts of similar lengths per batch, run to the longest (a slight excess)
    for g in range(0, len(order), B):
        idx = order[g:g + B]
        lanes = np.concatenate([idx, np.repeat(idx[:1], B - len(idx))])
        m = int(periods[i, lanes].max())
        ta.set_time(0.0)
        ta.state[:] = starts[lanes].T
        ta.pars[0, :], ta.pars[1, :] = float(a), b
        ta.pars[2, :] = np.where(starts[lanes, 2] >= 0, 1.0, -1.0)
        ta.reset_cooldowns()
        ta.propagate_grid(np.repeat((STEP * np.arange(m + 1))[:, None], B, axis=1))
        samples += int(periods[i, idx].sum())
floor = time.process_time() - clock
census = sum(float(v) for k, v in ds.attrs.items() if k.startswith("fresh_cpu_seconds_"))
chunks = float(ds.attrs.get("fresh_cpu_seconds_chunks", np.nan))
print(f"{ds.sizes['a']} values x {ds.sizes['start']} starts, {samples} samples in the census' paths")
print(f"bare ensemble {floor:.1f} s CPU ({1e6 * floor / samples:.2f} us per sample); census fresh starts "
      f"{census:.1f} s CPU (chunks {chunks:.1f} s): census / bare {census / floor:.1f}, chunks / bare {chunks / floor:.1f}")
