"""The 2:6 window orbits the 281 x 200 census never met (128.43-128.48 V, 177.69-178.06 V; thesis-1dof, matlab-listing,
measured, 10 Hz): a census at 1000 starts at the window values and their neighbours, linked, with the thesis-orbits
branches' stable orbits and link verdicts from benchmarks/attractors_recovery.py.  Ran at d1223fb, 2026-11-26
23:14-23:17 UTC, 2 workers, idle:
python benchmarks/reports/attractors-recovery/windows_1000.py DIR > windows-1000-d1223fb.txt
(the branch folder /tmp/x/br: thesis-orbits branches saved by attractors_recovery.py --save-branches)."""
import pathlib, sys, time
import numpy as np
ROOT = pathlib.Path(__file__).resolve().parents[3]
sys.path.insert(0,str(ROOT / 'benchmarks')); sys.path.insert(0,str(ROOT))
import attractors_recovery as R, bifurc, maps
from studies.thesis_orbits import PRESET
from bifurc.labels.codes import OUTCOMES
def main():
    vals=np.array([128.0,128.455,128.5,177.5,178.0,178.5])
    t=time.perf_counter()
    ds=bifurc.attractors("thesis-1dof","V",vals,preset=PRESET,params={"relay_hz":10.0},dc_law="measured",
        box={"x":(0.0,0.03),"v":(-1.5,1.5)},n_starts=1000,seed=1,progress=False,link=True)
    print('sec',time.perf_counter()-t)
    n_att=ds.sizes['attractor']-len(OUTCOMES)
    for i,v in enumerate(vals):
        print(v,[(j,int(ds.period.values[i,j]),int(ds.impacts_per_period.values[i,j]),round(float(ds.basin_fraction.values[i,j]),3), str(ds.event_link.values[i,j]) if int(ds.event.values[i,j]) else '') for j in range(n_att) if ds.present.values[i,j]])
    pb=maps.problem("thesis-1dof",preset=PRESET,params={"relay_hz":10.0,"V":float(vals[0])},dc_law="measured")
    names=list(pb.system.state_names)
    bs=R.branches(sys.argv[1] if len(sys.argv) > 1 else None)
    orb=R.stable_orbits(bs,vals,names,pb)
    for i,v in enumerate(vals): print(v,[(p,m) for p,m,_,_ in orb[i]])
    for k,v,verdict in R.links(ds,bs,orb,vals,names,n_att):
        print(k,v,verdict)
    
if __name__=="__main__":
    main()