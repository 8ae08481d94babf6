"""Where a contact acts on a deformable block's boundary, and how the zones' displacement
moves its points (deformable blocks; the zones and their coupling: ``deformable/component.py``).

Where a contact acts on a block's boundary. Each polygon face of a deformable block is split
by the zone mesher (``zone_mesh.mesh_polygons``) into ceil(L / h) equal boundary segments, so
a body point's segment is found in O(1) from its position along the face. A contact acts on a *stretch* of the face its point
lies on: a face contact anchored at a vertex (the two halves of a shared edge: each is the
vertex at one end against the other block's face, ``contacts.initial_contacts``) covers its
length L from that vertex along the face, i.e. the half of the shared edge next to it, on
both blocks; any other contact (a vertex found by the search against a face, a contact
anchored midway) acts at its point (a stretch of length 0). The face is A's face at A's
vertex (the one whose outward normal is the contact's), B's face ``edge_b``, else the
nearest face of the block to the point.

Geometry. A contact point p (body frame) of a deformable block is at

    x = pos + R(theta) (p + u_bar),    u_bar = sum_i w_i u_i

u_bar the mean displacement over the contact's stretch (for a point, the linear
interpolation on its segment): w_i the integrals of the boundary's linear shape functions
over the stretch, divided by its length (sum w_i = 1).

Units per metre out of plane: m. Everything in the block's axes, relative to its centroid.
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit

from .contacts import ANCHOR_A, ANCHOR_B, ANCHOR_MID
from ..step.kinematics import body_point, rotate, unrotate

__all__ = ["deformed_points", "rest_points", "contact_sides", "spread"]


@njit(cache=True, inline="always")
def _face_param(zones, e, px, py):
    """Where body point (px, py) projects on face ``e`` (from vertex e to the next vertex of
    its block), in segments from the face's start, clamped to [0, segments]."""
    e0, e1 = zones.edge_offsets[e], zones.edge_offsets[e + 1]
    g0, g1 = zones.edge_points[e0], zones.edge_points[e1 - 1]
    ex, ey = zones.x0[g1, 0] - zones.x0[g0, 0], zones.x0[g1, 1] - zones.x0[g0, 1]
    t = ((px - zones.x0[g0, 0]) * ex + (py - zones.x0[g0, 1]) * ey) / (ex * ex + ey * ey)
    return min(max(t, 0.0), 1.0) * (e1 - e0 - 1)


@njit(cache=True, inline="always")
def _nearest_face(zones, blk, px, py):
    """The face of deformable block ``blk`` (its first vertex's index) nearest to its body
    point (px, py)."""
    best, face = np.inf, -1
    for e in range(zones.block_vertices[blk], zones.block_vertices[blk + 1]):
        g0, g1 = (zones.edge_points[zones.edge_offsets[e]],
                  zones.edge_points[zones.edge_offsets[e + 1] - 1])
        ex, ey = zones.x0[g1, 0] - zones.x0[g0, 0], zones.x0[g1, 1] - zones.x0[g0, 1]
        rx, ry = px - zones.x0[g0, 0], py - zones.x0[g0, 1]
        t = min(max((rx * ex + ry * ey) / (ex * ex + ey * ey), 0.0), 1.0)
        dx, dy = rx - t * ex, ry - t * ey
        if dx * dx + dy * dy < best:
            best, face = dx * dx + dy * dy, e
    return face


@njit(cache=True, inline="always")
def _face_direction(zones, blk, e, toward_end):
    """Unit direction (block frame) along face e of block ``blk``: from its start to its end
    (``toward_end``) or back."""
    f = e + 1 if e + 1 < zones.block_vertices[blk + 1] else zones.block_vertices[blk]
    ex, ey = (zones.vertices[f, 0] - zones.vertices[e, 0],
              zones.vertices[f, 1] - zones.vertices[e, 1])
    ln = np.hypot(ex, ey)
    sign = 1.0 if toward_end else -1.0
    return sign * ex / ln, sign * ey / ln


