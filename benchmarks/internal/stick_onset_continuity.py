"""Do the pieces a branch is restarted into past a stick onset belong to the same family?  (issue 28, section 3;
the thesis-orbits study's `measured` law at 10 Hz, where restarts past stick onsets give 2, 3, 4, 5, 6, 7 impacts
per period.)  Not a timing.

The study's branch (thesis-1dof, matlab-listing numbers, DC law `measured`, relay 10 Hz, from the orbit a
300-period simulation reaches at V = 95 V, toward 300 V, 200 points, tol 1e-12, Newton 1e-11) is computed again
(`continue_branch`, as `continue_orbit` runs it).  At each located stick onset V_s, the piece restarted past it
(n + 1 impacts) is continued back toward lower V from its first point, without restarts (`continue_piece`),
until it stops.  The same family: it stops at V_s (within the restart's distance, 1e-5 of the span) with a strobe
state equal to the n-impact orbit's at V_s up to what the state moves over that distance (the n-impact piece's
own slope dY/dV times it), and multipliers near the n-impact orbit's.  Another family would stop elsewhere, or
reach V_s with a state apart by the order of the orbit's magnitude.
Printed side by side: the stop's distance from V_s, the state gap (each component over the orbit's magnitude,
the largest), the gap expected from the slope, the largest multiplier modulus of both.
Run: python benchmarks/internal/stick_onset_continuity.py   (~10 s)
"""
from __future__ import annotations

import os
import subprocess
import time
from types import SimpleNamespace

import numpy as np

import maps
from bifurc.orbits.arclength import continue_branch, continue_piece
from bifurc.orbits.continuation import ContinuationProblem
from bifurc.orbits.orbit import first_guess
from bifurc import find_periodic_orbit
from maps import StroboscopicMap

V0, V1 = 95.0, 300.0


def main():
    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True).stdout.strip()
    print(f"commit {commit}, {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, load {os.getloadavg()[0]:.1f}")
    pb = maps.problem("thesis-1dof", "matlab-listing", {"relay_hz": 10.0, "V": V0}, dc_law="measured")
    smap = StroboscopicMap(pb, tol=1e-12)
    start, k0, period = first_guess(smap, pb, transient=300)
    orbit = find_periodic_orbit(smap, start, period, k0=k0, tol=1e-11)
    cont = ContinuationProblem(smap, "V", period, k0, scale=orbit.scale, p_scale=V1 - V0, p_ref=V0, tol=1e-11)
    branch = continue_branch(cont, orbit, V0, V1, max_points=200)

    def state(pt):
        return np.concatenate([cont.co.reduce(s.y) for s in pt.nodes]) / np.tile(cont.scale, cont.n)

    print(f"{'V_s':>13} {'impacts':>8} {'back to V - V_s':>15} {'state gap':>10} {'from slope':>10} "
          f"{'|mu|max n, n+1':>16}  stop of the piece continued back")
    for sp in branch.special:
        if sp.kind != "stick_onset":
            continue
        before, after = branch.points[sp.index], branch.points[sp.index + 1]
        if before.impacts_per_period == after.impacts_per_period or sp.index < 1:
            continue
        earlier = branch.points[sp.index - 1]
        back = ContinuationProblem(smap.at(phase=after.phase), "V", period, after.k0, scale=cont.scale, p_scale=V1 - V0, p_ref=V0,
                                   tol=1e-11)
        piece = continue_piece(back, SimpleNamespace(nodes=after.nodes), after.p, sp.p - 1.0, max_points=60)
        end = piece.points[-1]
        slope = np.max(np.abs(state(before) - state(earlier))) / abs(before.p - earlier.p)
        gap = np.max(np.abs(state(end) - state(before)))
        mus = (np.max(np.abs(before.multipliers)), np.max(np.abs(end.multipliers)))
        n0, n1 = before.impacts_per_period, after.impacts_per_period
        print(f"{sp.p:13.8f} {n0:>3} -> {n1:<2} {end.p - sp.p:15.3g} {gap:10.3g} "
              f"{slope * abs(end.p - before.p):10.3g} {mus[0]:8.4f}, {mus[1]:.4f}  {piece.stop_reason[:70]}")


if __name__ == "__main__":
    main()
