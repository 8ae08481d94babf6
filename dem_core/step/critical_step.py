"""The critical time step from the largest eigenvalue of the contact stiffness
(``Model(step_estimate="eigen")``).

Central differences are stable for a linear system when ``dt < 2 / omega_max``, with
``omega_max^2`` the largest eigenvalue of ``M^-1 K`` (M the inertial masses and moments, K the
stiffness of the free degrees of freedom). ``step.frequency_bound`` bounds it block by block
(Gershgorin, a factor 2 for the neighbours): safe but, on a bonded Voronoi slope, about 2.8
times too high in omega^2 (1.67 in the step). Here omega_max^2 is computed instead.

Sources: the stability limit of the central-difference (leapfrog) scheme, dt < 2 / omega_max
for an undamped linear system, is derived in T. Belytschko, W. K. Liu and B. Moran (2000),
Nonlinear Finite Elements for Continua and Structures, Wiley, ch. 6 (stability of explicit
time integration); the block-by-block bound uses the circle theorem of S. Gershgorin (1931),
"Uber die Abgrenzung der Eigenwerte einer Matrix", Izv. Akad. Nauk SSSR, Ser. Mat. 7,
749-754: every eigenvalue lies within a row's diagonal entry plus the sum of the magnitudes
of its off-diagonal entries.

Stiffness of contact k (rigid blocks A, B; 3 dofs each: u, v, rotation w)::

    K_k = L kn g_n g_n^T + L ks g_t g_t^T,   g = [-e, -(r_A x e), e, (r_B x e)]

with e the unit normal n (g_n) or tangent t (g_t), r_A, r_B the lever arms from the centroids
to the contact point x_A (``contacts`` module docstring; with rounded corners the point of A's
arc and the normal of the rounded shapes, ``contact.rounding``) and r x e = r_x e_y - r_y e_x
(2-D).
Every listed contact counts at full stiffness, open, slipping or broken: adding stiffness only
raises eigenvalues, so the estimate is an upper bound of the tangent stiffness's between two
contact searches (new contacts appear only at a search, which recomputes the step). The two
halves of a shared edge are counted as two point contacts (lumped): the lumped matrix exceeds
the linear element's (``forces.edge_correction``) in the Loewner order, so this also bounds
``edge_elements``.

``largest_omega2`` solves ``M^-1/2 K M^-1/2 x = lambda x`` matrix-free (a numba product over
the contacts, one pass each) with ARPACK's Lanczos (``scipy.sparse.linalg.eigsh``) from a fixed
start; the converged Ritz value is raised by its tolerance (ARPACK's residual bound on it).
tests/test_critical_step.py checks it against a closed form and against the stability limit
of central differences. Cost: a few tens of contact passes (``benchmarks/critical_step_cost.py``;
the measured times: docs/performance.md, "The step from the largest eigenvalue, with
settling").
"""
from __future__ import annotations

import numpy as np
from numba import njit
from scipy.sparse.linalg import ArpackNoConvergence, LinearOperator, eigsh

from ..contact.rounding import is_rounded, no_rounding, rounded_contact
from .kinematics import contact_normal, rotate
from .state import FIX_ROT, FIX_X, FIX_Y

__all__ = ["contact_geometry", "largest_omega2", "TOL", "SMALL"]

TOL = 1e-4          # relative tolerance of the Ritz value (ARPACK's ``tol``)
SMALL = 60          # dofs up to which the matrix is built and solved densely


@njit(cache=True)
def contact_geometry(c, s, rnd):
    """Each live contact's unit normal (nc, 2) and lever arms from A's and B's centroids to
    the contact point x_A (nc, 2) each, m, at the current state; a rounded contact's (``rnd``
    the corners' Rounding) are its normal and the touch on A's arc, where its force acts
    (``forces.contact_update``)."""
    n = c.count[0]
    normal = np.empty((n, 2))
    arm_a = np.empty((n, 2))
    arm_b = np.empty((n, 2))
    for k in range(n):
        a, b = c.block_a[k], c.block_b[k]
        if is_rounded(rnd, c, k):
            xf, yf, nx, ny, _ = rounded_contact(rnd, s, a, b, c.vertex_a[k], c.edge_b[k])
            d = rnd.arc[c.vertex_a[k]]
            x, y = xf + d * nx - s.pos[a, 0], yf + d * ny - s.pos[a, 1]
        else:
            nx, ny = contact_normal(s, a, b, c.face[k], c.normal_b[k, 0], c.normal_b[k, 1])
            x, y = rotate(s.rot, a, c.point_a[k, 0], c.point_a[k, 1])
        normal[k, 0], normal[k, 1] = nx, ny
        arm_a[k, 0], arm_a[k, 1] = x, y                     # x_A - pos[A]
        arm_b[k, 0] = x + s.pos[a, 0] - s.pos[b, 0]         # x_A - pos[B]
        arm_b[k, 1] = y + s.pos[a, 1] - s.pos[b, 1]
    return normal, arm_a, arm_b


