"""One census run of the Lorenz-84 scene from the checkout in cwd: values x starts, 1 worker; prints a JSON line."""
import sys, time, re, importlib, tempfile, json, resource
from pathlib import Path
import numpy as np
code = re.findall(r"```python\n(.*?)```", (Path.cwd()/"docs/howto/autonomous-flows.md").read_text(), flags=re.S)[0]
folder = Path(tempfile.mkdtemp(prefix="lorenz84-")); (folder/"lorenz84_scene.py").write_text(code)
sys.path.insert(0, str(folder)); mod = importlib.import_module("lorenz84_scene")
t = time.perf_counter(); c = time.process_time()
import bifurc
n = int(sys.argv[1]); vals = [float(v) for v in sys.argv[2].split(",")]
ds = bifurc.attractors(mod.LORENZ, "a", vals, bifurc.Census(cells=100, locate=768, link=False),
                       starts=bifurc.Box(n=n, seed=1), run=bifurc.Run(workers=1, progress=False))
from bifurc.attractors.dataset import census_lines
print(json.dumps({"wall": time.perf_counter() - t, "cpu": time.process_time() - c,
                  "fresh_cpu": sum(float(v) for k, v in ds.attrs.items() if k.startswith("fresh_cpu_seconds_")),
                  "periods": float(ds.attrs["periods_per_start_mean"]), "lines": census_lines(ds)[1:]}))
