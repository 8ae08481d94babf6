"""The state bundles: what the time step reads and writes, as named tuples of flat arrays.

Numba takes a bundle whole (a ``typing.NamedTuple`` of arrays), so a kernel's signature names a
few bundles instead of dozens of arrays. Arrays are updated in place; a bundle is never
rebuilt during a step. ``nb`` blocks, ``nv`` vertices. Units SI per unit thickness (plane
strain): masses kg/m, moments of inertia kg m^2/m, forces N/m, moments N m/m. Angles CCW, rad.

- ``BlockState``: what changes every step (pose, velocities, forces).
- ``BlockProps``: what is constant within a stage (masses, fixity, geometry).
- ``contacts.Contacts``: the contact arrays with their stresses (``contacts.py``).
- ``CrackLog``: every bond failure so far.
- ``Integrator``: time step, damping and the kinetic-damping memory.
- ``Parallel``: the threaded contact kernel's chunks and scratch (``parallel.py``); empty: serial.
- one bundle per optional force component (``components/``), empty when the scene has none.
"""
from __future__ import annotations

import copy
from typing import NamedTuple

import numpy as np
from numba import njit

from .kinematics import update_rotation

__all__ = ["BlockProps", "BlockState", "CrackLog", "Integrator", "FIX_X", "FIX_Y", "FIX_ROT",
           "polygon_inertia", "block_props", "state_at_rest", "copy_bundle", "Parallel",
           "no_parallel"]

# Bits of BlockProps.fixity: a set bit means that velocity component is prescribed.
FIX_X, FIX_Y, FIX_ROT = 1, 2, 4


def polygon_inertia(local_vertices: np.ndarray) -> float:
    """Polar second moment of area about the centroid, m^4 (vertices relative to the centroid)."""
    x, y = local_vertices[:, 0], local_vertices[:, 1]
    xn, yn = np.roll(x, -1), np.roll(y, -1)
    cross = x * yn - xn * y
    return float((cross * (x * x + x * xn + xn * xn + y * y + y * yn + yn * yn)).sum() / 12.0)


class BlockProps(NamedTuple):
    """What does not change during a stage.

    vertex_offsets : (nb + 1,) int64. CSR into ``local_vertices``.
    local_vertices : (nv, 2) float64, m. CCW, relative to the centroid at theta = 0.
    mass, inertia : (nb,) float64. Real mass kg/m and polar moment kg m^2/m (gravity uses these).
    inv_mass, inv_inertia : (nb,) float64. Inverse *inertial* mass and moment (mass scaling
        may make these smaller than 1/mass; a prescribed component's values are unused).
    radius : (nb,) float64, m. Largest centroid-vertex distance.
    fixity : (nb,) int8. Bits FIX_X, FIX_Y, FIX_ROT: that velocity component is prescribed.
    velocity_bc : (nb, 3) float64. Prescribed (vx, vy, omega) in m/s, rad/s.
    active : (nb,) int8. 0 once a block has been removed (excavated).
    surface_material : (nv,) int32. Material id of the block face that starts at each vertex
        (the flaw, joint or region boundary it lies on), -1 for a free face. A contact found by
        the search takes the material of the face it touches.
    """

    vertex_offsets: np.ndarray
    local_vertices: np.ndarray
    mass: np.ndarray
    inertia: np.ndarray
    inv_mass: np.ndarray
    inv_inertia: np.ndarray
    radius: np.ndarray
    fixity: np.ndarray
    velocity_bc: np.ndarray
    active: np.ndarray
    surface_material: np.ndarray


class BlockState(NamedTuple):
    """What changes every step.

    pos : (nb, 2) float64, m. Centroid.
    theta : (nb,) float64, rad. CCW rotation from the initial orientation.
    rot : (nb, 2) float64. (cos theta, sin theta), kept with theta (``kinematics``).
    rot_half : (nb, 2) float64. (cos theta/2, sin theta/2): the common normal of two faces.
    vel : (nb, 2) float64, m/s. Centroid velocity at the last half step (leapfrog).
    omega : (nb,) float64, rad/s. Angular velocity at the last half step.
    force : (nb, 3) float64. Unbalanced force (N/m) and moment (N m/m) of the last step,
        before damping.
    pos0 : (nb, 2), theta0 : (nb,). Pose at the start (displacements are measured from here).
    pos_search : (nb, 2), theta_search : (nb,). Pose at the last contact search.
    work : (nb, 2) float64, J/m. Energy account of each block so far (``output.energy``):
        [:, 0] work done on the model through its prescribed velocity components, [:, 1]
        energy its local damping and kinetic-damping stops took out.
    """

    pos: np.ndarray
    theta: np.ndarray
    rot: np.ndarray
    rot_half: np.ndarray
    vel: np.ndarray
    omega: np.ndarray
    force: np.ndarray
    pos0: np.ndarray
    theta0: np.ndarray
    pos_search: np.ndarray
    theta_search: np.ndarray
    work: np.ndarray

    @staticmethod
    def fields_of_old_files(held) -> dict:
        """A model file from before the energy account: nothing done so far (``io``)."""
        return {"work": np.zeros((held["pos"].shape[0], 2))}


class CrackLog(NamedTuple):
    """Bond failures in the order they happened.

    rows : (cap, 7) float64. [time s, x m, y m, mode (1 tension, 2 shear), block_a, block_b,
        material id]; rows past ``cap`` are counted but not kept.
    count : (1,) int64. Failures so far.
    """

    rows: np.ndarray
    count: np.ndarray


