"""Deformable blocks: the zones coupled to the contacts by a floating frame.

A deformable block keeps its rigid pose (``BlockState.pos``, ``theta``: the frame; the
contacts, the search and the integration of the blocks are unchanged) and carries the
displacement u of its zones' gridpoints in that frame (``zones.py`` mechanics, each block
meshed by ``zone_mesh.mesh_polygons`` in its body frame). Everything here is in the block's axes,
relative to its centroid (the frame of ``BlockProps.local_vertices``).

Where a contact acts on a deformable block's boundary, and how the zones' displacement moves
its points: ``boundary_points.py``.

Forces (``add_deformable``, after every other force of the step). The frame gets every
contact force whole, at its point (``forces.contact_update``, as for a rigid block). The
zones' gridpoints get, in the block's axes, their zones' forces (``zones.add_zone_forces``:
elastic, or Mohr-Coulomb with a tension cut-off where a zone has a strength)
and each contact's force F = L (sn n + ts t) spread over its stretch with the same weights,
F w_i on B's gridpoints and -F w_i on A's (a uniform stress over the stretch: the consistent
nodal forces, so the work of the contact force on the zones is F . u_bar). Of that load the
zones keep only its non-rigid part (mean axes of the floating frame):

    f_i <- f_i - m_i (a + alpha k x (x_i - c)),    a = sum f / M,    alpha = M_c / I_c

(c the gridpoints' mass centre, M_c the load's moment about it, I_c = sum m_i |x_i - c|^2):
each gridpoint loses the frame's acceleration due to the load the zones carry, so the zones'
load is self-equilibrated in force and moment (to round-off) whatever the frame does. A body
force in proportion to mass (gravity, a centrifuge g-level, ``Model.apply_load``) has no
non-rigid part and strains nothing by itself; forces that act on the frame only (applied
loads, water, cables, liners, the reaction of a prescribed velocity) are taken as spread like
the mass. A held block's zones instead take its whole load, their weight (the step's
``Gravity`` bundle, in the block's axes) included.

Motion (``advance_zones``, called by the step's one integration,
``step.integration.advance_nodes``, right after the blocks move). The gridpoints move by local
damping and leapfrog (``step.nodes.damped``) with the blocks' dt, alpha, kick and
kinetic-damping stop (``step.relaxation``), and the mass-weighted mean displacement and
(linearised) mean rotation about the centroid are taken out of u and of its velocity, so u
stays a pure deformation and the frame's pose stays the body's mass centre and mean rotation:

    u_i <- u_i - ubar,   ubar = sum m_i u_i / M
    u_i <- u_i - phi k x x0_i,   phi = sum m_i (x0_i x u_i) / sum m_i |x0_i|^2   (same for v)

The frame's rotation is slow in the quasi-static runs this is for: the centrifugal and
Coriolis terms of the rotating frame (omega^2 r, 2 omega x v) are left out.

Units per metre out of plane: m, m/s, N/m, kg/m, Pa.
"""
from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit

from ..step.kinematics import contact_normal, unrotate
from .zone_mesh import mesh_polygons
from .zone_plasticity import elastic_table
from .zones import add_zone_forces, stiffness_matrix, zones_from_mesh
from ..contact.boundary_points import contact_sides, spread
from .held import box_sides
from ..step.nodes import damped

__all__ = ["Deformable", "no_deformable", "deformable_bundle", "add_deformable",
           "advance_zones", "zone_kinetic_energy", "gridpoint_stiffness",
           "kinetic_energy", "strain_energy"]


