"""Return mapping of perfectly plastic Mohr-Coulomb and Hoek-Brown at integration points (numpy).

Layout and signs
----------------
Stress and strain at n points are (n, 4) **Mandel** vectors [xx, yy, zz, sqrt(2) xy] with
**tension positive** (the FE convention); then sigma : eps = sigma_M . eps_M and tangents are
(n, 4, 4) arrays, symmetric for associated flow only (psi < phi: D - D g n^T D / (n^T D g),
g the flow and n the yield normal; solve with LU, not Cholesky or CG). Plane strain keeps
sigma_zz so that principal stresses are ordered correctly. The yield criteria are written in
ordered principal stresses s1 >= s2 >= s3 with **compression positive** (rock-mechanics
convention); `plane_strain_return` does the conversion.

Algorithm
---------
The return is done in principal stresses (isotropic elasticity, isotropic criteria keep the
principal directions of the trial stress). Mohr-Coulomb with a tension cut-off is a convex
polyhedron of planes in principal space; the return tries every active set of one, two and three
planes and keeps the first that satisfies the Kuhn-Tucker conditions (multipliers >= 0, all
planes satisfied); for associated flow this is the unique closest point in the energy norm, so
edges, the apex and the tension corners are handled without special cases. Hoek-Brown is
smooth except at its two edges (s1 = s2, s2 = s3) and its apex (s1 = s2 = s3 = -s sci/mb):
active sets {main}, {main, edge}, apex are tried in turn with a damped Newton method.

The algorithmic tangent is exact: the principal part is the derivative of the converged local
system (implicit function theorem) and the spin part, for the in-plane principal pair a, b, is
2G (s_a - s_b) / (s_a^tr - s_b^tr) (or its limit when the trial eigenvalues coincide).

Reference: Clausen, Damkilde, Andersen (2006, 2007), "Efficient return algorithms for associated
plasticity with multiple yield planes", IJNME; de Souza Neto, Peric, Owen (2008), ch. 8.
"""
import itertools
import math

import numpy as np

from .materials import HoekBrown, MohrCoulomb, lame

__all__ = ["ELASTIC", "SHEAR", "TENSION", "elastic_tangent", "principal_decomposition",
           "plane_strain_return", "return_map", "mohr_coulomb_principal", "hoek_brown_principal",
           "yield_function", "acoustic_determinant"]

ELASTIC, SHEAR, TENSION = 0, 1, 2
SQ2 = math.sqrt(2.0)


def elastic_tangent(E, nu):
    """(4, 4) Mandel plane-strain elastic matrix: lambda m m^T + 2G I, m = [1, 1, 1, 0]."""
    lam, G = lame(E, nu)
    m = np.array([1.0, 1.0, 1.0, 0.0])
    return lam * np.outer(m, m) + 2.0 * G * np.eye(4)


def principal_decomposition(sig):
    """Eigenvalues and in-plane direction of (n, 4) Mandel tensors.

    Returns
    -------
    lam : (n, 3) array
        [largest in-plane, smallest in-plane, zz] eigenvalues (tension positive if sig is).
    basis : (4, n, 4) array
        Mandel vectors of e_a x e_a, e_b x e_b, e_z x e_z and the unit in-plane shear
        (e_a x e_b + e_b x e_a)/sqrt(2).
    """
    sxx, syy, szz, sxy = sig[:, 0], sig[:, 1], sig[:, 2], sig[:, 3] / SQ2
    mean, half = 0.5 * (sxx + syy), 0.5 * (sxx - syy)
    radius = np.hypot(half, sxy)
    theta = 0.5 * np.arctan2(sxy, half)
    c, s = np.cos(theta), np.sin(theta)
    zero, one = np.zeros_like(c), np.ones_like(c)
    basis = np.stack([
        np.stack([c * c, s * s, zero, SQ2 * c * s], axis=1),
        np.stack([s * s, c * c, zero, -SQ2 * c * s], axis=1),
        np.stack([zero, zero, one, zero], axis=1),
        np.stack([-SQ2 * c * s, SQ2 * c * s, zero, c * c - s * s], axis=1)])
    return np.stack([mean + radius, mean - radius, szz], axis=1), basis


