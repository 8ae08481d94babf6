"""Deformable blocks, the zones: constant-strain triangle zones on gridpoints.

A deformable block is meshed into triangular zones whose corners are its own gridpoints (UDEC's
internal discretisation; each block has its own gridpoints, so two blocks meet only through
contacts). This module is the zones' mechanics on their own: the mesh, the explicit step of
the gridpoints, energies, the critical time step and the assembled stiffness (for static
checks). Their coupling to the contacts by a floating frame is ``deformable/component.py``
(``Model(deformable=...)``; docs/mechanics.md, "the floating frame").

Zone mechanics (plane strain, small strain in each zone's co-rotated frame, linear elastic or
Mohr-Coulomb; stress **tension positive**, as in the continuum module, unlike the contacts' sn):

    b_i = (y0_j - y0_k) / 2A,  c_i = (x0_k - x0_j) / 2A    (i, j, k cyclic; A the area, m2)
    F = sum_i x_i (b_i, c_i),  theta = atan2(F_yx - F_xy, F_xx + F_yy)   (polar rotation)
    u_i = R(theta)^T x_i - x0_i                                           (co-rotated, m)
    exx = sum b_i ux_i,  eyy = sum c_i uy_i,  gxy = sum (c_i ux_i + b_i uy_i)
    sxx = (lam + 2 mu) exx + lam eyy,  syy = lam exx + (lam + 2 mu) eyy,  sxy = mu gxy
    force on node i (N/m) = R (-A (b_i sxx + c_i sxy), -A (c_i syy + b_i sxy))

with lam = E nu / ((1 + nu)(1 - 2 nu)), mu = E / (2 (1 + nu)) (Pa). A zone with a strength
(``Zones.strength``: Mohr-Coulomb c, phi, psi and a tension cut-off T; c = +inf, the default,
is elastic and skips this) takes its plastic strain ``Zones.plastic`` off the strain above
(exx - exx_p, eyy - eyy_p, gxy - gxy_p) and its trial stress is returned to the yield surface,
which updates the plastic strain (``zone_plasticity``: in-plane principal stresses, szz
elastic, perfectly plastic; docs/mechanics.md, "Mohr-Coulomb zones"). A rigid rotation of any
size strains nothing; for small rotations this is the linear triangle (``stiffness_matrix``,
elastic). ``Zones.stress`` is reported in the world frame (R s R^T). The mass of each zone is
lumped in thirds on its nodes. The gridpoints move by the same leapfrog and local damping as
the blocks (``components.nodes.damped``). The critical step is 2 / omega_max with
omega_max^2 bounded by Gershgorin's theorem on M^-1 K (the largest row sum of |K| / m), times
``safety`` (a yielding zone is no stiffer). Reference:
Zienkiewicz & Taylor, The Finite Element Method, vol. 1, ch. 6 (the linear triangle);
Crisfield, Non-linear Finite Element Analysis, vol. 1, ch. 7 (co-rotational elements); the
UDEC manual, "deformable blocks".
"""
from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba import njit

from ..step.nodes import damped
from .zone_mesh import check_polygon
from .zone_plasticity import strength_table, yield_zone

__all__ = ["Zones", "mesh_polygon", "mesh_rectangle", "zones_from_mesh", "run_zone_steps",
           "kinetic_energy", "strain_energy", "stiffness_matrix", "critical_dt"]

FIX_X, FIX_Y = 1, 2