class Deformable(NamedTuple):
    """The zones of every deformable block (``ng`` gridpoints, ``nz`` zones); all empty (and
    ``point_offsets`` of length 0) when no block is deformable.

    x0 : (ng, 2) float64, m. Gridpoint rest position in its block's frame (centroid origin).
    x : (ng, 2) float64, m. Its position now in the block's frame: x0 + u.
    v : (ng, 2) float64, m/s. Velocity du/dt (block axes, half steps).
    f : (ng, 2) float64, N/m. Non-rigid part of the gridpoint's load in the last step.
    mass : (ng,) float64, kg/m. Lumped (real) mass; inv_mass the inertial inverse (mass
        scaling may make it smaller).
    stiff : (ng,) float64, N/m per m. Largest row sum of |K| over the gridpoint's two dofs
        (the zones' Gershgorin bound; ``gridpoint_stiffness`` adds the contacts).
    nodes, bc, area, lame, stress : the zones (``zones.Zones``: stress tension +, reported
        in the block's axes).
    zone_block : (nz,) int64. The block of each zone.
    point_offsets : (nb + 1,) int64. Gridpoints of block b: point_offsets[b] to [b + 1]
        (an empty range for a rigid block).
    block_vertices : (nb + 1,) int64, vertices : (nv, 2) float64, m. ``BlockProps``'
        vertex_offsets and local_vertices (every block's faces).
    edge_offsets : (nv + 1,) int64, edge_points : (ne,) int64. The boundary gridpoints of
        the face that starts at polygon vertex j (``BlockProps.local_vertices``), in order from
        vertex j to the next: edge_points[edge_offsets[j]:edge_offsets[j + 1]] (empty for a
        rigid block's faces); the first is vertex j's own gridpoint.
    held : (nb,) int8. 1 for a deformable block held by a boundary condition (``Model.fix``,
        ``set_velocity``): its frame is held whole and its zones take its whole load.
    point_held : (ng,) int8. Bits FIX_X, FIX_Y: the gridpoint's held directions (block axes).
    box_sides : (ng,) int8. Bits 1, 2, 4, 8: the gridpoint lay on the left, right, bottom, top
        side of the model's bounding box at the start (``BOX_SIDES``).
    strength, plastic, yielded : the zones' Mohr-Coulomb strength (nz, 4), plastic strain
        (nz, 4) and failure bits (nz,) (``zones.Zones``, ``zone_plasticity``; c = +inf:
        an elastic zone).
    """

    x0: np.ndarray
    x: np.ndarray
    v: np.ndarray
    f: np.ndarray
    mass: np.ndarray
    inv_mass: np.ndarray
    stiff: np.ndarray
    nodes: np.ndarray
    bc: np.ndarray
    area: np.ndarray
    lame: np.ndarray
    stress: np.ndarray
    zone_block: np.ndarray
    point_offsets: np.ndarray
    block_vertices: np.ndarray
    vertices: np.ndarray
    edge_offsets: np.ndarray
    edge_points: np.ndarray
    strength: np.ndarray
    plastic: np.ndarray
    yielded: np.ndarray
    held: np.ndarray
    point_held: np.ndarray
    box_sides: np.ndarray

    @staticmethod
    def fields_of_old_files(have) -> dict:
        """The fields a model file from before them lacks (``have``: the fields it holds),
        as they were then: elastic zones (``io``)."""
        nz = len(have["area"])
        return {"strength": elastic_table(nz), "plastic": np.zeros((nz, 4)),
                "yielded": np.zeros(nz, np.int8),
                "held": np.zeros(len(have["point_offsets"]) - 1, np.int8),
                "point_held": np.zeros(len(have["x0"]), np.int8),
                "box_sides": np.zeros(len(have["x0"]), np.int8)}


def no_deformable() -> Deformable:
    """The empty bundle: every block rigid (the kernels do nothing and read nothing)."""
    v2, v1, i1 = np.zeros((0, 2)), np.zeros(0), np.zeros(0, np.int64)
    return Deformable(v2, v2.copy(), v2.copy(), v2.copy(), v1, v1.copy(), v1.copy(),
                      np.zeros((0, 3), np.int64), np.zeros((0, 6)), v1.copy(), np.zeros((0, 2)),
                      np.zeros((0, 3)), i1, i1.copy(), i1.copy(), np.zeros((0, 2)), i1.copy(),
                      i1.copy(), np.zeros((0, 4)), np.zeros((0, 4)),
                      np.zeros(0, np.int8), np.zeros(0, np.int8), np.zeros(0, np.int8),
                      np.zeros(0, np.int8))


def is_empty(zones) -> bool:
    """No deformable block: ``zones`` None (the rigid step's form) or an empty bundle."""
    return zones is None or zones.point_offsets.shape[0] == 0


