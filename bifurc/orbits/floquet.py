"""Floquet multipliers of a period-n orbit from its n one-period Jacobians, without forming their product.

The multipliers are the eigenvalues of the monodromy matrix M = J_{n-1} ... J_0.  Forming M and taking
its eigenvalues loses every multiplier smaller than eps ||M|| (a period-89 orbit whose multipliers
span 1e-60 ... 1e10 keeps only the large ones).  Here they come from the block-cyclic matrix

    C = [[0, ..., 0, J_{n-1}], [J_0, 0, ..., 0], ..., [0, ..., J_{n-2}, 0]]     (nd x nd),

whose eigenvalues are the n-th roots of the multipliers: C^n is block diagonal with the cyclic
products of the J_j, all similar to M.  The standard (Hessenberg) QR algorithm on C is backward stable
for C, so each root lambda keeps a relative accuracy eps kappa, and mu = lambda^n a relative accuracy
n eps kappa, however small |mu| is.  Kressner ("The periodic QR algorithm is a disguised QR algorithm",
Linear Algebra Appl. 417, 2006) shows the periodic QR algorithm of Bojanczyk, Golub and Van Dooren
(1992) is the QR algorithm applied to this (permuted) cyclic matrix; LAPACK's shifts do not keep
its structure, which costs n d x n d work instead of n d^3 (a 356 x 356 eigenproblem for period 89
in four states: milliseconds) and leaves the n roots of one multiplier separate, regrouped here:
the n roots of one mu share their n-th power to within their error.
"""
from __future__ import annotations

import numpy as np

def product_eigenvalues(jacobians, scale=None) -> np.ndarray:
    """The eigenvalues of J_{n-1} ... J_0 (d of them) from the cyclic matrix of the ``jacobians``;
    ``scale`` (d,): per-state magnitudes to balance each J_j with (S^-1 J S, same eigenvalues)."""
    Js = [np.asarray(J, dtype=float) for J in jacobians]
    n, d = len(Js), Js[0].shape[0]
    if scale is not None:
        s = np.asarray(scale, dtype=float)
        Js = [J / s[:, None] * s[None, :] for J in Js]
    if n == 1:
        return np.linalg.eigvals(Js[0])
    C = np.zeros((n * d, n * d))
    for j, J in enumerate(Js):
        k = (j + 1) % n
        C[k * d:(k + 1) * d, j * d:(j + 1) * d] = J
    lam = np.linalg.eigvals(C)
    return _regroup(lam, n, d)


def _regroup(lam, n: int, d: int) -> np.ndarray:
    """d multipliers from the n d roots ``lam``: repeatedly the largest remaining root's n-th power and
    the n remaining roots whose n-th powers lie nearest it (relative distance), averaged."""
    with np.errstate(over="ignore", under="ignore"):
        logmod = n * np.log(np.maximum(np.abs(lam), 1e-300))
        arg = n * np.angle(lam)
    left = list(np.argsort(-logmod))
    out = []
    for _ in range(d):
        i = left[0]
        dist = [abs(logmod[k] - logmod[i]) + abs(np.angle(np.exp(1j * (arg[k] - arg[i])))) for k in left]
        group = [left[k] for k in np.argsort(dist, kind="stable")[:n]]
        left = [k for k in left if k not in group]
        out.append(np.exp(np.mean(logmod[group])) * np.mean(np.exp(1j * arg[group])) /
                   max(abs(np.mean(np.exp(1j * arg[group]))), 1e-300))
    out = np.array(out)
    return np.where(np.abs(out.imag) <= 1e-14 * np.abs(out), out.real + 0j, out)
