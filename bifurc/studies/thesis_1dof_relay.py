"""Thesis 1-DOF relay-frequency study, 2 to 10 Hz (thesis Fig 4.27, section 4.8).

For each case (preset and voltage) a bifurcation diagram over the relay
frequency, the class at 2, 3, ..., 10 Hz, and a comparison with what the thesis
reports: numerically period-1 at 2, 3, 4, 5, 9, 10 Hz and period-2 at 6, 7, 8 Hz
(Fig 4.27); experimentally period-1 at all of them (Figs 3.9-3.17).  Nothing is
tuned to agree.
"""
import numpy as np

NAME = "thesis-1dof-relay"
SCENE = "thesis-1dof"
PARAM = "relay_hz"
#: (case name, preset, parameter overrides): the presets as the thesis gives them, and 90 V
#: (the upper end of the experiments' 70-90 V, amplitude or RMS not stated)
CASES = [
    ("thesis-text", "thesis-text", {}),
    ("matlab-listing", "matlab-listing", {}),
    ("matlab-listing-90V", "matlab-listing", {"V": 90.0}),
]
FULL = dict(values=np.round(np.linspace(2.0, 10.0, 81), 10), transient=300, record=100)
QUICK = dict(values=np.arange(2.0, 11.0), transient=60, record=30)
AT = list(range(2, 11))
THESIS_NUMERICAL = {2: 1, 3: 1, 4: 1, 5: 1, 6: 2, 7: 2, 8: 2, 9: 1, 10: 1}  # period per Fig 4.27
THESIS_EXPERIMENT = {w: 1 for w in AT}                                      # Figs 3.9-3.17
THESIS_SIMULATED_SECONDS = 3.0                                              # tf = 3 in the listings
