"""Figure of a periodic orbit (``bifurc.periodic_orbit``): its strobe nodes in the state plane and
its Floquet multipliers on the unit circle."""
from __future__ import annotations

import numpy as np

from ..storage.files import check_figure_output, save_figure
from ..storage.load import require_kind

def orbit_plane(ds) -> tuple[str, str]:
    """The two states drawn: (x, v) where the orbit has them, else its first two states."""
    states = [v for v in ds.data_vars if ds[v].dims == ("node",) and not v.startswith("flag_") and v != "signature"]
    if {"x", "v"} <= set(states):
        return "x", "v"
    return (states[0], states[1]) if len(states) > 1 else (states[0], states[0])


def _label(da) -> str:
    units = da.attrs.get("units", "")
    return da.name + (f" [{units}]" if units not in ("", "1") else "")


def plot_orbit(ds, path=None, ax=None, overwrite=False):
    """The orbit's strobe nodes in the (x, v) plane (or its first two states), numbered, with the
    nodes followed by an impact marked; and, beside them, its Floquet multipliers against the unit
    circle (filled: stable orbit).

    ``ax``: draw into this Axes, or a pair (plane, multipliers).  ``path``: also save there (an existing
    file is refused unless ``overwrite``) and close the figure.  Returns the plane's Axes.
    """
    require_kind(ds, "orbit", "plot_orbit")
    if path is not None:
        check_figure_output(path, overwrite)
    own = ax is None
    if own:
        import matplotlib.pyplot as plt
        _, (ax, mu_ax) = plt.subplots(1, 2, figsize=(11, 4.8), gridspec_kw={"width_ratios": [3, 2]})
    else:
        ax, mu_ax = ax if isinstance(ax, (tuple, list)) else (ax, None)
    a, b = orbit_plane(ds)
    x, y = ds[a].values, ds[b].values
    ax.plot(np.append(x, x[:1]), np.append(y, y[:1]), ":", color="0.6", lw=1)
    ax.plot(x, y, "o", color="#0072B2", ms=7, label="strobe nodes")
    hits = [k for k, s in enumerate(ds.signature.values) if "impact" in str(s).split(",")]
    if hits:
        ax.plot(x[hits], y[hits], "x", color="#D55E00", ms=11, mew=2, label="impact in the following period")
    for k in range(x.size):
        ax.annotate(str(k), (x[k], y[k]), textcoords="offset points", xytext=(6, 6), fontsize=8)
    ax.set_xlabel(_label(ds[a]))
    ax.set_ylabel(_label(ds[b]))
    stable = int(ds.stable.values) == 1
    ax.set_title(f"{ds.attrs.get('scene', '')}: period {int(ds.period.values)}, "
                 f"{int(ds.impacts_per_period.values)} impacts per period, {'stable' if stable else 'unstable'}")
    ax.legend(loc="best", fontsize=8)
    if mu_ax is not None:
        _draw_multipliers(mu_ax, ds, stable)
    if path is not None:
        save_figure(ax.figure, path, overwrite=overwrite, close=own)
    return ax


def _draw_multipliers(ax, ds, stable) -> None:
    mu = ds.multiplier_abs.values * np.exp(1j * ds.multiplier_arg.values)
    t = np.linspace(0, 2 * np.pi, 200)
    ax.plot(np.cos(t), np.sin(t), color="0.5", lw=1)
    ax.plot(mu.real, mu.imag, "o", color="#009E73", mfc="#009E73" if stable else "none", ms=8)
    ax.axhline(0, color="0.85", lw=0.8)
    ax.axvline(0, color="0.85", lw=0.8)
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("Re μ")
    ax.set_ylabel("Im μ")
    ax.set_title("Floquet multipliers")
