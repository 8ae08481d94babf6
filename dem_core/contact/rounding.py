"""Rounded corners (UDEC's corner rounding): a defined contact normal at corners.

With ``Model(rounding=d)`` (d > 0, m) every corner of every block is a circular arc of radius
d tangent to the two edges that meet there; with ``rounding="auto"`` (the default) each block
has its own d (``block_roundings``: 1 % of the median edge, less on a sliver). The arc's centre (the corner's *centre*) is fixed
in the block, on the corner's bisector, at distance d from both edge lines::

    c = v + d (m1 + m2) / (1 + m1 . m2)        v the vertex, m1, m2 the inward unit normals
                                               of its two edges (a right angle: c = v + d (1, 1))

The rounded block is the polygon of its corner centres (its *core*: the block's edges moved
inward by d) grown by d in every direction, so two rounded blocks A and B are in contact when
their cores are closer than d_A + d_B, along the line of the cores' nearest points (below,
2 d stands for d_A + d_B). A vertex contact
(A's corner against B's face e, which runs from B's vertex e to vertex f) takes:

    x      = A's corner centre (world), C_e, C_f B's corner centres at the face's ends
    t      = (C_f - C_e) / |C_f - C_e|,  s = (x - C_e) . t
    0 <= s <= |C_f - C_e|:   n = B's inward face normal,    u_n = (C_e - x) . n - 2 d
    s > |C_f - C_e|:         past the face's end: if x is in the corner's wedge,
                             (x - C_f) . t_next <= 0 (t_next along B's next face),
                             n = (C_f - x) / |C_f - x|,     u_n = |C_f - x| - 2 d
                             (corner against corner: the line of the two centres),
                             else the next face's normal and distance
    s < 0:                   the same at the face's start with the previous face
    corner against corner, but B's corner centre C projects onto one of A's two core faces
    at the vertex (beyond x): B's corner against that face of A,
                             x = the foot of C on it, n = A's outward face normal,
                             u_n = (C - x) . n - 2 d

n is the unit normal from A into B, u_n the opening (m, > 0 open, < 0 overlap) between the
rounded shapes, x the nearest point of A's core. n turns continuously: where the face ends
(s = |C_f - C_e|) the line of centres is the face's normal, at the far side of the corner's
wedge it is the next face's, and where B's corner reaches A's face it is that face's. The force
acts on A's rounded boundary, at x + d_A n; the shear displacement is measured between x and
B's point of the contact (``Contacts.point_b``, moved across the normal from x when the
contact slips or opens), along t = (-n_y, n_x). The same pair of touching corners gives one
contact whichever block the search calls A (``detection``: touch points and normals).

Which contacts: those of a vertex against a face (``Contacts.face`` = 0: made by the search).
The two contacts of a shared edge (``face`` = 1) keep their bisector normal: two faces lying
on one another touch along their straight parts, where rounding changes nothing. d = 0 is the
sharp-cornered model, bit for bit: the kernels read only the radius then.

References: Cundall, P. A. (1988), Formulation of a three-dimensional distinct element model,
Part I, Int. J. Rock Mech. Min. Sci. 25(3), 107-116 (contact detection and the normal at
corners); Itasca, UDEC manual, Theory and Background (block corner rounding).
UDEC's rounding length is given as the distance from a corner to its tangent points; here d
is the arc's radius (the two are equal at a right angle; at a 120 degree Voronoi corner the
tangent points lie d tan 30 deg = 0.58 d from the corner).
"""
from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba import njit

from ..step.kinematics import body_point, rotate, unrotate

__all__ = ["Rounding", "no_rounding", "rounding_bundle", "corner_centres", "largest_rounding",
           "is_rounded", "rounded_contact", "corner_centre", "follow_faces", "MAX_ROUNDING_FRACTION",
           "AUTO_FRACTION", "block_roundings", "rounded_rows"]

# a rounding radius must leave every edge at least this fraction of the straight part the
# sharpest rounding it can take would leave (``largest_rounding``): no edge vanishes
MAX_ROUNDING_FRACTION = 0.5
# ``rounding="auto"``: this fraction of the median edge length (UDEC advises about 1 %)
AUTO_FRACTION = 0.01


