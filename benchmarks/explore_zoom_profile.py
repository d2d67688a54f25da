"""Where a zoom's first picture goes (issue 49: 200 values of the main job, 300 + 100 relay periods, no extension,
within 5 s on 2 cores), in CPU seconds, which a loaded machine inflates far less than wall times.

    python benchmarks/explore_zoom_profile.py OLD_CHECKOUT NEW_CHECKOUT [--rounds 2] [--no-record]

1. The zoom, per checkout (a fresh process with ``PYTHONPATH`` and the working directory set to it, rounds
   alternating old and new): warm zoom processes ready (:class:`bifurc.explore.compute.Spares`), then
   :class:`bifurc.explore.compute.Zoom` over 8 to 9 Hz on 200 values, polled every 0.05 s as a page does until the
   first picture: the CPU seconds of each zoom process (from ``/proc/<pid>/stat``) and of the page's process
   (its polls, loads of the stored chunks and joins), the wall times of the first and the last stored chunk, and
   the CPU of one join of every chunk into the picture (:meth:`bifurc.explore.compute.Zoom.picture`, after it);
   the first round's pictures compared value by value, bit for bit (class, period, impacts, strobe states).
2. The floor, in this process (the new checkout's code): 100 of the 200 values (every other one, a zoom process'
   share) as one :func:`bifurc.sweep` call with the first picture's settings, as the batch engine's orbits alone
   (:meth:`maps.StroboscopicMap.orbits`, 300 + 100 periods), and as a bare heyoka batch ensemble of the same
   trajectories (``BareBatch`` of benchmarks/frequency_diagram.py: relay and contact flag only, 4 lanes, no event
   log, no classification, no storage); CPU seconds, best of the rounds.
"""
from __future__ import annotations

import json
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent

CODE = r"""
import json, os, pickle, resource, sys, tempfile, time
import numpy as np, maps, bifurc
from bifurc.explore import compute
folder = tempfile.mkdtemp()
pb = maps.problem("thesis-1dof", preset="matlab-listing", params={"V": 90})
bifurc.sweep(pb, "relay_hz", np.array([8.5]), bifurc.Diagram(budget=6000, error_sample=0),
             run=bifurc.Run(workers=1, progress=False, path=folder + "/d.nc"))
c = compute.Computer(bifurc.load(folder + "/d.nc"))
spares = compute.Spares(c).fill()
while spares.ready() < spares.n:
    time.sleep(0.05)
tick = os.sysconf("SC_CLK_TCK")
def cpu(pid):
    f = open(f"/proc/{pid}/stat").read().rsplit(")", 1)[1].split()
    return (int(f[11]) + int(f[12])) / tick
before = {ch.pid: cpu(ch.pid) for ch in spares.children}
me0 = resource.getrusage(resource.RUSAGE_SELF)
z = compute.Zoom(c, 8.0, 9.0, 200, spares=spares)
while True:
    s = z.poll()
    if s["error"]:
        raise SystemExit(s["error"])
    if s["stage"] >= 1:
        break
    time.sleep(0.05)
after = {ch.pid: cpu(ch.pid) for ch in z.children}
me1 = resource.getrusage(resource.RUSAGE_SELF)
wall0 = time.time() - (time.perf_counter() - z.started)
lands = sorted(os.path.getmtime(f) - wall0 for f in z.folder.glob("s0-*.pickle"))
z.close(); spares.close()
t = time.process_time()
for _ in range(5):
    z.picture()
join = (time.process_time() - t) / 5
with open(sys.argv[1], "wb") as f:
    pickle.dump(z.picture(), f)
print(json.dumps({"first_picture": s["seconds"], "zoom_cpu": [after[p] - before[p] for p in after],
                  "page_cpu": me1.ru_utime + me1.ru_stime - me0.ru_utime - me0.ru_stime,
                  "first_chunk": lands[0], "last_chunk": lands[-1], "join": join, "chunks": len(z.chunks)}))
"""