class Integrator(NamedTuple):
    """Settings of the explicit scheme and the kinetic-damping memory.

    dt : float, s. Time step. damping : float. Local damping coefficient alpha in [0, 1).
    half_margin : float, m. A block that moved this far since the last search stops the run
        for a new search (inf: never).
    kinetic_interval : int. Steps between kinetic-energy checks (0: kinetic damping off).
    kinetic : (8,) float64. The kinetic-damping memory (``relaxation``: the energy at the last
        check, J/m, inertial masses; steps since it; 1 when the motion was just stopped, the
        next velocity update is half a step; the largest energy checked since the last stop;
        stops; late stops; the check interval now, 0 for ``kinetic_interval``; checks).
    edge_elements : bool. The two contacts of each shared edge act as one linear element
        (``forces.edge_correction``); False: the kernels never read ``Contacts.partner``.
    kinetic_adaptive : bool. A late kinetic-damping stop halves the check interval, and
        the checks' spacing is spread (``relaxation``).
    """

    dt: float
    damping: float
    half_margin: float
    kinetic_interval: int
    kinetic: np.ndarray
    edge_elements: bool = False
    kinetic_adaptive: bool = False


def block_props(bs, density) -> BlockProps:
    """Masses from ``density`` (kg/m^3, scalar or (nb,)) and the polygons of a BlockSystem."""
    nb = bs.n_blocks
    rho = np.broadcast_to(np.asarray(density, dtype=np.float64), (nb,))
    if not np.all(np.isfinite(rho)) or np.any(rho <= 0):
        bad = int(np.flatnonzero(~(np.isfinite(rho) & (rho > 0)))[0])
        raise ValueError(f"density must be finite and > 0 kg/m^3; block {bad} has {rho[bad]!r}")
    off = np.asarray(bs.vertex_offsets, dtype=np.int64)
    local = np.empty_like(bs.vertices, dtype=np.float64)
    inertia_area = np.empty(nb)
    radius = np.empty(nb)
    for b in range(nb):
        v = bs.vertices[off[b]:off[b + 1]] - bs.centroid[b]
        local[off[b]:off[b + 1]] = v
        inertia_area[b] = polygon_inertia(v)
        radius[b] = np.sqrt((v * v).sum(axis=1).max())
    if np.any(bs.area <= 0) or not np.all(np.isfinite(local)):
        bad = int(np.flatnonzero(bs.area <= 0)[0]) if np.any(bs.area <= 0) else -1
        raise ValueError(f"block {bad} has non-positive area or non-finite vertices")
    mass = rho * bs.area
    inertia = rho * inertia_area
    return BlockProps(vertex_offsets=off, local_vertices=local, mass=mass, inertia=inertia,
                      inv_mass=1.0 / mass, inv_inertia=1.0 / inertia, radius=radius,
                      fixity=np.zeros(nb, np.int8), velocity_bc=np.zeros((nb, 3)),
                      active=np.ones(nb, np.int8),
                      surface_material=np.full(len(local), -1, np.int32))


def state_at_rest(centroid) -> BlockState:
    """Blocks at their centroids, unrotated and still."""
    c = np.array(centroid, dtype=np.float64)
    nb = c.shape[0]
    rot, rot_half = np.zeros((nb, 2)), np.zeros((nb, 2))
    update_rotation(np.zeros(nb), rot, rot_half)
    return BlockState(pos=c.copy(), theta=np.zeros(nb), rot=rot, rot_half=rot_half,
                      vel=np.zeros((nb, 2)),
                      omega=np.zeros(nb), force=np.zeros((nb, 3)), pos0=c.copy(),
                      theta0=np.zeros(nb), pos_search=c.copy(), theta_search=np.zeros(nb),
                      work=np.zeros((nb, 2)))


def copy_bundle(bundle):
    """A deep copy of a bundle (every array copied)."""
    return type(bundle)(*[copy.deepcopy(v) for v in bundle])


class Parallel(NamedTuple):
    """The threaded kernel's chunks, owners, scratch and shared-block table; all empty: serial.

    first : (chunks + 1,) int64. Chunk j is the contacts first[j] <= k < first[j + 1].
    owner : (nb,) int64. The chunk that holds all of block i's contacts, or -1 (shared).
    own_offsets : (chunks + 1,) int64, own_blocks : int64. The blocks each chunk owns.
    shared : (ns,) int64. The shared blocks (contacts in several chunks, or none).
    offsets : (ns + 1,) int64, entries : int64. The contacts of each shared block in contact
        order; an entry is 2 k for block A of contact k (force subtracted), 2 k + 1 for B.
    work : (nc, 4) float64. Force on B (N/m) and point (m) of contact k, written when k
        touches a shared block or fails.
    edge_work : (nc, 4) float64, or (0, 4) without edge elements. The edge's share of contact
        k (``forces.edge_correction``: force on B, N/m; moments on B and on A, N m/m), written
        when k touches a shared block and its partner lies in the same chunk.
    events : (nc,) int8. The failure event (1 tension, 2 shear) of contact k this step, set by
        the chunk, read and cleared by the crack-log pass; 0 otherwise.
    failures : (chunks,) int64. Each chunk's bond failures this step.
    """

    first: np.ndarray
    owner: np.ndarray
    own_offsets: np.ndarray
    own_blocks: np.ndarray
    shared: np.ndarray
    offsets: np.ndarray
    entries: np.ndarray
    work: np.ndarray
    edge_work: np.ndarray
    events: np.ndarray
    failures: np.ndarray


@njit(cache=True)
def no_parallel() -> Parallel:
    """The empty bundle: the serial kernel (``forces.add_contact_forces``, which also builds it
    inside numba)."""
    e = np.zeros(0, np.int64)
    return Parallel(e, e, e, e, e, e, e, np.zeros((0, 4)), np.zeros((0, 4)),
                    np.zeros(0, np.int8), e)