class Zones(NamedTuple):
    """The zones and their gridpoints (flat arrays; numba takes the tuple whole).

    x0, x : (ng, 2) float64, m. Gridpoint positions at rest (no strain) and now.
    v, f : (ng, 2) float64, m/s and N/m. Velocities; forces of the last step.
    mass : (ng,) float64, kg/m. Lumped mass; inv_mass its inverse (0 for a fixed point in both
        directions is not used: ``fixity`` holds a point).
    fixity : (ng,) int8. Bit 1 holds x, bit 2 holds y (velocity kept at 0).
    load : (ng, 2) float64, N/m. Applied point loads.
    nodes : (nz, 3) int64. A zone's gridpoints, counter-clockwise.
    bc : (nz, 6) float64, 1/m. b_1, b_2, b_3, c_1, c_2, c_3 (module docstring).
    area : (nz,) float64, m2.
    lame : (nz, 2) float64, Pa. lam, mu.
    stress : (nz, 3) float64, Pa. sxx, syy, sxy of the last step (tension +).
    block : (nz,) int64. The block a zone belongs to.
    strength : (nz, 4) float64. Mohr-Coulomb c (Pa; +inf: elastic), phi (deg), psi (deg),
        T (Pa, at most c / tan phi) (``zone_plasticity``).
    plastic : (nz, 4) float64. Plastic strain exx_p, eyy_p, gxy_p (engineering), ezz_p in the
        zone's co-rotated frame (ezz_p stays 0: in-plane return, ``zone_plasticity``).
    yielded : (nz,) int8. Bits ``zone_plasticity.SHEAR``, ``TENSION`` (failing in the last
        step), ``SHEAR_PAST``, ``TENSION_PAST`` (failed before).
    """

    x0: np.ndarray
    x: np.ndarray
    v: np.ndarray
    f: np.ndarray
    mass: np.ndarray
    inv_mass: np.ndarray
    fixity: np.ndarray
    load: np.ndarray
    nodes: np.ndarray
    bc: np.ndarray
    area: np.ndarray
    lame: np.ndarray
    stress: np.ndarray
    block: np.ndarray
    strength: np.ndarray
    plastic: np.ndarray
    yielded: np.ndarray


def mesh_rectangle(x0, y0, x1, y1, nx, ny):
    """(points (n, 2), triangles (m, 3)): nx x ny cells, each cut into four triangles by its
    centre (no preferred diagonal, so no built-in anisotropy)."""
    if not (nx >= 1 and ny >= 1 and x1 > x0 and y1 > y0):
        raise ValueError(f"mesh_rectangle: need x1 > x0, y1 > y0 and nx, ny >= 1, got "
                         f"{(x0, y0, x1, y1, nx, ny)!r}")
    gx, gy = np.meshgrid(np.linspace(x0, x1, nx + 1), np.linspace(y0, y1, ny + 1), indexing="ij")
    corners = np.column_stack([gx.ravel(), gy.ravel()])
    cx = 0.5 * (gx[:-1, :-1] + gx[1:, 1:])
    cy = 0.5 * (gy[:-1, :-1] + gy[1:, 1:])
    centres = np.column_stack([cx.ravel(), cy.ravel()])
    pts = np.vstack([corners, centres])
    tri = []
    for i in range(nx):
        for j in range(ny):
            a, b = i * (ny + 1) + j, (i + 1) * (ny + 1) + j          # (i, j), (i + 1, j)
            c, d = b + 1, a + 1                                      # (i + 1, j + 1), (i, j + 1)
            m = len(corners) + i * ny + j
            tri += [(a, b, m), (b, c, m), (c, d, m), (d, a, m)]
    return pts, np.asarray(tri, np.int64)


