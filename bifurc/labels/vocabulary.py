"""The label vocabulary's names and defaults that the command line reads: light (no numpy), so that building the
parser imports no numerical module."""

#: default budget [strobe (relay) periods]: of a diagram or regime-map value, its own trajectory's periods, transient
#: included; of a census start, its path's periods (the records run beside it not counted).  One default for
#: `diagram`, `map` and `attractors` (issue 45 section 1).  The census had 2000: on benchmarks/attractors.py's census
#: (thesis-1dof, `matlab-listing`, `measured`, 10 Hz; 5 values 80-220 V x 100 box starts), 6000 cost 1.04x its CPU
#: seconds (83.1 against 79.8, interleaved, load 10-17 on 2 cores) and 12 of 500 starts that were "transient" (on a
#: chaotic saddle) at 2000 periods settled on a periodic attractor by 6000, none moved otherwise
#: (benchmarks/reports/one-judge.md); the diagram's 6000 keeps its main job bit-identical
BUDGET = 6000

#: default number of tangent trajectories (the value's own and perturbed copies) a diagram's exponent interval
#: comes from
TRAJECTORIES = 4

#: how a sweep's exponents are integrated (stored with every sweep as ``lyapunov_method``)
METHODS = {
    "tangent": "tangent: one tangent vector integrated with the recorded window (variational equations along it, "
               "saltation at every state event, renormalised every relay period)",
    "companion": "companion: a second trajectory 1e-8 away, renormalised toward the recorded states every relay "
                 "period (Benettin's two-trajectory method)",
}

#: default longest period searched [strobe periods], the diagram's, the regime map's and the census' (the candidates
#: are the multiples of the forcing period q up to it: at 8.5 Hz on the thesis model q = 17, so the census' former
#: 16 found none).  A census orbit too long for a chunk to show a path landing on it is assigned from the record
#: that found it (bifurc/attractors/census.py, _record_and_classify): at 100 without that rule, 8 of 8 switch-on
#: starts of thesis-1dof (`fit`, 10 Hz, 170 V) on a 45:24 orbit ended not_converged
MAX_PERIOD = 100