class Rounding(NamedTuple):
    """The corner geometry the contact kernels read (empty arrays: sharp corners).

    radius : float, m. The largest arc radius (0: sharp corners, the arrays are empty).
    centre : (nv, 2) float64, m. Each vertex's corner centre in its block's frame (relative
        to the centroid at theta = 0, like ``BlockProps.local_vertices``).
    next, prev : (nv,) int64. The next and previous vertex of the same block (CCW ring).
    arc : (nv,) float64, m. The arc radius at each vertex: its block's d (one radius per
        block, so a block's core is its edges moved in by that d).
    """

    radius: float
    centre: np.ndarray
    next: np.ndarray
    prev: np.ndarray
    arc: np.ndarray


def no_rounding() -> Rounding:
    """Sharp corners: the kernels take the vertex-against-face geometry."""
    return Rounding(0.0, np.zeros((0, 2)), np.zeros(0, np.int64), np.zeros(0, np.int64),
                    np.zeros(0))


def _rings(offsets):
    """(next, prev) vertex of each vertex in its block's CCW ring, (nv,) int64 each."""
    nv = int(offsets[-1])
    idx = np.arange(nv, dtype=np.int64)
    block = np.repeat(np.arange(len(offsets) - 1), np.diff(offsets))
    first, last = offsets[block], offsets[block + 1] - 1
    nxt = np.where(idx == last, first, idx + 1)
    prv = np.where(idx == first, last, idx - 1)
    return nxt.astype(np.int64), prv.astype(np.int64)


def _inward_normals(local, nxt):
    """(nv, 2) inward unit normal of the edge that starts at each vertex (CCW polygons)."""
    e = local[nxt] - local
    e /= np.hypot(e[:, 0], e[:, 1])[:, None]
    return np.column_stack([-e[:, 1], e[:, 0]])


def corner_centres(offsets, local, radius) -> np.ndarray:
    """(nv, 2) corner centres (m, block frame): v + d (m1 + m2) / (1 + m1 . m2), at distance
    d from the lines of both edges at each vertex (module docstring); ``radius`` one d for
    every vertex or (nv,) one per vertex."""
    offsets = np.asarray(offsets, np.int64)
    local = np.asarray(local, np.float64)
    nxt, prv = _rings(offsets)
    m_out = _inward_normals(local, nxt)          # the edge leaving each vertex
    m_in = m_out[prv]                            # the edge arriving at it
    dot = (m_out * m_in).sum(axis=1)
    d = np.broadcast_to(np.asarray(radius, np.float64), dot.shape)
    return local + (d / (1.0 + dot))[:, None] * (m_out + m_in)


def _edge_limits(offsets, local):
    """(nv,) for the edge leaving each vertex: L / (cot(a1 / 2) + cot(a2 / 2)), the radius at
    which rounding both its corners leaves no straight part (a1, a2 the interior angles at
    its ends)."""
    nxt, prv = _rings(offsets)
    e = local[nxt] - local
    length = np.hypot(e[:, 0], e[:, 1])
    t = e / length[:, None]
    cos_a = -(t[prv] * t).sum(axis=1)                  # interior angle at each vertex
    half = 0.5 * np.arccos(np.clip(cos_a, -1.0, 1.0))
    cot = np.cos(half) / np.maximum(np.sin(half), 1e-300)
    return length / (cot + cot[nxt])


def largest_rounding(offsets, local):
    """(d_max, block): the largest radius with which every edge keeps a straight part, i.e.
    min over edges of L / (cot(a1 / 2) + cot(a2 / 2)) (a1, a2 the interior angles at its
    ends), and the block that sets it."""
    offsets = np.asarray(offsets, np.int64)
    limit = _edge_limits(offsets, np.asarray(local, np.float64))
    j = int(np.argmin(limit))
    block = int(np.searchsorted(offsets, j, side="right") - 1)
    return float(limit[j]), block