def mesh_polygon(polygon, size):
    """(points, triangles) of a convex polygon (k, 2), counter-clockwise: a fan from its
    centroid, each triangle then split into four at its edges' midpoints until no edge is
    longer than ``size`` (m). Points shared by neighbouring triangles are merged."""
    poly = check_polygon(polygon, size, "mesh_polygon: polygon")
    x, y = poly[:, 0], poly[:, 1]
    cross = x * np.roll(y, -1) - np.roll(x, -1) * y
    area = 0.5 * cross.sum()
    centroid = ((x + np.roll(x, -1)) * cross).sum() / (6 * area), \
        ((y + np.roll(y, -1)) * cross).sum() / (6 * area)
    tris = [np.array([poly[i], poly[(i + 1) % len(poly)], centroid]) for i in range(len(poly))]
    while max(np.max(np.linalg.norm(t - np.roll(t, -1, axis=0), axis=1)) for t in tris) > size:
        new = []
        for t in tris:
            m01, m12, m20 = 0.5 * (t[0] + t[1]), 0.5 * (t[1] + t[2]), 0.5 * (t[2] + t[0])
            new += [np.array([t[0], m01, m20]), np.array([m01, t[1], m12]),
                    np.array([m20, m12, t[2]]), np.array([m01, m12, m20])]
        tris = new
    pts, index, out = [], {}, []
    for t in tris:
        row = []
        for p in t:
            key = (round(p[0], 9), round(p[1], 9))
            if key not in index:
                index[key] = len(pts)
                pts.append(p)
            row.append(index[key])
        out.append(row)
    return np.asarray(pts), np.asarray(out, np.int64)


def zones_from_mesh(points, triangles, E, nu, density, block=None, strength=None) -> Zones:
    """The Zones of a mesh: triangles (m, 3) into points (n, 2), turned counter-clockwise;
    elastic constants E (Pa), nu and density (kg/m3), each a scalar or one per zone;
    ``strength`` None (elastic zones), dict(cohesion=Pa, friction=deg, dilation=deg,
    tensile_strength=Pa) of scalars or one per zone, or a (4,) / (m, 4) table
    (``zone_plasticity.strength_table``)."""
    pts = np.asarray(points, float)
    tri = np.array(triangles, np.int64)
    nz = len(tri)
    E, nu, rho = (np.broadcast_to(np.asarray(v, float), (nz,)) for v in (E, nu, density))
    bad = [(n, v) for n, v in (("E", E), ("density", rho)) if not np.all(np.isfinite(v) & (v > 0))]
    if not np.all((nu > -1.0) & (nu < 0.5)):
        bad.append(("nu", nu))
    if bad:
        n, v = bad[0]
        raise ValueError(f"zones: {n} must be finite and > 0 (nu in (-1, 0.5)), got "
                         f"{v[~np.isfinite(v) | (v <= 0) if n != 'nu' else (v <= -1) | (v >= 0.5)][:3]}")
    p = pts[tri]                                            # (nz, 3, 2)
    twice = ((p[:, 1, 0] - p[:, 0, 0]) * (p[:, 2, 1] - p[:, 0, 1])
             - (p[:, 2, 0] - p[:, 0, 0]) * (p[:, 1, 1] - p[:, 0, 1]))
    cw = twice < 0
    tri[cw] = tri[cw][:, [0, 2, 1]]
    twice = np.abs(twice)
    if not np.all(twice > 0):
        raise ValueError(f"zones: zone(s) {np.flatnonzero(twice <= 0)[:5].tolist()} have no area")
    p = pts[tri]
    xs, ys = p[:, :, 0], p[:, :, 1]
    b = (np.roll(ys, -1, axis=1) - np.roll(ys, -2, axis=1)) / twice[:, None]
    c = (np.roll(xs, -2, axis=1) - np.roll(xs, -1, axis=1)) / twice[:, None]
    area = 0.5 * twice
    lam = E * nu / ((1 + nu) * (1 - 2 * nu))
    mu = E / (2 * (1 + nu))
    mass = np.zeros(len(pts))
    np.add.at(mass, tri.ravel(), np.repeat(rho * area / 3.0, 3))
    if np.any(mass <= 0):
        raise ValueError(f"zones: gridpoint(s) {np.flatnonzero(mass <= 0)[:5].tolist()} belong "
                         "to no zone")
    ng = len(pts)
    table = strength_table(strength, nz, "zones: strength")
    return Zones(pts.copy(), pts.copy(), np.zeros((ng, 2)), np.zeros((ng, 2)), mass, 1.0 / mass,
                 np.zeros(ng, np.int8), np.zeros((ng, 2)), tri, np.column_stack([b, c]), area,
                 np.column_stack([lam, mu]), np.zeros((nz, 3)),
                 np.zeros(nz, np.int64) if block is None else np.asarray(block, np.int64),
                 table, np.zeros((nz, 4)), np.zeros(nz, np.int8))