@njit(cache=True, inline="always")
def _patch_direction(zones, k, c, s):
    """The direction (A's frame, then B's frame) in which contact k's length runs from its
    point, and whether it has one: a face contact anchored at a vertex covers its length
    along the face from that vertex (the half of a shared edge next to it: module
    docstring); any other contact is a point."""
    a, b = c.block_a[k], c.block_b[k]
    anchor = c.anchor[k]
    if c.face[k] == 0 or anchor == ANCHOR_MID:
        return 0.0, 0.0, 0.0, 0.0, False
    if anchor == ANCHOR_A:
        v = c.vertex_a[k]
        v0, v1 = zones.block_vertices[a], zones.block_vertices[a + 1]
        prev = v - 1 if v > v0 else v1 - 1
        # of A's two faces at the vertex, the one whose outward normal is normal_b
        nxt = v + 1 if v + 1 < v1 else v0
        ex, ey = (zones.vertices[nxt, 0] - zones.vertices[v, 0],
                  zones.vertices[nxt, 1] - zones.vertices[v, 1])
        px, py = (zones.vertices[v, 0] - zones.vertices[prev, 0],
                  zones.vertices[v, 1] - zones.vertices[prev, 1])
        along_next = (ey * c.normal_b[k, 0] - ex * c.normal_b[k, 1]) / np.hypot(ex, ey)
        along_prev = (py * c.normal_b[k, 0] - px * c.normal_b[k, 1]) / np.hypot(px, py)
        if along_next >= along_prev:
            dax, day = _face_direction(zones, a, v, True)
        else:
            dax, day = _face_direction(zones, a, prev, False)
        wx, wy = rotate(s.rot, a, dax, day)
        dbx, dby = unrotate(s.rot, b, wx, wy)
        return dax, day, dbx, dby, True
    e = c.edge_b[k]                         # ANCHOR_B: B's vertex at an end of face e
    if e < 0:
        return 0.0, 0.0, 0.0, 0.0, False
    f = e + 1 if e + 1 < zones.block_vertices[b + 1] else zones.block_vertices[b]
    de = ((c.point_b[k, 0] - zones.vertices[e, 0]) ** 2
          + (c.point_b[k, 1] - zones.vertices[e, 1]) ** 2)
    df = ((c.point_b[k, 0] - zones.vertices[f, 0]) ** 2
          + (c.point_b[k, 1] - zones.vertices[f, 1]) ** 2)
    dbx, dby = _face_direction(zones, b, e, de <= df)
    wx, wy = rotate(s.rot, b, dbx, dby)
    dax, day = unrotate(s.rot, a, wx, wy)
    return dax, day, dbx, dby, True


@njit(cache=True, inline="always")
def _side(zones, blk, face, px, py, dx, dy, length, patch):
    """(face, q0, q1): the stretch of a deformable block's boundary a contact point (px, py)
    acts on, in segments along ``face`` (-1: the nearest face), from the point to
    point + length (dx, dy) (a patch) or q0 = q1 (a point); face -1 for a rigid block."""
    if (zones.edge_offsets[zones.block_vertices[blk]]
        == zones.edge_offsets[zones.block_vertices[blk] + 1]):
        return -1, 0.0, 0.0
    if face < 0:
        face = _nearest_face(zones, blk, px, py)
    q0 = _face_param(zones, face, px, py)
    if not patch:
        return face, q0, q0
    q1 = _face_param(zones, face, px + length * dx, py + length * dy)
    return face, min(q0, q1), max(q0, q1)


@njit(cache=True, inline="always")
def contact_sides(zones, k, c, s):
    """(face, q0, q1) of contact k's A side, then of its B side (``_side``): A's vertex
    face for a contact anchored at A's vertex, B's face ``edge_b``, else the nearest."""
    dax, day, dbx, dby, patch = _patch_direction(zones, k, c, s)
    a, b = c.block_a[k], c.block_b[k]
    L = c.length[k]
    fa = -1
    if c.anchor[k] == ANCHOR_A and c.vertex_a[k] >= 0:
        v = c.vertex_a[k]                   # the vertex: the face that starts or ends there
        if patch:
            v0, v1 = zones.block_vertices[a], zones.block_vertices[a + 1]
            nxt = v + 1 if v + 1 < v1 else v0
            ex, ey = (zones.vertices[nxt, 0] - zones.vertices[v, 0],
                      zones.vertices[nxt, 1] - zones.vertices[v, 1])
            fa = v if ex * dax + ey * day > 0.0 else (v - 1 if v > v0 else v1 - 1)
        else:
            fa = v
    ea, qa0, qa1 = _side(zones, a, fa, c.point_a[k, 0], c.point_a[k, 1], dax, day, L, patch)
    eb, qb0, qb1 = _side(zones, b, c.edge_b[k], c.point_b[k, 0], c.point_b[k, 1], dbx, dby, L,
                         patch)
    return ea, qa0, qa1, eb, qb0, qb1