def block_roundings(offsets, local, fraction=None):
    """(nb,) radius of each block for ``rounding="auto"`` (m): ``fraction`` (None:
    ``AUTO_FRACTION``) of the median edge length of all the blocks, d (UDEC's advice: about
    1 % of the typical edge), lowered on a block

    - whose sharpest corner (interior angle a) would stand clear of a face it is placed on by
      more than a right angle's corner does, d (sqrt 2 - 1): to d (sqrt 2 - 1) / (1/sin(a/2) -
      1) (UDEC's rounding length, the distance from a corner to its tangent points, bounds the
      same clearance; a 20 deg corner rounded with d would hang 4.8 d clear and its block
      drop onto the next);
    - whose edges the radius would consume: to ``MAX_ROUNDING_FRACTION`` of the block's
      largest rounding (``largest_rounding``).

    So slivers and wedges keep their edges and their contacts, and every other block gets d."""
    fraction = AUTO_FRACTION if fraction is None else fraction
    offsets = np.asarray(offsets, np.int64)
    local = np.asarray(local, np.float64)
    nxt, prv = _rings(offsets)
    e = local[nxt] - local
    length = np.hypot(e[:, 0], e[:, 1])
    d = fraction * float(np.median(length))
    limit = np.minimum.reduceat(_edge_limits(offsets, local), offsets[:-1])
    t = e / length[:, None]
    half = 0.5 * np.arccos(np.clip(-(t[prv] * t).sum(axis=1), -1.0, 1.0))
    clear = 1.0 / np.maximum(np.sin(half), 1e-300) - 1.0       # clearance over radius
    worst = np.maximum.reduceat(clear, offsets[:-1])
    right = math.sqrt(2.0) - 1.0
    by_corner = d * np.minimum(1.0, right / np.maximum(worst, 1e-300))
    return np.minimum(by_corner, MAX_ROUNDING_FRACTION * limit)


def rounding_bundle(props, radius) -> Rounding:
    """The Rounding of the blocks of ``props`` (BlockProps): arcs of ``radius`` (m) at every
    corner, or with ``"auto"`` each block's ``block_roundings``. ValueError naming the value
    if it is not "auto" or a finite length >= 0, or a length too large for the blocks (above
    ``MAX_ROUNDING_FRACTION`` of ``largest_rounding``)."""
    offsets, local = props.vertex_offsets, props.local_vertices
    if isinstance(radius, str) and radius == "auto":
        per_block = block_roundings(offsets, local)
        if per_block.size == 0 or not per_block.max() > 0.0:
            return no_rounding()
        arc = np.repeat(per_block, np.diff(offsets))
        nxt, prv = _rings(offsets)
        return Rounding(float(arc.max()), corner_centres(offsets, local, arc), nxt, prv, arc)
    try:
        d = float(radius)
    except (TypeError, ValueError):
        raise ValueError(f"rounding must be 'auto' or a length in m (>= 0), got "
                         f"{radius!r}") from None
    if isinstance(radius, bool) or not math.isfinite(d) or d < 0.0:
        raise ValueError(f"rounding must be 'auto' or a finite length >= 0 m, got {radius!r}")
    if d == 0.0:
        return no_rounding()
    d_max, block = largest_rounding(offsets, local)
    if d > MAX_ROUNDING_FRACTION * d_max:
        raise ValueError(
            f"rounding {radius!r} m is too large for the blocks: at most "
            f"{MAX_ROUNDING_FRACTION * d_max:.4g} m ({MAX_ROUNDING_FRACTION:g} x "
            f"{d_max:.4g} m, the radius at which an edge of block {block} would vanish)")
    nxt, prv = _rings(offsets)
    return Rounding(d, corner_centres(offsets, local, d), nxt, prv,
                    np.full(len(local), d))


@njit(cache=True, inline="always")
def is_rounded(rnd, c, k):
    """True if contact k of ``c`` takes the rounded geometry: rounding on and a vertex of A
    against a known face of B (``Contacts.face`` = 0)."""
    return rnd.radius > 0.0 and c.face[k] == 0 and c.vertex_a[k] >= 0 and c.edge_b[k] >= 0


def rounded_rows(c, rnd) -> np.ndarray:
    """Rows of the live contacts of ``c`` that take the rounded geometry (``is_rounded``)."""
    n = c.n
    if rnd.radius <= 0.0:
        return np.zeros(0, np.int64)
    return np.flatnonzero((c.face[:n] == 0) & (c.vertex_a[:n] >= 0) & (c.edge_b[:n] >= 0))


