"""ds.bifurc.spectrum(): peaks of a known sum of sines, and of a simulated history."""
import numpy as np
import pytest
import xarray as xr

import bifurc  # noqa: F401  (registers ds.bifurc)
from maps.parameters import ParameterError


def test_spectrum_of_a_sum_of_sines_lists_its_frequencies_and_amplitudes():
    t = np.arange(0.0, 4.0, 1e-3)                       # 4 s: 0.25 Hz bins, both tones on a bin
    x = 0.003 * np.sin(2 * np.pi * 5.0 * t) + 0.001 * np.cos(2 * np.pi * 12.5 * t) + 0.02
    ds = xr.Dataset({"x": ("t", x, {"units": "m"})}, coords={"t": t}, attrs={"bifurc_kind": "history"})
    sp = ds.bifurc.spectrum(n_peaks=2)
    assert sp.attrs["peak_frequencies"].tolist() == pytest.approx([5.0, 12.5], abs=1e-12)
    assert sp.attrs["peak_amplitudes"].tolist() == pytest.approx([0.003, 0.001], rel=1e-9)
    assert sp.amplitude.attrs["units"] == "m" and sp.frequency.attrs["units"] == "Hz"
    with pytest.raises(ParameterError, match="'y'"):
        ds.bifurc.spectrum("y")