def zoom(checkout: Path, picture: Path) -> dict:
    """One zoom in ``checkout``; its first picture pickled to ``picture``."""
    env = dict(os.environ, PYTHONPATH=str(checkout), MPLBACKEND="Agg")
    out = subprocess.run([sys.executable, "-c", CODE, str(picture)], cwd=checkout, env=env, capture_output=True,
                         text=True, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def differing(a: Path, b: Path) -> int:
    """Values whose first picture differs between two pickled pictures (class, period, impacts, strobe states;
    bit for bit, NaN equal to NaN)."""
    import pickle

    import numpy as np
    with open(a, "rb") as fa, open(b, "rb") as fb:
        x, y = pickle.load(fa), pickle.load(fb)
    assert np.array_equal(x.relay_hz.values, y.relay_hz.values)
    bad = np.zeros(x.sizes["relay_hz"], bool)
    for name in ("class_code", "period", "impacts_per_period", "x", "v"):
        u, w = x[name].transpose("relay_hz", ...).values, y[name].transpose("relay_hz", ...).values
        same = (u == w) | (np.isnan(u) & np.isnan(w)) if u.dtype.kind == "f" else u == w
        bad |= ~same.reshape(same.shape[0], -1).all(axis=1)
    return int(bad.sum())


def floor(rounds: int) -> dict:
    """CPU seconds of 100 values (a zoom process' share): sweep, engine orbits, bare heyoka batch (best)."""
    import numpy as np

    import bifurc
    import maps
    from frequency_diagram import BareBatch, Problem
    pb = maps.problem("thesis-1dof", preset="matlab-listing", params={"V": 90})
    values = np.linspace(8, 9, 200)[::2]
    m = bifurc.Diagram(transient=300, record=100, budget=400, lyapunov=False, grazing=False, error_sample=0)
    run = bifurc.Run(workers=1, progress=False)
    smap = maps.StroboscopicMap(pb, tol=1e-10)
    bare = BareBatch(Problem(params=dict(pb.values)))
    bare.warm()
    bifurc.sweep(pb, "relay_hz", values[:4], m, run=run)
    sides = {"sweep": lambda: bifurc.sweep(pb, "relay_hz", values, m, run=run),
             "orbits": lambda: smap.orbits([{"relay_hz": float(v)} for v in values], pb.state_vector(), 100,
                                           transient=300, method="batch", batch_size=4),
             "bare": lambda: bare.run_many(values)}
    got = {k: [] for k in sides}
    for _ in range(rounds):
        for k, f in sides.items():
            t = time.process_time()
            f()
            got[k].append(time.process_time() - t)
    return {k: min(v) for k, v in got.items()}


def main(argv=None) -> int:
    sys.path.insert(0, str(HERE))
    from explore_zoom_compare import checkouts
    from record import Run
    args = checkouts(__doc__, 2, argv)
    run = Run("explorer zoom: where the first picture's time goes",
              " ".join(["python benchmarks/explore_zoom_profile.py", *map(str, (argv or sys.argv[1:]))]),
              notes="CPU seconds of the zoom processes and the page's process until the first picture of 200 values "
                    "(300 + 100 relay periods), and the floor of 100 values (a zoom process' share). " + args.notes)
    import tempfile
    folder = tempfile.mkdtemp(prefix="bifurc-zoom-profile-")
    got: dict = {"old": [], "new": []}
    for r in range(args.rounds):
        for name in (("old", "new") if r % 2 == 0 else ("new", "old")):
            load = os.getloadavg()[0]
            m = zoom(getattr(args, name), Path(folder) / f"{name}-{r}.pickle")
            got[name].append(m)
            print(f"round {r + 1} {name}: first picture {m['first_picture']:.2f} s, zoom processes "
                  f"{' + '.join(f'{x:.2f}' for x in m['zoom_cpu'])} CPU s, page {m['page_cpu']:.2f} CPU s, chunks "
                  f"stored {m['first_chunk']:.2f} to {m['last_chunk']:.2f} s (load {load:.1f})", flush=True)
    for name, ms in got.items():
        med = lambda key: statistics.median(key(m) for m in ms)  # noqa: E731
        run.figure(f"{name}: CPU of one zoom process until the first picture (median)",
                   round(med(lambda m: statistics.mean(m["zoom_cpu"])), 2), "s")
        run.figure(f"{name}: CPU of the page's process until the first picture (median)",
                   round(med(lambda m: m["page_cpu"]), 2), "s")
        run.figure(f"{name}: last chunk stored to first picture seen (median)",
                   round(med(lambda m: m["first_picture"] - m["last_chunk"]), 2), "s")
        run.figure(f"{name}: first picture (median, loaded)", round(med(lambda m: m["first_picture"]), 2), "s")
        run.figure(f"{name}: join of every chunk into the picture (Zoom.picture, CPU, median)",
                   round(med(lambda m: m["join"]), 3), "s", note=f"{ms[0]['chunks']} chunks")
    diff = differing(Path(folder) / "old-0.pickle", Path(folder) / "new-0.pickle")
    print(f"values whose first picture differs, new against old (first round): {diff} of 200")
    run.figure("values whose first picture differs, new against old (class, period, impacts, strobe states, bit for "
               "bit; first round)", diff, "values", note="of 200")
    fl = floor(args.rounds + 1)
    print("floor, CPU s per 100 values (best): " + ", ".join(f"{k} {v:.2f}" for k, v in fl.items()))
    for k, v in fl.items():
        run.figure(f"floor: 100 values, {k} (CPU, best)", round(v, 2), "s")
    if not args.no_record:
        print(f"wrote {run.write()}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