@njit(cache=True, inline="always")
def _past_corner(rnd, x, y, corner, far, sign, fx, fy):
    """B-frame (n_x, n_y, distance, corner) of the point (x, y) past the end of B's face at
    the corner ``corner``, ``far`` the other end of B's face on the other side of that corner
    (sign +1: the next face, -1: the previous one), (fx, fy) the face's own normal: the line
    to the corner's centre while (x, y) is in the corner's wedge (and ``corner``), else the
    other face's normal and distance (and -1)."""
    cx, cy = rnd.centre[corner, 0], rnd.centre[corner, 1]
    ux, uy = rnd.centre[far, 0] - cx, rnd.centre[far, 1] - cy
    if (x - cx) * ux + (y - cy) * uy > 0.0:            # past the wedge: the other face
        lu = sign * math.hypot(ux, uy)
        nx, ny = -uy / lu, ux / lu
        return nx, ny, (cx - x) * nx + (cy - y) * ny, -1
    rx, ry = cx - x, cy - y
    r = math.hypot(rx, ry)
    if r == 0.0:                                       # (on the centre: the face's normal)
        return fx, fy, 0.0, -1
    return rx / r, ry / r, r, corner


@njit(cache=True, inline="always")
def _face_of_a(rnd, x, y, va, w, cx, cy, sign):
    """A-frame foot and distance of B's corner centre (cx, cy) on A's core edge from ``va``
    to ``w`` (sign +1: A's next vertex, -1: its previous one) if it projects past ``va`` onto
    that edge: (qx, qy, n_x, n_y, distance) with n A's outward normal (into B); else a
    distance of -inf. (x, y): A's corner centre at ``va``."""
    ux, uy = rnd.centre[w, 0] - x, rnd.centre[w, 1] - y
    lu2 = ux * ux + uy * uy
    t = ((cx - x) * ux + (cy - y) * uy) / lu2
    if t <= 0.0 or t >= 1.0:
        return x, y, 0.0, 0.0, -math.inf
    lu = sign * math.sqrt(lu2)
    nx, ny = uy / lu, -ux / lu                         # outward for a CCW block
    return x + t * ux, y + t * uy, nx, ny, (cx - x) * nx + (cy - y) * ny


# More than ten arguments: inlined into the contact update, they are the scalars the caller
# has already computed (grouping them would only rename them)
@njit(cache=True, inline="always")
def _corner_on_face_of_a(rnd, s, a, b, va, corner, xc, yc, nx, ny, dist):
    """Corner against corner (A's centre (xc, yc) against B's ``corner``, normal (nx, ny),
    distance ``dist``, world): if B's corner centre projects onto one of A's two core edges
    at ``va`` beyond ``va``, the nearest features are B's corner and that face of A: returns
    A's foot of B's centre on the face, A's face normal and the distance; else the inputs."""
    bx, by = body_point(s.pos, s.rot, b, rnd.centre[corner, 0], rnd.centre[corner, 1])
    cx, cy = unrotate(s.rot, a, bx - s.pos[a, 0], by - s.pos[a, 1])     # in A's frame
    x, y = rnd.centre[va, 0], rnd.centre[va, 1]
    q1x, q1y, m1x, m1y, d1 = _face_of_a(rnd, x, y, va, rnd.next[va], cx, cy, 1.0)
    q2x, q2y, m2x, m2y, d2 = _face_of_a(rnd, x, y, va, rnd.prev[va], cx, cy, -1.0)
    if d2 > d1:
        q1x, q1y, m1x, m1y, d1 = q2x, q2y, m2x, m2y, d2
    if d1 == -math.inf:
        return xc, yc, nx, ny, dist
    qx, qy = body_point(s.pos, s.rot, a, q1x, q1y)
    mx, my = rotate(s.rot, a, m1x, m1y)
    return qx, qy, mx, my, d1


@njit(cache=True, inline="always")
def corner_centre(rnd, s, a, va):
    """World position (m) of the centre of A's corner at vertex ``va``: the point of A the
    shear displacement of a rounded contact is measured from (fixed in A; where B's corner
    touches A's face, ``rounded_contact``'s nearest point slides with B and would measure no
    slip at all)."""
    return body_point(s.pos, s.rot, a, rnd.centre[va, 0], rnd.centre[va, 1])


