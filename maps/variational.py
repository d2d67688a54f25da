"""Exact derivatives of a hybrid flow: heyoka's variational equations plus saltation at events.

Between events, heyoka integrates the first-order variational equations
(``hy.var_ode_sys``) of the current mode: the sensitivity matrix Y = dy/d(y0, p) of the state
with respect to the initial state and the chosen parameters.  At a state event (a guard
crossed at t_e with g(y, t) = 0) the event time itself depends on (y0, p), and Y jumps by the
saltation rule (:func:`maps.transitions.saltation`):

    Y+ = R_y Y- + [0 | R_p] + (f+ - R_y f-) (grad g . Y- + [0 | g_p]) / (grad g . f- + dg/dt)

with R the reset map (identity for the compliant contact, whose force jumps at onset and
release so that f+ != f-) composed with any settle projection (a bar that sticks: rank
deficient), f- and f+ the vector fields before and after.  A relay switch happens at a fixed
time: it needs no saltation for derivatives with respect to the state or to parameters other
than the relay frequency.

:class:`Derivatives` compiles, once per system and parameter list, everything the rule needs:
the vector field, each guard's gradient in state, time and parameters, and each reset's and
declared projection's Jacobian.
"""
from __future__ import annotations

import copy
import time as _time

import heyoka as hy
import numpy as np

from .hybrid import call_cfunc, time_derivative
from .parameters import ParameterError

__all__ = ["Derivatives", "variational_integrator"]

_COMPILED: dict = {}


def variational_integrator(system, tol: float, params: tuple = ()):
    """A heyoka integrator of the system with its first-order variational equations with
    respect to the state and the named ``params`` (state layout: y, then dy_i/d(y0, p)_j row
    by row), the system's guard events included; compiled once per (structure, tol, params)."""
    key = (system.structure, float(tol), tuple(params))
    proto = _COMPILED.get(key)
    if proto is None:
        for p in params:
            system.parameter(p)          # unknown names: one line naming the allowed ones
        clock = _time.perf_counter()
        args = list(system.sym.state_vars) + [system.sym[p] for p in params]
        vsys = hy.var_ode_sys(system.heyoka_system(), args, order=1)
        # compact_mode=False: ~2.5x faster steps (a Jacobian step 4.6x a plain step on thesis-1dof,
        # against 11x compact) for a longer one-time compile (~4 s instead of ~1 s; benchmarks/jacobian.py)
        proto = hy.taylor_adaptive(vsys, np.zeros(len(system.states)), tol=tol,
                                   t_events=system.heyoka_events(float), compact_mode=False)
        proto.compile_seconds = _time.perf_counter() - clock
        _COMPILED[key] = proto
    return copy.deepcopy(proto), proto.compile_seconds


class Derivatives:
    """Compiled derivatives of a system's transitions with respect to the state and ``params``."""

    def __init__(self, system, params: tuple = ()):
        self.system, self.params = system, tuple(params)
        s = system.sym
        self.n, self.m = len(system.states), len(self.params)
        self._wrt = list(s.state_vars)
        self._pars = [s[p] for p in self.params]
        self._rhs = self._cfunc(system.rhs)
        self._guards: dict = {}
        self._maps: dict = {}

    def _cfunc(self, exprs):
        return hy.cfunc(list(exprs), vars=self.system.sym.state_vars, compact_mode=True)

    def pars(self, params, flags) -> np.ndarray:
        """The runtime-parameter vector of (params, flags) that the evaluators below take (build it
        once per event and mode)."""
        return np.asarray(self.system.par_vector(params, flags), dtype=float)

    def rhs(self, t, y, pars) -> np.ndarray:
        """The vector field f(t, y) in the mode of ``pars``."""
        return call_cfunc(self._rhs, y, pars, t)

    def guard(self, guard, t, y, pars):
        """(grad_y g, dg/dt, dg/dp) of a guard surface at (t, y)."""
        f = self._guards.get(guard.name)
        if f is None:
            g = guard.expr
            grad = [hy.diff(g, v) for v in self._wrt]
            exprs = grad + [time_derivative(g)] + [hy.diff(g, p) for p in self._pars]
            f = self._guards[guard.name] = self._cfunc(exprs)
        out = call_cfunc(f, y, pars, t)
        return out[:self.n], float(out[self.n]), out[self.n + 1:]

    def reset(self, guard, t, y, pars):
        """(R_y, R_p) of a guard's reset map at y (identity and zero without a reset)."""
        if guard.reset is None:
            return np.eye(self.n), np.zeros((self.n, self.m))
        return self._jacobian(("reset", guard.name), lambda: self.system.reset_expressions(guard), t, y, pars)

    def projection(self, name, t, y, params, flags):
        """(P_y, P_p) of the settle projection named ``name`` (declared in ``system.projections``)."""
        decl = getattr(self.system, "projections", {}).get(name)
        if decl is None:
            raise ParameterError(f"an exact Jacobian through the settle transition {name!r} needs its projection "
                                 f"declared as expressions (system.projections[{name!r}])")
        key = ("projection", name, tuple(sorted(flags.items())))
        return self._jacobian(key, lambda: decl(self.system.sym, flags), t, y, self.pars(params, flags))

    def _jacobian(self, key, exprs, t, y, pars):
        f = self._maps.get(key)
        if f is None:
            rows = exprs()
            f = self._maps[key] = self._cfunc([hy.diff(r, v) for r in rows for v in self._wrt + self._pars])
        J = call_cfunc(f, y, pars, t).reshape(self.n, self.n + self.m)
        return J[:, :self.n], J[:, self.n:]
