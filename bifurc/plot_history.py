"""Time-history figure of a simulated scene."""
from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

__all__ = ["plot_time_history"]


def _label(var, name=None):
    units = var.attrs.get("units", "")
    return f"{name or var.attrs.get('long_name', var.name)} [{units}]" if units and units != "1" else \
        (name or var.attrs.get("long_name", var.name))


def plot_time_history(ds, path=None):
    """Displacement (impacts marked), rig progression (2-DOF), current and relay state against time.

    Returns the matplotlib Figure; writes a PNG when ``path`` is given.
    """
    two_dof = "x1" in ds
    panels = ["disp"] + (["prog"] if "progression" in ds else []) + (["i"] if "i" in ds else []) + \
             (["relay"] if "relay" in ds else [])
    heights = [3 if p == "disp" else (1 if p == "relay" else 2) for p in panels]
    fig, axes = plt.subplots(len(panels), 1, sharex=True, figsize=(9, 1.6 + 1.3 * sum(heights) / 2),
                             gridspec_kw={"height_ratios": heights}, squeeze=False)
    axes = axes[:, 0]
    t = ds.time.values
    for ax, p in zip(axes, panels):
        if p == "disp":
            r = (ds.x1 - ds.x2) if two_dof else ds.x
            ax.plot(t, 1e3 * r.values, lw=0.8, color="C0")
            ax.axhline(1e3 * ds.attrs.get("param_e", 0.0), color="k", lw=0.8, ls="--", label="stop")
            if ds.sizes.get("impact", 0):
                ti = ds.impact_time.values
                ax.plot(ti, np.full_like(ti, 1e3 * ds.attrs.get("param_e", 0.0)), "v", color="C3", ms=4,
                        label=f"impacts ({ti.size})")
            ax.set_ylabel("bar - rig [mm]" if two_dof else "bar position x [mm]")
            ax.legend(loc="upper right", fontsize=8)
        elif p == "prog":
            ax.plot(t, 1e3 * ds.progression.values, lw=0.8, color="C2")
            ax.set_ylabel("progression [mm]")
        elif p == "i":
            ax.plot(t, ds.i.values, lw=0.5, color="C1")
            ax.set_ylabel("current i [A]")
        elif p == "relay":
            ax.fill_between(t, ds.relay.values, step="post", alpha=0.4, color="C4")
            ax.set_ylim(-0.1, 1.1)
            ax.set_yticks([0, 1], ["off", "on"])
            ax.set_ylabel("relay")
        ax.grid(alpha=0.3)
    axes[-1].set_xlabel("time [s]")
    a = ds.attrs
    keys = [k for k in ("V", "relay_hz", "R", "C", "k", "c") if f"param_{k}" in a]
    params = ", ".join(f"{k} = {a[f'param_{k}']:g} {a[f'param_{k}_units']}" for k in keys)
    status = "" if a.get("status") == "ok" else f" [{a.get('status')}]"
    fig.suptitle(f"{a.get('scene', '')}{status}: {params}\ncircuit {a.get('circuit')}, tol {a.get('tol'):g}",
                 fontsize=9)
    fig.tight_layout()
    if path:
        fig.savefig(path, dpi=120)
        plt.close(fig)
    return fig
