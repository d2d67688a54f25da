"""Amplitude spectrum of a time history (thesis Figs 4.14-4.22): ``ds.bifurc.spectrum()``."""
from __future__ import annotations

import numpy as np

from maps.parameters import ParameterError

def spectrum(ds, var: str = "x", t_from: float | None = None, n_peaks: int = 5):
    """One-sided amplitude spectrum of ``ds[var]`` sampled on a uniform ``time`` grid [s].

    ``t_from`` [s]: skip the transient before it (default: none).  Amplitude of a sine of
    amplitude a at a bin frequency: a (rectangular window, mean removed).  Returns an xarray
    Dataset with ``amplitude`` over ``frequency`` [Hz] and attributes ``peak_frequencies`` [Hz] and
    ``peak_amplitudes`` (the ``n_peaks`` largest local maxima, largest first).
    """
    import xarray as xr
    if var not in ds or "t" not in ds[var].dims:
        raise ParameterError(f"spectrum: variable {var!r} over time not in this dataset; it has "
                             f"{', '.join(k for k in ds.data_vars if 't' in ds[k].dims) or 'none'}")
    da = ds[var] if t_from is None else ds[var].sel(t=slice(float(t_from), None))
    t, y = da.t.values, np.asarray(da.values, dtype=float)
    if t.size < 4:
        raise ParameterError(f"spectrum: need at least 4 samples of {var!r} after t_from, got {t.size}")
    dt = np.diff(t)
    if not np.allclose(dt, dt[0], rtol=1e-6, atol=0):
        raise ParameterError("spectrum: the time grid must be uniform (maps.simulate's dt)")
    ok = np.isfinite(y)
    y = y[ok] - y[ok].mean()
    amp = np.abs(np.fft.rfft(y)) * 2.0 / y.size
    amp[0] /= 2.0
    freq = np.fft.rfftfreq(y.size, dt[0])
    inner = np.nonzero((amp[1:-1] > amp[:-2]) & (amp[1:-1] >= amp[2:]))[0] + 1
    top = inner[np.argsort(amp[inner])[::-1][:n_peaks]]
    unit = ds[var].attrs.get("units", "")
    out = xr.Dataset({"amplitude": ("frequency", amp, {"units": unit, "long_name": f"amplitude of {var}"})},
                     coords={"frequency": ("frequency", freq, {"units": "Hz", "long_name": "frequency"})})
    out.attrs.update(variable=var, peak_frequencies=freq[top], peak_amplitudes=amp[top],
                     frequency_resolution=float(freq[1]) if freq.size > 1 else float("nan"))
    return out
