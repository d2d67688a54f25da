"""The model's force laws as the thesis plots them (Figs 4.5, 4.6, 4.10-4.12, 4.26): ``bifurc params --plot``.

Every curve comes from the compiled model's own outputs (``HybridSystem.evaluate``), never a second
copy of a formula: the DC force against xa (every DC law, Table 4.1's points); dL/dx against xb from
the AC force at i = 1 A (F_ac = +-dL/dx i^2 / 2), L from it integrated from L0 far from the coil and
d2L/dx2 differentiated (Table 4.2's points beside L); the AC force over a short run of the scene.
"""
from __future__ import annotations

import numpy as np

from maps.laws import DC_LAWS

from ..storage.files import check_figure_output, save_figure

def check_force_laws(scene, preset=None, params=None) -> None:
    """Raise a ParameterError when ``scene`` has neither solenoid (no DC or AC force law to draw)."""
    from maps.parameters import ParameterError
    from maps.problem import problem
    values = dict(problem(scene, preset, params).values)
    if "d_dc" not in values and "d_ac" not in values:
        raise ParameterError(f"--plot: scene {scene!r} has no solenoid force law to draw (scenes with one: "
                             "thesis-1dof, thesis-2dof, prototype, dc-only, ac-only, ac-stop)")


def _evaluate(pb, names, r, flags=None, state=None):
    """The outputs ``names`` at bar positions ``r`` [m] above the stop, bar and rig at rest, other states
    from ``state`` over the scene's start (n, len(names))."""
    from maps.model import dc_region_flags
    system, values = pb.system, dict(pb.values)
    key = "x" if "x" in system.state_names else "x1"
    out = []
    for rk in np.asarray(r, float):
        x0 = dict(pb.x0, **(state or {}))
        x0[key] = float(rk) + (float(x0.get("x2", 0.0)) if key == "x1" else 0.0)
        y = system.state_vector(x0)
        fl = dict(system.flag_defaults, **(flags or {}))
        if system.options is not None and system.options.dc_law == "measured":
            fl.update(dc_region_flags(system.options, y, values))
        out.append(system.evaluate(list(names), y, values, fl))
    return np.asarray(out, float)


def law_curves(scene="thesis-1dof", preset=None, params=None, dc_law=None, n=401, t_end=0.1) -> dict:
    """The plotted data: {"xa": [m], "F_dc": {law: [N]}, "xb": [m], "L", "dL", "ddL": [H, H/m, H/m2],
    "t": [s], "F_ac": [N] over ``t_end`` of ``maps.simulate`` from the scene's start, "dc_law": the
    scene's law}.  The DC force with the DC coil on (relay gate P = 0), the AC force with it on (P = 1)."""
    import maps
    from maps.problem import problem
    base = problem(scene, preset, params, dc_law=dc_law)
    o = base.system.options
    out = {"dc_law": getattr(o, "dc_law", None)}
    d_dc, d_ac = dict(base.values).get("d_dc"), dict(base.values).get("d_ac")
    if d_dc is not None:
        xa = np.linspace(-0.04, 0.04, n)    # Table 4.1 spans |xa| <= 29 mm
        out["xa"], out["F_dc"] = xa, {}
        for law in DC_LAWS:
            pb = problem(scene, preset, params, dc_law=law)      # each law at its own d_dc (C.14's: 0)
            out["F_dc"][law] = _evaluate(pb, ["F_dc"], xa + dict(pb.values)["d_dc"], {"P": 0.0})[:, 0]
    if d_ac is not None:
        xb = np.linspace(-0.06, 0.12, n)
        wide = np.linspace(-0.3, 0.12, 4 * n)         # from far behind the coil, where L = L0 within 1e-20
        sign = 1.0 if o.ac_sign == "physical" else -1.0
        dL = 2.0 * sign * _evaluate(base, ["F_ac"], wide - d_ac, {"P": 1.0}, {"i": 1.0})[:, 0]
        L = dict(base.values)["L0"] + np.concatenate([[0.0], np.cumsum(0.5 * (dL[1:] + dL[:-1]) * np.diff(wide))])
        out["xb"] = xb
        out["dL"] = np.interp(xb, wide, dL)
        out["L"] = np.interp(xb, wide, L)
        out["ddL"] = np.interp(xb, wide, np.gradient(dL, wide))
        h = maps.simulate(base, t_end=t_end, dt=t_end / 2000)
        y = np.column_stack([h[s].values for s in base.system.state_names])
        fl = dict(base.system.flag_defaults, P=1.0)
        out["t"] = h.t.values
        out["F_ac"] = np.array([base.system.evaluate(["F_ac"], yk, dict(base.values), fl, t=tk)[0]
                                for tk, yk in zip(h.t.values, y)])
    return out


def plot_force_laws(scene="thesis-1dof", preset=None, params=None, dc_law=None, path=None, overwrite=False):
    """Draw :func:`law_curves` in four panels (DC force, inductance, its derivatives, AC force against
    time) with the thesis' tables; ``path``: also write the figure (refused if it exists, unless
    ``overwrite``).  Returns (figure, curves)."""
    import matplotlib.pyplot as plt
    from maps.thesis_data import load_table
    if path is not None:
        check_figure_output(path, overwrite)
    c = law_curves(scene, preset, params, dc_law)
    fig, ax = plt.subplots(2, 2, figsize=(11, 8))
    a = ax[0, 0]
    if "xa" in c:
        for law, F in c["F_dc"].items():
            a.plot(1e3 * c["xa"], F, lw=2.0 if law == c["dc_law"] else 1.0, label=f"{law}"
                   + (" (this model)" if law == c["dc_law"] else ""))
        t41 = load_table("dc_force")
        xs = np.asarray(t41["x_a_m"], float)
        a.plot(-1e3 * xs, np.asarray(t41["force_N"], float), "kx", label="Table 4.1 (20 V)")
        a.set(xlabel="xa = bar centre - DC solenoid centre [mm]", ylabel="DC force F_dc [N]",
              title="DC force (Figs 4.5, 4.6)")
        a.legend(fontsize=8)
    if "xb" in c:
        t42 = load_table("inductance")
        ax[0, 1].plot(1e3 * c["xb"], c["L"], label="model (eq 4.13)")
        ax[0, 1].plot(1e3 * np.asarray(t42["x_b_m"], float), np.asarray(t42["L_H"], float), "kx", label="Table 4.2")
        ax[0, 1].set(xlabel="xb [mm]", ylabel="L [H]", title="inductance (Fig 4.10)")
        ax[0, 1].legend(fontsize=8)
        ax[1, 0].plot(1e3 * c["xb"], c["dL"], label="dL/dx [H/m] (Fig 4.11)")
        ax[1, 0].plot(1e3 * c["xb"], c["ddL"] / 100.0, label="d2L/dx2 / 100 [H/m2] (Fig 4.12)")
        ax[1, 0].set(xlabel="xb [mm]", title="inductance derivatives (Figs 4.11, 4.12)")
        ax[1, 0].legend(fontsize=8)
    if "F_ac" in c:
        ax[1, 1].plot(c["t"], c["F_ac"], lw=0.7)
        ax[1, 1].set(xlabel="t [s]", ylabel="F_ac [N]", title="AC force over the run's start (Fig 4.26)")
    fig.suptitle(f"force laws of {scene}" + (f" ({preset})" if preset else ""), fontsize=10)
    fig.tight_layout()
    if path is not None:
        save_figure(fig, path, overwrite)
    return fig, c