@njit(cache=True)
def _product(x, block_a, block_b, kn_l, ks_l, normal, arm_a, arm_b, scale):
    """y = D K D x, D = diag(scale) (M^-1/2 on the free dofs, 0 on the held ones)."""
    z = x * scale
    y = np.zeros_like(x)
    for k in range(block_a.shape[0]):
        a, b = block_a[k], block_b[k]
        nx, ny = normal[k, 0], normal[k, 1]
        for e in range(2):
            ex, ey, kk = (nx, ny, kn_l[k]) if e == 0 else (-ny, nx, ks_l[k])
            wa = arm_a[k, 0] * ey - arm_a[k, 1] * ex
            wb = arm_b[k, 0] * ey - arm_b[k, 1] * ex
            # relative displacement of B against A at the contact point, along e
            d = (z[3 * b] * ex + z[3 * b + 1] * ey + z[3 * b + 2] * wb
                 - z[3 * a] * ex - z[3 * a + 1] * ey - z[3 * a + 2] * wa)
            f = kk * d
            y[3 * b] += f * ex
            y[3 * b + 1] += f * ey
            y[3 * b + 2] += f * wb
            y[3 * a] -= f * ex
            y[3 * a + 1] -= f * ey
            y[3 * a + 2] -= f * wa
    return y * scale


def largest_omega2(c, s, p, rnd=None) -> float:
    """omega_max^2 (1/s^2) of the free blocks on their contacts (module docstring; ``rnd``
    the corners' Rounding, None: sharp corners); 0.0 for a model with no contact or no free
    dof. The Lanczos start is the same vector every time, so
    the value is a function of the state alone (a saved and reloaded model steps as before)."""
    n = c.count[0]
    if n == 0:
        return 0.0
    normal, arm_a, arm_b = contact_geometry(c, s, no_rounding() if rnd is None else rnd)
    free = np.column_stack([(p.fixity & FIX_X) == 0, (p.fixity & FIX_Y) == 0,
                            (p.fixity & FIX_ROT) == 0]) & (p.active > 0)[:, None]
    scale = np.where(free, np.sqrt(np.column_stack([p.inv_mass, p.inv_mass, p.inv_inertia])),
                     0.0).ravel()
    args = (c.block_a[:n], c.block_b[:n], c.kn[:n] * c.length[:n], c.ks[:n] * c.length[:n],
            normal, arm_a, arm_b, scale)
    if not scale.any():
        return 0.0
    size = scale.size
    if size <= SMALL:                      # ARPACK needs room: a few blocks are solved densely
        dense = np.column_stack([_product(col, *args) for col in np.eye(size)])
        lam = float(np.linalg.eigvalsh(0.5 * (dense + dense.T))[-1])
    else:
        op = LinearOperator((size, size), matvec=lambda x: _product(x, *args), dtype=np.float64)
        v0 = scale / np.linalg.norm(scale)
        try:
            lams = eigsh(op, k=1, which="LA", tol=TOL, v0=v0, return_eigenvectors=False)
        except ArpackNoConvergence:        # rare: a larger Krylov space
            lams = eigsh(op, k=1, which="LA", tol=TOL, v0=v0, ncv=min(size - 1, 60),
                         maxiter=100 * size, return_eigenvectors=False)
        lam = float(lams[0]) * (1.0 + TOL)
    if not np.isfinite(lam) or lam < 0:
        raise ValueError(f"the contact stiffness gave a largest eigenvalue of {lam!r}: a "
                         "contact's kn or ks is negative or not finite")
    return lam