@njit(cache=True, inline="always")
def _weights(q0, q1, seg):
    """(w_i, w_j): the shares of a segment's two gridpoints (segment ``seg`` of its face) in
    a unit load spread evenly over [q0, q1] (segment units, q1 > q0): the integrals of the
    linear shape functions."""
    lo, hi = max(q0, float(seg)) - seg, min(q1, seg + 1.0) - seg
    if hi <= lo:
        return 0.0, 0.0
    wj = 0.5 * (hi * hi - lo * lo)
    return (hi - lo - wj) / (q1 - q0), wj / (q1 - q0)


# a contact's stretch shorter than this (segment units) is a point
POINT = 1e-9


@njit(cache=True, inline="always")
def _stretch(zones, e, q0, q1):
    """(first segment, last + 1, point): the segments of face e that [q0, q1] touches; a
    point (q1 - q0 < POINT) has one segment."""
    nseg = zones.edge_offsets[e + 1] - zones.edge_offsets[e] - 1
    s0 = min(int(q0), nseg - 1)
    if q1 - q0 < POINT:
        return s0, s0 + 1, True
    return s0, min(max(int(math.ceil(q1)), s0 + 1), nseg), False


@njit(cache=True, inline="always")
def _share(q0, q1, seg, point):
    if point:
        return 1.0 - (q0 - seg), q0 - seg
    return _weights(q0, q1, seg)


@njit(cache=True, inline="always")
def _patch_u(zones, e, q0, q1):
    """Mean displacement (block axes, m) over [q0, q1] of face e (0 for e < 0)."""
    if e < 0:
        return 0.0, 0.0
    ux, uy = 0.0, 0.0
    s0, s1, point = _stretch(zones, e, q0, q1)
    for seg in range(s0, s1):
        wi, wj = _share(q0, q1, seg, point)
        i, j = (zones.edge_points[zones.edge_offsets[e] + seg],
                zones.edge_points[zones.edge_offsets[e] + seg + 1])
        ux += wi * (zones.x[i, 0] - zones.x0[i, 0]) + wj * (zones.x[j, 0] - zones.x0[j, 0])
        uy += wi * (zones.x[i, 1] - zones.x0[i, 1]) + wj * (zones.x[j, 1] - zones.x0[j, 1])
    return ux, uy


@njit(cache=True, inline="always")
def spread(out, zones, e, q0, q1, fx, fy, scale):
    """Spread (fx, fy) (block axes) over [q0, q1] of face e into ``out`` (x scale), with the
    weights of ``_patch_u`` (the same virtual work)."""
    s0, s1, point = _stretch(zones, e, q0, q1)
    for seg in range(s0, s1):
        wi, wj = _share(q0, q1, seg, point)
        i, j = (zones.edge_points[zones.edge_offsets[e] + seg],
                zones.edge_points[zones.edge_offsets[e] + seg + 1])
        out[i, 0] += scale * wi * fx
        out[i, 1] += scale * wi * fy
        out[j, 0] += scale * wj * fx
        out[j, 1] += scale * wj * fy


@njit(cache=True, inline="always")
def deformed_points(k, c, s, zones):
    """(xa, ya, xb, yb): world points (m) of contact k's two points on deformed blocks,
    x = pos + R (p + u) with u the mean displacement over the stretch of boundary the
    contact acts on (module docstring)."""
    ea, qa0, qa1, eb, qb0, qb1 = contact_sides(zones, k, c, s)
    uax, uay = _patch_u(zones, ea, qa0, qa1)
    ubx, uby = _patch_u(zones, eb, qb0, qb1)
    xa, ya = body_point(s.pos, s.rot, c.block_a[k], c.point_a[k, 0] + uax,
                        c.point_a[k, 1] + uay)
    xb, yb = body_point(s.pos, s.rot, c.block_b[k], c.point_b[k, 0] + ubx,
                        c.point_b[k, 1] + uby)
    return xa, ya, xb, yb


@njit(cache=True, inline="always")
def rest_points(k, c, s, zones):
    """After ``forces._reanchor`` put contact k's free point(s) at a deformed place, take the
    displacement there off, so ``point_a`` and ``point_b`` are again rest (body) points."""
    ea, qa0, qa1, eb, qb0, qb1 = contact_sides(zones, k, c, s)
    if c.anchor[k] != ANCHOR_A:
        ux, uy = _patch_u(zones, ea, qa0, qa1)
        c.point_a[k, 0] -= ux
        c.point_a[k, 1] -= uy
    if c.anchor[k] != ANCHOR_B:
        ux, uy = _patch_u(zones, eb, qb0, qb1)
        c.point_b[k, 0] -= ux
        c.point_b[k, 1] -= uy