@njit(cache=True, inline="always")
def rounded_contact(rnd, s, a, b, va, e):
    """A's rounded corner at vertex ``va`` against B's rounded boundary at its face ``e``
    (first vertex index), at the pose ``s`` (BlockState); returns (x_c, y_c, n_x, n_y, u_n):
    the nearest point of A's core (world, m: A's corner centre, or the foot of B's corner
    centre on A's face next to it), the unit normal from A into B and the opening between the
    rounded shapes (m, > 0 open). Module docstring: the equations."""
    xc, yc = body_point(s.pos, s.rot, a, rnd.centre[va, 0], rnd.centre[va, 1])
    x, y = unrotate(s.rot, b, xc - s.pos[b, 0], yc - s.pos[b, 1])     # in B's frame
    f = rnd.next[e]
    ex, ey = rnd.centre[e, 0], rnd.centre[e, 1]
    tx, ty = rnd.centre[f, 0] - ex, rnd.centre[f, 1] - ey
    length = math.hypot(tx, ty)
    tx, ty = tx / length, ty / length
    along = (x - ex) * tx + (y - ey) * ty
    nx, ny = -ty, tx                                   # B's inward face normal
    corner = -1
    if along > length:
        nx, ny, dist, corner = _past_corner(rnd, x, y, f, rnd.next[f], 1.0, nx, ny)
    elif along < 0.0:
        nx, ny, dist, corner = _past_corner(rnd, x, y, e, rnd.prev[e], -1.0, nx, ny)
    else:
        dist = (ex - x) * nx + (ey - y) * ny
    nx, ny = rotate(s.rot, b, nx, ny)
    if corner >= 0:
        xc, yc, nx, ny, dist = _corner_on_face_of_a(rnd, s, a, b, va, corner, xc, yc, nx, ny,
                                                    dist)
    return xc, yc, nx, ny, dist - rnd.arc[va] - rnd.arc[e]


@njit(cache=True)
def follow_faces(c, s, rnd):
    """At a contact search: every rounded contact whose corner has slid past the end of its
    face of B and out of that corner's wedge (where ``rounded_contact`` already takes the next
    face's normal and distance) is moved onto that next face (``edge_b``, ``normal_b``; its
    stresses and history kept), as often as it has passed faces. The search's tests (the
    point still on its face, ``detection``) then judge the face the contact really touches,
    and a corner that has slid off a block altogether is let go."""
    for k in range(c.count[0]):
        if not is_rounded(rnd, c, k):
            continue
        a, b = c.block_a[k], c.block_b[k]
        xc, yc = body_point(s.pos, s.rot, a, rnd.centre[c.vertex_a[k], 0],
                            rnd.centre[c.vertex_a[k], 1])
        x, y = unrotate(s.rot, b, xc - s.pos[b, 0], yc - s.pos[b, 1])     # in B's frame
        e = c.edge_b[k]
        for _ in range(rnd.next.shape[0]):
            f = rnd.next[e]
            ex, ey = rnd.centre[e, 0], rnd.centre[e, 1]
            tx, ty = rnd.centre[f, 0] - ex, rnd.centre[f, 1] - ey
            along = (x - ex) * tx + (y - ey) * ty
            if along > tx * tx + ty * ty:                  # past the face's end
                g = rnd.next[f]
                ux, uy = rnd.centre[g, 0] - rnd.centre[f, 0], rnd.centre[g, 1] - rnd.centre[f, 1]
                if (x - rnd.centre[f, 0]) * ux + (y - rnd.centre[f, 1]) * uy <= 0.0:
                    break                                  # in the corner's wedge
                e = f
            elif along < 0.0:                              # before the face's start
                g = rnd.prev[e]
                ux, uy = rnd.centre[g, 0] - ex, rnd.centre[g, 1] - ey
                if (x - ex) * ux + (y - ey) * uy <= 0.0:
                    break
                e = g
            else:
                break
        if e != c.edge_b[k]:
            f = rnd.next[e]
            tx, ty = rnd.centre[f, 0] - rnd.centre[e, 0], rnd.centre[f, 1] - rnd.centre[e, 1]
            ln = math.hypot(tx, ty)
            c.edge_b[k] = e
            c.normal_b[k, 0], c.normal_b[k, 1] = -ty / ln, tx / ln      # B's inward normal