# ------------------------------------------------------------------------------------------
# Mohr-Coulomb with tension cut-off: planes in ordered principal space (compression positive)


def _mohr_coulomb_planes(mat):
    """Rows a_i, b_i, g_i of f_i = a_i . s - b_i <= 0 and flow directions g_i; names."""
    sin_phi, sin_psi = math.sin(math.radians(mat.friction)), math.sin(math.radians(mat.psi))
    kp, kq = (1 + sin_phi) / (1 - sin_phi), (1 + sin_psi) / (1 - sin_psi)
    sc = 2.0 * mat.cohesion * math.sqrt(kp)
    rows = [((1, 0, -kp), sc, (1, 0, -kq), SHEAR), ((1, -kp, 0), sc, (1, -kq, 0), SHEAR),
            ((0, 1, -kp), sc, (0, 1, -kq), SHEAR)]
    if mat.tensile_strength is not None:
        t = mat.tensile_strength
        rows += [((0, 0, -1), t, (0, 0, -1), TENSION), ((0, -1, 0), t, (0, -1, 0), TENSION),
                 ((-1, 0, 0), t, (-1, 0, 0), TENSION)]
    A = np.array([r[0] for r in rows], float)
    b = np.array([r[1] for r in rows], float)
    Gf = np.array([r[2] for r in rows], float)
    kind = np.array([r[3] for r in rows])
    return A, b, Gf, kind


def mohr_coulomb_principal(s, mat):
    """Return ordered principal stresses (compression positive) to the Mohr-Coulomb surface.

    Parameters
    ----------
    s : (n, 3) array
        Trial principal stresses s1 >= s2 >= s3 (Pa, compression positive), all plastic or not.
    mat : MohrCoulomb

    Returns
    -------
    s_new : (n, 3) array
    jac : (n, 3, 3) array
        d s_new / d s_trial.
    mode : (n,) int array
        ELASTIC, SHEAR, TENSION, or SHEAR | TENSION (3) on a shear/tension corner.
    """
    lam, G = lame(mat.E, mat.nu)
    Dp = lam * np.ones((3, 3)) + 2 * G * np.eye(3)
    A, b, Gf, kind = _mohr_coulomb_planes(mat)
    n = s.shape[0]
    scale = mat.cohesion + np.abs(s).max(axis=1)
    tol = 1e-10 * scale
    s_new, jac = s.copy(), np.broadcast_to(np.eye(3), (n, 3, 3)).copy()
    mode = np.zeros(n, dtype=np.int64)
    todo = np.any(s @ A.T - b > tol[:, None], axis=1)
    best_violation, best = np.full(n, np.inf), np.zeros((n, 3))
    for k in (1, 2, 3):
        for J in itertools.combinations(range(len(b)), k):
            if not todo.any():
                return s_new, jac, mode
            J = list(J)
            DG = Dp @ Gf[J].T                      # (3, k) plastic stress directions
            M = A[J] @ DG
            if abs(np.linalg.det(M)) < 1e-12 * np.linalg.norm(M) ** k:
                continue                           # parallel or dependent planes
            Minv = np.linalg.inv(M)
            idx = np.nonzero(todo)[0]
            mult = (s[idx] @ A[J].T - b[J]) @ Minv.T   # (m, k) plastic multipliers (x G)
            cand = s[idx] - mult @ DG.T
            viol = np.max(cand @ A.T - b - tol[idx, None], axis=1)
            ordered = np.all(np.diff(cand, axis=1) <= 1e-9 * scale[idx, None], axis=1)
            # multipliers >= 0, tested on the stress each plane's flow removes (Pa): the
            # multipliers are strains (~ stress / E), so a tolerance in Pa on them let
            # negative ones through for stiff rock (a non-closest edge, a jump in the return)
            corr = mult * np.linalg.norm(DG, axis=0)
            ok = (viol <= 0.0) & ordered & np.all(corr >= -1e-9 * scale[idx, None], axis=1)
            better = viol < best_violation[idx]
            best_violation[idx[better]], best[idx[better]] = viol[better], cand[better]
            hit = idx[ok]
            s_new[hit] = cand[ok]
            jac[hit] = np.eye(3) - DG @ Minv @ A[J]
            mode[hit] = np.bitwise_or.reduce(kind[J])
            todo[hit] = False
    if todo.any():   # non-associated flow beyond the apex (or a degenerate corner)
        apex = _apex(mat)
        s_new[todo] = best[todo] if apex is None else apex
        jac[todo], mode[todo] = 0.0, SHEAR | TENSION
    return s_new, jac, mode


