"""The small census of the pub45 check: thesis-1dof, V in [120, 160] (5 values), 30 box starts (seed 1), 1 worker."""
import sys
import numpy as np
import bifurc, maps
print(bifurc.__file__, file=sys.stderr)
pb = maps.problem("thesis-1dof", params={"relay_hz": 10.0}, dc_law="measured", preset="matlab-listing")
ds = bifurc.attractors(pb, "V", np.linspace(120, 160, 5), bifurc.Census(link=False), starts=bifurc.Box(n=30, seed=1),
                       run=bifurc.Run(workers=1, progress=False))
ds.to_netcdf(sys.argv[1])
print({k: v for k, v in ds.attrs.items() if "seconds" in k})
