"""Exact derivatives of a hybrid flow: heyoka's variational equations plus saltation at events.

Between events, heyoka integrates the first-order variational equations
(``hy.var_ode_sys``) of the current mode: the sensitivity matrix Y = dy/d(y0, p) of the state
with respect to the initial state and the chosen parameters.  At a state event (a guard
crossed at t_e with g(y, t) = 0) the event time itself depends on (y0, p), and Y jumps by the
saltation rule (:func:`maps.transitions.saltation`):

    Y+ = R_y Y- + [0 | R_p] + (f+ - R_y f- - R_t) (grad g . Y- + [0 | g_p]) / (grad g . f- + dg/dt)

with R the reset map (identity for the compliant contact, whose force jumps at onset and
release so that f+ != f-) composed with any settle projection (a bar that sticks: rank
deficient), R_t its partial time derivative (a moving stop's reset), f- and f+ the vector
fields before and after.  A relay switch happens at a fixed
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

from . import transitions as tr
from .hybrid import call_cfunc, time_derivative
from .parameters import ParameterError

_COMPILED: dict = {}


def variational_integrator(system, tol: float, params: tuple = ()):
    """A heyoka integrator of the system with its first-order variational equations with
    respect to the state and the named ``params`` (state layout: y, then dy_i/d(y0, p)_j row
    by row), the system's guard events included; compiled once per (structure, tol, params)."""
    for p in params:
        system.parameter(p)          # unknown names: one line naming the allowed ones

    def build():
        args = list(system.sym.state_vars) + [system.sym[p] for p in params]
        return hy.var_ode_sys(system.heyoka_system(), args, order=1)
    return _compiled(system, tol, tuple(params), build)


def _tangent_vars(n: int) -> list:
    """The heyoka variables u_0 .. u_{n-1} of one tangent vector."""
    return [hy.make_vars(f"tangent_{i}") for i in range(n)]


def tangent_equations(system) -> list:
    """(u_i, sum_j df_i/dy_j u_j): the variational equations along one tangent vector u, as
    heyoka (variable, expression) pairs (heyoka's ``diff`` of the vector field)."""
    ys = system.sym.state_vars
    us = _tangent_vars(len(ys))
    return [(u, hy.sum([hy.diff(f, y) * uj for y, uj in zip(ys, us)])) for u, f in zip(us, system.rhs)]


def tangent_integrator(system, tol: float):
    """A heyoka integrator of the system and one tangent vector (state layout: y, then u), the
    system's guard events included; compiled once per (structure, tol)."""
    return _compiled(system, tol, "tangent", lambda: system.heyoka_system() + tangent_equations(system))


