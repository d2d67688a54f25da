"""The label vocabulary's names and defaults that the command line reads: light (no numpy), so that building the
parser imports no numerical module."""

#: default budget of a value [strobe periods of its own trajectory, transient included]
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
#: are the multiples of the forcing period q up to it: at 8.5 Hz on the thesis model q = 17, so 16 found none)
MAX_PERIOD = 100
