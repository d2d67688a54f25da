"""The methods of the work-precision study and their default tolerance ladders: a light module
(no numpy, no heyoka), so that ``bifurc accuracy --help`` lists them without loading the study."""

#: tolerance ladders per method (rtol = atol for scipy, the step h [s] for RK4).  "heyoka": the
#: toolkit's run with every guard record (turning points too); "heyoka-transient": the run the
#: scalar engine's transients take, without stops at observation-only guards (final state and
#: contacts: what the baselines compute)
DEFAULT_LADDERS = {
    "heyoka": [1e-6, 1e-8, 1e-10, 1e-12, 1e-14, 1e-15],
    "heyoka-transient": [1e-6, 1e-8, 1e-10, 1e-12, 1e-14, 1e-15],
    "scipy-DOP853": [1e-6, 1e-8, 1e-10, 1e-12, 1e-13],
    "scipy-RK45": [1e-6, 1e-8, 1e-10],
    "scipy-LSODA": [1e-6, 1e-8, 1e-10, 1e-12],
    "scipy-Radau": [1e-5, 1e-7, 1e-9],
    "rk4-bisection": [1e-3, 3e-4, 1e-4, 3e-5, 1e-5],
}