def _apex(mat):
    """Hydrostatic apex of the Mohr-Coulomb + cut-off polyhedron, compression positive (Pa):
    -min(c cot(phi), T); None for Tresca without a cut-off (no apex). Non-associated flow
    (psi < phi) cannot return a trial state beyond the apex by its own flow direction (with
    psi = 0 the flow has no volume change); such states go to the apex with a zero tangent,
    the usual convention (de Souza Neto et al. 2008, sec. 8.2)."""
    tips = [] if mat.friction == 0.0 else [mat.cohesion / math.tan(math.radians(mat.friction))]
    if mat.tensile_strength is not None:
        tips.append(mat.tensile_strength)
    return -min(tips) if tips else None


# ------------------------------------------------------------------------------------------
# Hoek-Brown: smooth surface with two edges and an apex, damped Newton per active set


def _hb_surfaces(x, mb, s, a, which):
    """Value, gradient and Hessian of the normalised HB surfaces (stress / sci).

    which: 0 = main f(s1, s3), 1 = edge f(s1, s2), 2 = edge f(s2, s3).
    """
    i, j = {0: (0, 2), 1: (0, 1), 2: (1, 2)}[which]
    base = np.maximum(mb * x[:, j] + s, 1e-100)
    h = base ** a
    dh = a * mb * base ** (a - 1)
    d2h = a * (a - 1) * mb * mb * base ** (a - 2)
    f = x[:, i] - x[:, j] - h
    g = np.zeros_like(x)
    g[:, i], g[:, j] = 1.0, -1.0 - dh
    H = np.zeros(x.shape + (3,))
    H[:, j, j] = -d2h
    return f, g, H


def _hb_newton(x_tr, Dp, mat, active, iters=60):
    """Closest-point projection on the surfaces `active` for normalised trial states x_tr.

    Returns the projected states, multipliers, d x / d x_tr (n, 3, 3) and a converged mask.
    Only unconverged points are iterated; a fraction-to-the-boundary rule keeps mb x + s > 0.
    """
    mb, s, a = mat.mb, mat.s, mat.a
    n, k = x_tr.shape[0], len(active)
    x_min = -s / mb
    x = np.maximum(x_tr, x_min + 1e-3 * s / mb)    # start inside the power law's domain
    lam = np.zeros((n, k))
    tangent = np.zeros((n, 3, 3))
    converged = np.zeros(n, bool)
    live = np.arange(n)
    for _ in range(iters + 1):
        xl, ll = x[live], lam[live]
        fs, gs, Hs = zip(*(_hb_surfaces(xl, mb, s, a, w) for w in active))
        r_s = xl - x_tr[live] + sum(ll[:, [q]] * gs[q] for q in range(k)) @ Dp
        r = np.concatenate([r_s, np.stack(fs, axis=1)], axis=1)
        jacobian = np.zeros((live.size, 3 + k, 3 + k))
        jacobian[:, :3, :3] = np.eye(3) + np.einsum(
            "ij,njk->nik", Dp, sum(ll[:, q, None, None] * Hs[q] for q in range(k)))
        for q in range(k):
            jacobian[:, :3, 3 + q] = gs[q] @ Dp
            jacobian[:, 3 + q, :3] = gs[q]
        # a singular local Jacobian (e.g. parallel gradients at a corner with this active
        # set) means this active set cannot hold the point: it leaves unconverged and the
        # caller tries the next active set, then the apex
        singular = ~(np.linalg.cond(jacobian) < 1e12)
        done = (np.max(np.abs(r), axis=1) < 1e-12) & ~singular
        if done.any():
            tangent[live[done]] = np.linalg.inv(jacobian[done])[:, :3, :3]
            converged[live[done]] = True
        keep = ~done & ~singular
        live, jacobian, r = live[keep], jacobian[keep], r[keep]
        if live.size == 0:
            break
        step = -np.linalg.solve(jacobian, r[..., None])[..., 0]
        dx = step[:, :3]
        room = x[live] - x_min
        with np.errstate(divide="ignore", invalid="ignore"):
            limit = np.where(dx < 0, 0.9 * room / -dx, np.inf).min(axis=1)
        t = np.minimum(1.0, limit)[:, None]
        x[live] += t * dx
        lam[live] += t * step[:, 3:]
    return x, lam, tangent, converged