def deformable_bundle(props, size, E, nu, density, strength=None, origin=None,
                      bounds=None) -> Deformable:
    """The zones of the blocks whose ``size`` (nb,) is finite (zone size, m; NaN: rigid),
    meshed by ``zone_mesh.mesh_polygons`` (gmsh) in their body frames, with E (Pa), nu and
    density (kg/m^3), each (nb,), and ``strength`` (nb, 4), a block's zones' Mohr-Coulomb row
    [c Pa, phi deg, psi deg, T Pa] (``zone_plasticity.strength_table``; None: elastic).
    ``origin`` (nb, 2), m: the blocks' centroids in the world (their frames are not turned
    yet) and ``bounds`` (x0, y0, x1, y1), m: the model's box, to mark the gridpoints on it
    (``box_sides``; none without them)."""
    off = props.vertex_offsets
    nb = len(off) - 1
    nv = int(off[-1])
    pts_all, tri_all, blk_all, E_z, nu_z, rho_z = [], [], [], [], [], []
    table = elastic_table(nb) if strength is None else np.asarray(strength, float)
    point_offsets = np.zeros(nb + 1, np.int64)
    edge_lists = [[] for _ in range(nv)]
    soft = np.flatnonzero(np.isfinite(size))
    meshes = mesh_polygons([props.local_vertices[off[b]:off[b + 1]] for b in soft],
                           [float(size[b]) for b in soft])
    mesh_of = dict(zip(soft.tolist(), meshes))
    ng = 0
    for b in range(nb):
        if b in mesh_of:
            pts, tri, faces = mesh_of[b]
            for j, face in enumerate(faces):
                edge_lists[off[b] + j] = (face + ng).tolist()
            pts_all.append(pts)
            tri_all.append(tri + ng)
            blk_all.append(np.full(len(tri), b, np.int64))
            for lst, val in ((E_z, E), (nu_z, nu), (rho_z, density)):
                lst.append(np.full(len(tri), float(val[b])))
            ng += len(pts)
        point_offsets[b + 1] = ng
    if ng == 0:
        return no_deformable()
    z = zones_from_mesh(np.vstack(pts_all), np.vstack(tri_all), np.concatenate(E_z),
                        np.concatenate(nu_z), np.concatenate(rho_z),
                        block=np.concatenate(blk_all), strength=table[np.concatenate(blk_all)])
    K = abs(stiffness_matrix(z))
    rows = np.asarray(K.sum(axis=1)).ravel().reshape(-1, 2).max(axis=1)
    edge_offsets = np.zeros(nv + 1, np.int64)
    edge_offsets[1:] = np.cumsum([len(e) for e in edge_lists])
    edge_points = np.asarray([g for e in edge_lists for g in e], np.int64)
    return Deformable(z.x0, z.x, z.v, z.f, z.mass, z.inv_mass.copy(), rows, z.nodes, z.bc, z.area,
                      z.lame, z.stress, z.block, point_offsets, np.asarray(off, np.int64).copy(),
                      np.asarray(props.local_vertices, np.float64).copy(), edge_offsets, edge_points,
                      z.strength, z.plastic, z.yielded, np.zeros(nb, np.int8), np.zeros(ng, np.int8),
                      box_sides(z.x0, point_offsets, origin, bounds))


