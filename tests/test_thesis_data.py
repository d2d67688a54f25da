"""The thesis' measured tables ship with the package; the inductance fit against its table."""
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


# The DC-force laws against Table 4.1: tests/test_dc_laws.py (listing C.9 overestimates the
# table through its linear term's sign; eq 4.6 is the table's least-squares odd cubic).


def test_inductance_fit_matches_the_peak_not_the_flank():
    t = load_table("inductance")
    xb, L = t["x_b_m"], t["L_H"]
    L0, A, B = (COMMON[k][0] for k in ("L0", "A", "B"))
    fit = L0 + A / (B * math.sqrt(math.pi / 2)) * np.exp(-2 * (xb / B) ** 2)
    assert abs(fit[0] - L[0]) / L[0] < 0.01  # the peak, 3 mm from the centre
    assert np.max(L - fit) > 0.2  # 17-30 mm: the Gaussian falls off faster than the coil