def hoek_brown_principal(s, mat):
    """Return ordered principal stresses (compression positive) to the Hoek-Brown surface.

    Same outputs as `mohr_coulomb_principal`. Mode is TENSION where the returned minor principal
    stress is tensile (s3 < 0) or at the apex, SHEAR otherwise.
    """
    lam, G = lame(mat.E, mat.nu)
    Dp = (lam * np.ones((3, 3)) + 2 * G * np.eye(3)) / mat.sci
    x_tr = s / mat.sci
    n = s.shape[0]
    x_new, jac = x_tr.copy(), np.broadcast_to(np.eye(3), (n, 3, 3)).copy()
    mode = np.zeros(n, dtype=np.int64)
    apex = -mat.s / mat.mb
    f_tr = _hb_surfaces(x_tr, mat.mb, mat.s, mat.a, 0)[0]
    todo = (f_tr > 1e-12) | (x_tr[:, 2] < apex)
    for active in ((0,), (0, 1), (0, 2)):
        idx = np.nonzero(todo)[0]
        if idx.size == 0:
            break
        x, mult, tangent, conv = _hb_newton(x_tr[idx], Dp, mat, active)
        tol = 1e-9 * (1.0 + np.abs(x).max(axis=1))
        ok = (conv & np.all(mult >= -tol[:, None], axis=1)
              & (x[:, 0] >= x[:, 1] - tol) & (x[:, 1] >= x[:, 2] - tol))
        hit = idx[ok]
        x_new[hit], jac[hit] = x[ok], tangent[ok]
        mode[hit] = np.where(x[ok, 2] < 0.0, TENSION, SHEAR)
        todo[hit] = False
    x_new[todo], jac[todo], mode[todo] = apex, 0.0, TENSION
    return x_new * mat.sci, jac, mode


def yield_function(s, mat):
    """Yield function value (Pa) at ordered compression-positive principal stresses s (n, 3).

    Mohr-Coulomb: max over its planes (with cut-off). Hoek-Brown: the main surface; where
    s3 is below the tensile apex st (the power law is undefined) it is (s1 - s3) + (st - s3),
    which is positive there and continuous with the surface at the apex.
    """
    if isinstance(mat, MohrCoulomb):
        A, b, _, _ = _mohr_coulomb_planes(mat)
        return np.max(s @ A.T - b, axis=1)
    x = s / mat.sci
    apex = -mat.s / mat.mb
    beyond = x[:, 2] < apex
    f = _hb_surfaces(np.where(beyond[:, None], apex, x), mat.mb, mat.s, mat.a, 0)[0]
    return np.where(beyond, x[:, 0] - x[:, 2] + apex - x[:, 2], f) * mat.sci


def acoustic_determinant(tangent, n_angles=360):
    """Smallest determinant of the acoustic tensor over in-plane band normals (Pa^2).

    Q_ik(n) = n_j C_ijkl n_l for unit normals n = (cos a, sin a), a in [0, pi); a band of
    normal n can form (the incremental problem loses ellipticity) where det Q(n) <= 0
    (Rudnicki & Rice 1975, J. Mech. Phys. Solids 23). Perfectly plastic Mohr-Coulomb with
    associated flow stays on the border (min det Q = 0 at yield); with psi < phi it is past it
    (min det Q < 0), the critical hardening modulus being positive (Vermeer & de Borst 1984,
    Heron 29(3)): the rate problem has no unique solution at such points.

    Parameters
    ----------
    tangent : (n, 4, 4) array
        Mandel plane-strain tangents d sigma / d eps (Pa).

    Returns
    -------
    (n,) array
        min over a of det Q(n(a)).
    """
    a = np.linspace(0.0, math.pi, n_angles, endpoint=False)
    c, s, zero = np.cos(a), np.sin(a), np.zeros_like(a)
    # row k: the Mandel strain of (e_k x n)_sym = the traction map sigma -> (sigma n)_k
    T = np.stack([np.stack([c, zero, zero, s / SQ2], axis=1),
                  np.stack([zero, s, zero, c / SQ2], axis=1)], axis=1)   # (angles, 2, 4)
    Q = np.einsum("aim,nmp,akp->naik", T, tangent, T)
    return np.linalg.det(Q).min(axis=1)