# parallel=True without a prange, as ``forces.add_contact_forces``: numba's parallel pipeline
# removes the bundle copies the inlined helpers leave (and their reference counting), about
# 5x faster here; it still runs on the calling thread
@njit(cache=True, parallel=True)
def add_deformable(zones, c, s, p, gravity):
    """The zones' forces (module docstring): elastic and contact forces on the gridpoints, then
    per block the rigid part of that load taken off, or, for a held block, its weight
    (``gravity``, the step's ``Gravity`` bundle) added. The gridpoints move in
    ``advance_zones``."""
    if zones is None:                    # rigid blocks: numba leaves the rest out
        return
    if zones.point_offsets.shape[0] == 0:
        return
    zones.f[:] = 0.0
    add_zone_forces(zones)
    for k in range(c.count[0]):
        a, b = c.block_a[k], c.block_b[k]
        ea, qa0, qa1, eb, qb0, qb1 = contact_sides(zones, k, c, s)
        if ea < 0 and eb < 0:
            continue
        nx, ny = contact_normal(s, a, b, c.face[k], c.normal_b[k, 0], c.normal_b[k, 1])
        L = c.length[k]
        fx, fy = L * (c.sn[k] * nx - c.ts[k] * ny), L * (c.sn[k] * ny + c.ts[k] * nx)
        if ea >= 0:
            lx, ly = unrotate(s.rot, a, fx, fy)
            spread(zones.f, zones, ea, qa0, qa1, lx, ly, -1.0)
        if eb >= 0:
            lx, ly = unrotate(s.rot, b, fx, fy)
            spread(zones.f, zones, eb, qb0, qb1, lx, ly, 1.0)
    wx, wy = 0.0, 0.0                    # gravity in the world, m/s^2
    for r in range(gravity.accel.shape[0]):
        wx, wy = gravity.accel[r, 0], gravity.accel[r, 1]
    for blk in range(zones.point_offsets.shape[0] - 1):
        g0, g1 = zones.point_offsets[blk], zones.point_offsets[blk + 1]
        if g0 < g1 and p.active[blk]:
            if zones.held[blk] != 0:
                gx, gy = unrotate(s.rot, blk, wx, wy)
                _weight(zones, g0, g1, gx, gy)
            else:
                _non_rigid(zones, g0, g1)


# (parallel=True: as ``add_deformable``)
@njit(cache=True, parallel=True)
def advance_zones(zones, p, dt, kick, alpha):
    """The gridpoints' step from the forces ``add_deformable`` left in ``f`` (module
    docstring): local damping ``alpha``, velocities kicked by ``kick`` s (dt, or dt / 2 on the
    step after a kinetic-damping stop, as the blocks), positions by v ``dt``; then the mean
    motion removed (not in a held block). Called by the step's integration
    (``step.integration.advance_nodes``)."""
    if zones is None:                    # rigid blocks: numba leaves the rest out
        return
    for blk in range(zones.point_offsets.shape[0] - 1):
        g0, g1 = zones.point_offsets[blk], zones.point_offsets[blk + 1]
        if g0 < g1 and p.active[blk]:
            if zones.held[blk] != 0:
                _move_held(zones, g0, g1, dt, kick, alpha)
            else:
                _move_block(zones, g0, g1, dt, kick, alpha)


@njit(cache=True, inline="always")
def _weight(zones, g0, g1, gx, gy):
    """A held block's gridpoints take their weight (gx, gy in block axes, m/s^2)."""
    for i in range(g0, g1):
        zones.f[i, 0] += zones.mass[i] * gx
        zones.f[i, 1] += zones.mass[i] * gy


@njit(cache=True, inline="always")
def _move_held(zones, g0, g1, dt, kick, alpha):
    """A held block's gridpoints (its frame does not move) under their whole load;
    ``point_held`` directions stay at rest."""
    for i in range(g0, g1):
        for q in range(2):
            if zones.point_held[i] & (1 << q):
                zones.v[i, q] = 0.0
            else:
                zones.v[i, q] += (damped(zones.f[i, q], zones.v[i, q], alpha) * zones.inv_mass[i]
                                  * kick)
            zones.x[i, q] += zones.v[i, q] * dt


@njit(cache=True, inline="always")
def _non_rigid(zones, g0, g1):
    """Take the rigid part off a free block's gridpoint load: f_i -= m_i (a + alpha k x
    (x_i - c)) (module docstring)."""
    x, f, m = zones.x, zones.f, zones.mass
    mt, cx, cy, fx, fy = 0.0, 0.0, 0.0, 0.0, 0.0
    for i in range(g0, g1):
        mt += m[i]
        cx += m[i] * x[i, 0]
        cy += m[i] * x[i, 1]
        fx += f[i, 0]
        fy += f[i, 1]
    cx /= mt
    cy /= mt
    mc, ic = 0.0, 0.0
    for i in range(g0, g1):
        rx, ry = x[i, 0] - cx, x[i, 1] - cy
        mc += rx * f[i, 1] - ry * f[i, 0]
        ic += m[i] * (rx * rx + ry * ry)
    ax, ay, al = fx / mt, fy / mt, mc / ic
    for i in range(g0, g1):
        rx, ry = x[i, 0] - cx, x[i, 1] - cy
        f[i, 0] -= m[i] * (ax - al * ry)
        f[i, 1] -= m[i] * (ay + al * rx)