@njit(cache=True)
def add_zone_forces(z):
    """The zones' forces added to ``z.f`` and their stresses (world frame) to ``z.stress``
    (module docstring: co-rotational constant-strain triangles). A zone with a finite
    cohesion takes its plastic strain off and returns its stress to its Mohr-Coulomb surface
    (``zone_plasticity.yield_zone``: ``z.plastic``, ``z.yielded`` updated); an elastic zone
    (c = +inf) skips both."""
    for e in range(z.nodes.shape[0]):
        fxx = 0.0
        fxy = 0.0
        fyx = 0.0
        fyy = 0.0
        for i in range(3):
            n = z.nodes[e, i]
            bi, ci = z.bc[e, i], z.bc[e, 3 + i]
            fxx += bi * z.x[n, 0]
            fxy += ci * z.x[n, 0]
            fyx += bi * z.x[n, 1]
            fyy += ci * z.x[n, 1]
        th = math.atan2(fyx - fxy, fxx + fyy)
        co, si = math.cos(th), math.sin(th)
        exx = 0.0
        eyy = 0.0
        gxy = 0.0
        for i in range(3):
            n = z.nodes[e, i]
            ux = co * z.x[n, 0] + si * z.x[n, 1] - z.x0[n, 0]      # R^T x - x0
            uy = -si * z.x[n, 0] + co * z.x[n, 1] - z.x0[n, 1]
            bi, ci = z.bc[e, i], z.bc[e, 3 + i]
            exx += bi * ux
            eyy += ci * uy
            gxy += ci * ux + bi * uy
        lam, mu = z.lame[e, 0], z.lame[e, 1]
        plastic = z.strength[e, 0] < np.inf
        if plastic:
            exx -= z.plastic[e, 0]
            eyy -= z.plastic[e, 1]
            gxy -= z.plastic[e, 2]
        sxx = (lam + 2.0 * mu) * exx + lam * eyy
        syy = lam * exx + (lam + 2.0 * mu) * eyy
        sxy = mu * gxy
        if plastic:
            sxx, syy, sxy = yield_zone(z.strength, z.plastic, z.yielded, e, sxx, syy, sxy, lam,
                                       mu)
        # world stress R s R^T
        z.stress[e, 0] = co * co * sxx - 2.0 * co * si * sxy + si * si * syy
        z.stress[e, 1] = si * si * sxx + 2.0 * co * si * sxy + co * co * syy
        z.stress[e, 2] = co * si * (sxx - syy) + (co * co - si * si) * sxy
        a = z.area[e]
        for i in range(3):
            n = z.nodes[e, i]
            bi, ci = z.bc[e, i], z.bc[e, 3 + i]
            gx = -a * (bi * sxx + ci * sxy)                           # in the zone's frame
            gy = -a * (ci * syy + bi * sxy)
            z.f[n, 0] += co * gx - si * gy
            z.f[n, 1] += si * gx + co * gy


@njit(cache=True)
def run_zone_steps(z, nsteps, dt, damping, gx, gy):
    """``nsteps`` explicit steps of the gridpoints: forces (zones, gravity (gx, gy) m/s2 on
    the lumped masses, ``z.load``), local damping, leapfrog; a held direction keeps v = 0."""
    for step in range(nsteps):
        z.f[:] = z.load
        for n in range(z.x.shape[0]):
            z.f[n, 0] += z.mass[n] * gx
            z.f[n, 1] += z.mass[n] * gy
        add_zone_forces(z)
        for n in range(z.x.shape[0]):
            for d in range(2):
                if z.fixity[n] & (1 << d):
                    z.v[n, d] = 0.0
                else:
                    z.v[n, d] += damped(z.f[n, d], z.v[n, d], damping) * z.inv_mass[n] * dt
                z.x[n, d] += z.v[n, d] * dt