# ------------------------------------------------------------------------------------------
# Tensor layer


def plane_strain_return(sig_trial, mat, tangent=True):
    """Return (n, 4) Mandel trial stresses (tension positive) to the yield surface of `mat`.

    Returns
    -------
    sig : (n, 4) array
        Admissible stress.
    tangent : (n, 4, 4) array or None
        Algorithmic tangent d sig / d eps (Mandel, symmetric for associated flow); None when
        called with tangent=False (a fixed-stiffness iteration needs only the stress).
    mode : (n,) int array
        ELASTIC (0), SHEAR (1), TENSION (2), or 3 for a shear and tension corner.
    """
    lamL, G = lame(mat.E, mat.nu)
    Dp = lamL * np.ones((3, 3)) + 2 * G * np.eye(3)
    eig, basis = principal_decomposition(sig_trial)
    order = np.argsort(eig, axis=1)               # ascending tension = descending compression
    s_tr = -np.take_along_axis(eig, order, axis=1)
    principal = mohr_coulomb_principal if isinstance(mat, MohrCoulomb) else hoek_brown_principal
    s_new, jac_c, mode = principal(s_tr, mat)
    n = sig_trial.shape[0]
    eig_new = np.empty_like(eig)
    np.put_along_axis(eig_new, order, -s_new, axis=1)
    # Un-permute the principal Jacobian (sign flips of stress and trial cancel).
    P = np.zeros((n, 3, 3))
    np.put_along_axis(P, order[:, :, None], 1.0, axis=2)        # P[n, i, order[i]] = 1
    jac = np.einsum("nki,nkl,nlj->nij", P, jac_c, P)
    dep = jac @ Dp
    sig = np.einsum("ni,inj->nj", eig_new, basis[:3])
    if not tangent:
        return sig, None, mode
    tangent = np.einsum("nij,ink,jnl->nkl", dep, basis[:3], basis[:3])
    gap_tr = eig[:, 0] - eig[:, 1]
    safe = gap_tr > 1e-12 * (1.0 + np.abs(eig).max(axis=1))
    spin = np.where(safe, 2 * G * (eig_new[:, 0] - eig_new[:, 1]) / np.where(safe, gap_tr, 1.0),
                    dep[:, 0, 0] - dep[:, 0, 1])
    tangent += spin[:, None, None] * np.einsum("nk,nl->nkl", basis[3], basis[3])
    return sig, tangent, mode


def return_map(sig_trial, mat, tangent=True):
    """Like `plane_strain_return` but elastic points skip the principal-space work.

    Elastic materials (no strength attributes) return the trial stress and the elastic tangent;
    tangent=False returns None for the tangent and skips its computation.
    """
    n = sig_trial.shape[0]
    De = elastic_tangent(mat.E, mat.nu)
    tan = np.broadcast_to(De, (n, 4, 4)).copy() if tangent else None
    mode = np.zeros(n, dtype=np.int64)
    sig = sig_trial.copy()
    if not isinstance(mat, (MohrCoulomb, HoekBrown)):
        return sig, tan, mode
    eig, _ = principal_decomposition(sig_trial)
    s_tr = -np.sort(eig, axis=1)
    f = yield_function(s_tr, mat)
    scale = np.abs(s_tr).max(axis=1) + (mat.cohesion if isinstance(mat, MohrCoulomb)
                                         else mat.sci * mat.s ** mat.a)
    plastic = f > 1e-10 * scale
    if plastic.any():
        sig[plastic], tan_p, mode[plastic] = plane_strain_return(sig_trial[plastic], mat,
                                                                 tangent)
        if tangent:
            tan[plastic] = tan_p
    return sig, tan, mode