@njit(cache=True, inline="always")
def _move_block(zones, g0, g1, dt, kick, alpha):
    """A free block's gridpoints: leapfrog, then the mean motion taken out of u and v."""
    for i in range(g0, g1):
        for q in range(2):
            zones.v[i, q] += damped(zones.f[i, q], zones.v[i, q], alpha) * zones.inv_mass[i] * kick
            zones.x[i, q] += zones.v[i, q] * dt
    _remove_rigid(zones, g0, g1, True)
    _remove_rigid(zones, g0, g1, False)


@njit(cache=True, inline="always")
def _remove_rigid(zones, g0, g1, displacement):
    """Take the mass-weighted mean translation and linearised rotation about the centroid out
    of u = x - x0 (``displacement``) or out of v."""
    m, x0 = zones.mass, zones.x0
    mt, ux, uy = 0.0, 0.0, 0.0
    for i in range(g0, g1):
        qx = zones.x[i, 0] - x0[i, 0] if displacement else zones.v[i, 0]
        qy = zones.x[i, 1] - x0[i, 1] if displacement else zones.v[i, 1]
        mt += m[i]
        ux += m[i] * qx
        uy += m[i] * qy
    ux /= mt
    uy /= mt
    num, den = 0.0, 0.0
    for i in range(g0, g1):
        qx = (zones.x[i, 0] - x0[i, 0] if displacement else zones.v[i, 0]) - ux
        qy = (zones.x[i, 1] - x0[i, 1] if displacement else zones.v[i, 1]) - uy
        num += m[i] * (x0[i, 0] * qy - x0[i, 1] * qx)
        den += m[i] * (x0[i, 0] * x0[i, 0] + x0[i, 1] * x0[i, 1])
    phi = num / den
    q = zones.x if displacement else zones.v
    for i in range(g0, g1):
        q[i, 0] -= ux - phi * x0[i, 1]
        q[i, 1] -= uy + phi * x0[i, 0]


@njit(cache=True)
def gridpoint_stiffness(zones, c, s):
    """(ng,) N/m per m: the zones' row bound plus 2 (kn + ks) L of every contact whose force
    reaches the gridpoint (Gershgorin: the spring couples it to the other block)."""
    out = zones.stiff.copy()
    tmp = np.zeros((out.shape[0], 2))
    for k in range(c.count[0]):
        kk = 2.0 * (c.kn[k] + c.ks[k]) * c.length[k]
        ea, qa0, qa1, eb, qb0, qb1 = contact_sides(zones, k, c, s)
        if ea >= 0:
            spread(tmp, zones, ea, qa0, qa1, kk, kk, 1.0)
        if eb >= 0:
            spread(tmp, zones, eb, qb0, qb1, kk, kk, 1.0)
    out += tmp[:, 0]
    return out


@njit(cache=True)
def zone_kinetic_energy(zones, active):
    """J/m: 1/2 sum v^2 / inv_mass over the gridpoints of active blocks (inertial masses, as
    ``step.free_kinetic_energy``): the zones' share of the kinetic-damping peak test."""
    ke = 0.0
    for blk in range(zones.point_offsets.shape[0] - 1):
        if active[blk]:
            for i in range(zones.point_offsets[blk], zones.point_offsets[blk + 1]):
                ke += ((zones.v[i, 0] * zones.v[i, 0] + zones.v[i, 1] * zones.v[i, 1])
                       / zones.inv_mass[i])
    return 0.5 * ke


def kinetic_energy(zones) -> float:
    """J/m: 1/2 sum m v^2 of the gridpoints' motion relative to the frame (real masses)."""
    return float(0.5 * (zones.mass * (zones.v ** 2).sum(axis=1)).sum())


def strain_energy(zones) -> float:
    """J/m: the zones' elastic energy (``zones.strain_energy``)."""
    if zones.area.shape[0] == 0:
        return 0.0
    from .zones import strain_energy as zone_energy
    return zone_energy(zones)
