"""The thesis' measured tables ship with the package; the model's fitted laws against them."""
import math

import numpy as np
import pytest

from maps.presets import COMMON
from maps.thesis_data import TABLES, load_table


@pytest.mark.parametrize("name", sorted(TABLES))
def test_tables_load_with_their_source(name):
    t = load_table(name)
    assert t["source"].startswith("Thesis Table")
    cols = [k for k in t if k != "source"]
    assert len(cols) >= 2 and all(np.all(np.isfinite(t[c])) for c in cols)
    assert len({t[c].size for c in cols}) == 1 and t[cols[0]].size >= 8


def test_dc_force_fit_shares_the_tables_shape_but_overestimates_it():
    """The listing's cubic is restoring and vanishes at the centre like the measurements, but over
    the measured range it gives more than the spring balance read (a finding, documented)."""
    t = load_table("dc_force")
    xa = t["x_a_m"]
    a1, a2, a3 = (COMMON[k][0] for k in ("a1", "a2", "a3"))
    fit = a3 * xa**3 - a2 * xa**2 + a1 * xa  # magnitude of the restoring force [N]
    assert fit[0] == 0.0 and np.all(np.diff(fit) > 0) and np.all(np.diff(t["force_N"]) >= 0)
    assert np.all(fit[1:] >= t["force_N"][1:])  # never below the measurement
    assert abs(fit[-1] - t["force_N"][-1]) < 0.5  # close at the end of the measured range (29 mm)


def test_inductance_fit_matches_the_peak_not_the_flank():
    t = load_table("inductance")
    xb, L = t["x_b_m"], t["L_H"]
    L0, A, B = (COMMON[k][0] for k in ("L0", "A", "B"))
    fit = L0 + A / (B * math.sqrt(math.pi / 2)) * np.exp(-2 * (xb / B) ** 2)
    assert abs(fit[0] - L[0]) / L[0] < 0.01  # the peak, 3 mm from the centre
    assert np.max(L - fit) > 0.2  # 17-30 mm: the Gaussian falls off faster than the coil