def kinetic_energy(z) -> float:
    """J/m."""
    return float(0.5 * (z.mass * (z.v ** 2).sum(axis=1)).sum())


def strain_energy(z) -> float:
    """J/m: 1/2 sum A sigma : eps_e of the zones in their co-rotated frames (eps_e = eps -
    eps_p, the elastic strain)."""
    x = z.x[z.nodes]                                         # (nz, 3, 2)
    b, c = z.bc[:, :3], z.bc[:, 3:]
    F = np.stack([(b * x[:, :, 0]).sum(1), (c * x[:, :, 0]).sum(1),
                  (b * x[:, :, 1]).sum(1), (c * x[:, :, 1]).sum(1)], axis=1)
    th = np.arctan2(F[:, 2] - F[:, 1], F[:, 0] + F[:, 3])
    co, si = np.cos(th)[:, None], np.sin(th)[:, None]
    x0 = z.x0[z.nodes]
    ux = co * x[:, :, 0] + si * x[:, :, 1] - x0[:, :, 0]
    uy = -si * x[:, :, 0] + co * x[:, :, 1] - x0[:, :, 1]
    exx, eyy = (b * ux).sum(1) - z.plastic[:, 0], (c * uy).sum(1) - z.plastic[:, 1]
    gxy = (c * ux + b * uy).sum(1) - z.plastic[:, 2]
    lam, mu = z.lame[:, 0], z.lame[:, 1]
    w = 0.5 * lam * (exx + eyy) ** 2 + mu * (exx ** 2 + eyy ** 2 + 0.5 * gxy ** 2)
    return float((w * z.area).sum())


def stiffness_matrix(z):
    """The assembled small-strain stiffness K (2 ng x 2 ng, scipy CSR, N/m per m), dofs (x, y)
    per gridpoint: for small displacements the explicit forces are f = -K u (checked in
    tests/test_zones.py)."""
    from scipy.sparse import coo_matrix

    nz = len(z.area)
    B = np.zeros((nz, 3, 6))
    b, c = z.bc[:, :3], z.bc[:, 3:]
    B[:, 0, 0::2] = b
    B[:, 1, 1::2] = c
    B[:, 2, 0::2] = c
    B[:, 2, 1::2] = b
    lam, mu = z.lame[:, 0], z.lame[:, 1]
    D = np.zeros((nz, 3, 3))
    D[:, 0, 0] = D[:, 1, 1] = lam + 2 * mu
    D[:, 0, 1] = D[:, 1, 0] = lam
    D[:, 2, 2] = mu
    Ke = z.area[:, None, None] * np.einsum("eki,ekl,elj->eij", B, D, B)
    dof = np.stack([2 * z.nodes, 2 * z.nodes + 1], axis=2).reshape(nz, 6)
    rows = np.repeat(dof, 6, axis=1).ravel()
    cols = np.tile(dof, (1, 6)).ravel()
    ng = len(z.mass)
    return coo_matrix((Ke.ravel(), (rows, cols)), shape=(2 * ng, 2 * ng)).tocsr()


def critical_dt(z, safety=0.5) -> float:
    """``safety`` x 2 / omega_max, omega_max^2 <= max over dofs of sum_j |K_ij| / m_i
    (Gershgorin on M^-1 K), s."""
    if not 0 < safety <= 1:
        raise ValueError(f"safety must be in (0, 1], got {safety!r}")
    K = stiffness_matrix(z)
    rows = np.asarray(abs(K).sum(axis=1)).ravel()
    w2 = float((rows / np.repeat(z.mass, 2)).max())
    return safety * 2.0 / math.sqrt(w2)