def _compiled(system, tol, kind, build):
    """A copy of the integrator of ``build()`` (the augmented system), compiled once per (structure, tol, kind)."""
    key = (system.structure, float(tol), kind)
    proto = _COMPILED.get(key)
    if proto is None:
        clock = _time.perf_counter()
        # compact_mode=False: ~2.5x faster steps (a Jacobian step 4.6x a plain step on thesis-1dof,
        # against 11x compact) for a longer one-time compile (~4 s instead of ~1 s; benchmarks/jacobian.py)
        dynamics = build()     # a var_ode_sys takes the state alone (heyoka starts its sensitivities)
        size = len(system.states) if isinstance(dynamics, hy.var_ode_sys) else len(dynamics)
        proto = hy.taylor_adaptive(dynamics, np.zeros(size), tol=tol,
                                   t_events=system.heyoka_events(float, callbacks=True), compact_mode=False)
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
        self._jumps: dict = {}

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
        """(R_y, R_p, R_t) of a guard's reset map at (t, y) (identity, zero and None without a
        reset; R_t None: the reset does not read time)."""
        if guard.reset is None:
            return np.eye(self.n), np.zeros((self.n, self.m)), None
        return self._jacobian(("reset", guard.name), lambda: self.system.reset_expressions(guard), t, y, pars)

    def projection(self, name, t, y, params, flags):
        """(P_y, P_p, P_t) of the settle projection named ``name`` (declared in ``system.projections``;
        P_t None: it does not read time)."""
        decl = self.system.projections.get(name)
        if decl is None:
            raise ParameterError(f"an exact Jacobian through the settle transition {name!r} needs its projection "
                                 f"declared as expressions (system.projections[{name!r}])")
        key = ("projection", name, tuple(sorted(flags.items())))
        return self._jacobian(key, lambda: decl(self.system.sym, flags), t, y, self.pars(params, flags))

    def transition(self, Y, out, t, params, flags_before, flags_after, guard=None, y_minus=None, y_now=None):
        """(sensitivities after the transition ``out``, dt_e/d(y0, p) or None): ``Y`` (n x (n + m),
        or n x 1 for one tangent vector) holds them just before it.  A guard crossed in ``y_minus``
        under ``flags_before``: the saltation rule with the reset composed with any settle
        projection; no guard (a settle at a fixed time, in state ``y_now`` before it): the
        projection's Jacobian, if it projects; else ``Y`` unchanged."""
        p = params
        if guard is not None:
            before, after = self.pars(p, flags_before), self.pars(p, flags_after)    # built once per event
            R_y, R_p, R_t = self.reset(guard, t, y_minus, before)
            if out.projection is not None:
                if out.projection == guard.name:    # the guard's own projection, after its reset
                    here = (y_minus if guard.reset is None
                            else np.asarray(self.system.reset_function(guard)(np.array(y_minus), p, t), dtype=float))
                else:
                    here = out.records[0][2]        # the state the guard left, before settle's projection
                P_y, P_p, P_t = self.projection(out.projection, t, here, p, flags_after)
                if R_t is not None:
                    R_t = P_y @ R_t if P_t is None else P_y @ R_t + P_t
                else:
                    R_t = P_t
                R_y, R_p = P_y @ R_y, P_y @ R_p + P_p
            y_after = out.y if out.y is not None else y_minus
            grad, g_t, g_p = self.guard(guard, t, y_minus, before)
            f_minus = self.rhs(t, y_minus, before)
            dt = tr.event_time_row(Y, f_minus, grad, g_t, g_p)
            return tr.saltation(Y, f_minus, self.rhs(t, y_after, after), grad, g_t, g_p, R_y, R_p, dt, R_t), dt
        if out.projection is not None:            # a projection at a fixed time
            P_y, P_p, _ = self.projection(out.projection, t, y_now, p, flags_after)
            return tr.projected(Y, P_y, P_p), None
        return Y, None

    def tangent_jump(self, guard, changes):
        """The saltation rule for ONE tangent vector through ``guard`` whose transition changes the
        flags by ``changes`` and projects nothing, compiled once per (guard, changes):
        ``jump(state, pars, t) -> u+`` takes the state (y-, u-) stacked, the runtime parameters of
        the flags before the event and the event time [s], and returns

            u+ = R_y u- + (f+ - R_y f- - R_t) (grad g . u-) / (grad g . f- + dg/dt),

        R the guard's reset (identity without one), R_t its partial time derivative (a moving
        stop's), f- the vector field at y- before the event
        and f+ at R(y-) under the flags after it (:func:`maps.transitions.saltation` with one
        column).  One compiled call instead of the general rule's several evaluations and small
        matrix products: the batch engine's hot path in a recorded window.  A grazing crossing
        (denominator 0) gives a non-finite u+, which ends the tangent (:mod:`maps.tangent`)."""
        key = (guard.name, *changes.items())
        jump = self._jumps.get(key)
        if jump is None:
            f = self._compile_jump(guard, changes)
            jump = self._jumps[key] = lambda state, pars, t: call_cfunc(f, state, pars, t)
        return jump

    def matrix_jump(self, guard, changes, columns: int | None = None):
        """The saltation rule of :meth:`tangent_jump` for every column of Y = dy/dy0 (n x n, no
        parameter columns; or n x ``columns`` tangent vectors) in ONE call of one compiled
        function, with the event time's row: ``jump(state, pars, t) -> (Y+, dt_e/dy0, rate)``,
        ``state`` the state y- and Y- stacked as the integrator holds them (Y row by row), where
        dt_e/dy0 = -(grad g . Y) / rate (:func:`maps.transitions.event_time_row` without
        parameters) and rate = grad g . f- + dg/dt, the surface's crossing rate: 0 at a grazing
        crossing, where the other values are not finite and the caller falls back to the general
        rule, which says so.  ``jump.nparams``: the runtime parameters it reads (the first ones of
        ``pars``).  The scalar engine's path for a state Jacobian (Floquet multipliers, a map's
        linearisation): one flat call costs about half a batch call over the columns."""
        n = self.n
        c = n if columns is None else int(columns)
        key = ("matrix", c, guard.name, *changes.items())
        jump = self._jumps.get(key)
        if jump is None:
            Ys = [[hy.make_vars(f"sens_{i}_{j}") for j in range(c)] for i in range(n)]
            f = self._compile_jump(guard, changes, [[Ys[k][j] for k in range(n)] for j in range(c)],
                                   [y for row in Ys for y in row], time_rows=True)
            k, nc, timed = f.nparams, n * c, f.is_time_dependent

            def jump(state, pars, t):
                if type(pars) is not np.ndarray:
                    pars = np.asarray(pars, dtype=float)
                p = pars[:k] if len(pars) > k else pars
                out = f(state, pars=p, time=float(t)) if timed else f(state, pars=p)
                return out[:nc].reshape(n, c), out[nc:nc + c], float(out[-1])
            jump.nparams = k
            self._jumps[key] = jump
        return jump

    def _compile_jump(self, guard, changes, columns=None, inputs=None, time_rows: bool = False):
        """The compiled saltation rule of ``guard`` (flags changed by ``changes``) for the tangent
        vectors ``columns`` (lists of n heyoka variables; default one, :func:`_tangent_vars`), a
        function of the state then ``inputs`` (default: the one column); outputs row i of every
        column in turn (i major), then with ``time_rows`` the event time's derivative along each
        and the crossing rate grad g . f- + dg/dt."""
        s, system = self.system.sym, self.system
        ys = list(s.state_vars)
        if columns is None:
            columns = [_tangent_vars(self.n)]
            inputs = columns[0]
        R = system.reset_expressions(guard)
        R_y = [[hy.diff(r, y) for y in ys] for r in R]
        zero = hy.expression(0.0)
        R_t = [time_derivative(r) for r in R] if guard.reset is not None else [zero] * self.n
        after = {y: r for y, r in zip(ys, R) if guard.reset is not None}
        after.update({s[k]: hy.expression(float(v)) for k, v in changes.items()})
        f_minus = list(system.rhs)
        f_plus = [hy.subs(f, after) if after else f for f in f_minus]
        g = guard.expr
        grad = [hy.diff(g, y) for y in ys]
        rate = system.lie_derivative(g)                      # grad g . f- + dg/dt
        along = [hy.sum([a * u for a, u in zip(grad, us)]) / rate for us in columns]
        rows = []
        for i in range(self.n):
            Rf = hy.sum([R_y[i][j] * f_minus[j] for j in range(self.n)])
            if R_t[i] != zero:                   # a reset that reads time (a moving stop)
                Rf = Rf + R_t[i]
            for us, a in zip(columns, along):
                Ru = hy.sum([R_y[i][j] * us[j] for j in range(self.n)])
                rows.append(Ru + (f_plus[i] - Rf) * a)
        if time_rows:
            rows.extend(-a for a in along)
            rows.append(rate)
        return hy.cfunc(rows, vars=ys + list(inputs), compact_mode=True)

    def _jacobian(self, key, exprs, t, y, pars):
        """(d/dy, d/dp, d/dt or None where no row reads time) of the map ``exprs()`` at (t, y)."""
        entry = self._maps.get(key)
        if entry is None:
            rows = exprs()
            d_t = [time_derivative(r) for r in rows]
            timed = any(d != hy.expression(0.0) for d in d_t)
            f = self._cfunc([hy.diff(r, v) for r in rows for v in self._wrt + self._pars] + (d_t if timed else []))
            entry = self._maps[key] = (f, timed)
        f, timed = entry
        n, c = self.n, self.n + self.m
        out = call_cfunc(f, y, pars, t)
        J = out[:n * c].reshape(n, c)
        return J[:, :n], J[:, n:], (out[n * c:] if timed else None)
