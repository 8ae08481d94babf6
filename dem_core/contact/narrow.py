"""Contact search, narrow phase: each vertex of A against the faces of B, for the pairs the
broad phase reported.

Among the edges of B the vertex supports (A's edges at the vertex do not run into it steeper
than ``SUPPORT_SLOPE``, ``_supports``), the one with the largest signed distance (the nearest for
a vertex inside B; at a corner tie, the edge facing A's wedge; among the collinear pieces of a
side split by neighbours' corners, which tie, the piece the vertex projects onto); a candidate
if that distance (or the distance to the edge's segment, near a corner) is below the margin and
the vertex's wedge faces the edge (``narrow_phase``: rows (A, vertex, B, edge)).
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit

__all__ = ["narrow_phase", "SUPPORT_SLOPE"]

# A vertex contacts a face only while neither of its block's edges at the vertex runs into
# that face steeper than this slope (sin of about 11.5 deg; ``_supports``).
SUPPORT_SLOPE = 0.2


@njit(cache=True)
def _outward(wv, offsets, blk, e):
    """Unit outward normal of edge e (first vertex index) of CCW block ``blk``."""
    f = e + 1 if e + 1 < offsets[blk + 1] else offsets[blk]
    ex, ey = wv[f, 0] - wv[e, 0], wv[f, 1] - wv[e, 1]
    ln = math.hypot(ex, ey)
    return ey / ln, -ex / ln


@njit(cache=True)
def _to_segment(wv, offsets, blk, e, x, y):
    """Distance (m) from (x, y) to edge e of block ``blk`` as a segment."""
    f = e + 1 if e + 1 < offsets[blk + 1] else offsets[blk]
    ex, ey = wv[f, 0] - wv[e, 0], wv[f, 1] - wv[e, 1]
    s = ((x - wv[e, 0]) * ex + (y - wv[e, 1]) * ey) / (ex * ex + ey * ey)
    s = min(max(s, 0.0), 1.0)
    return math.hypot(x - wv[e, 0] - s * ex, y - wv[e, 1] - s * ey)


# Flat arguments (more than ten): a helper of the narrow phase's inner loop, called per
# vertex and edge; a record argument would be built and reference-counted at every call
@njit(cache=True)
def _diagonal_at_crossing(wv, offsets, B, be, f, x, y, a1x, a1y, a2x, a2y, margin):
    """True when A's vertex sits on a corner of B and A's two faces there continue B's two
    faces (each antiparallel to one of them): the blocks are diagonal neighbours where two
    straight lines cross (an X, e.g. a flaw line crossing a joint). They cannot overlap by a
    small translation without first overlapping the blocks they share edges with, and a
    contact between them has no defined normal: it would lock slip along either line."""
    near = 0.25 * margin
    for corner, other in ((be, be - 1 if be > offsets[B] else offsets[B + 1] - 1), (f, f)):
        if math.hypot(x - wv[corner, 0], y - wv[corner, 1]) > near:
            continue
        b1x, b1y = _outward(wv, offsets, B, be)
        b2x, b2y = _outward(wv, offsets, B, other)
        if (a1x * b1x + a1y * b1y < -0.999 and a2x * b2x + a2y * b2y < -0.999) or \
                (a1x * b2x + a1y * b2y < -0.999 and a2x * b1x + a2y * b1y < -0.999):
            return True
    return False


@njit(cache=True)
def _point_touch(wv, offsets, A, v, B, tie):
    """True when A's vertex v sits on a corner of B (within ``tie``) and no edge of A there
    runs along an edge of B there in the same direction: the two blocks meet at that one point
    only (diagonal neighbours where two lines meet, e.g. where the cells of two beds meet on a
    bedding joint). Such a touch has no contact length and no defined normal; a contact there
    would add stiffness and stress to an interface the shared edges already carry."""
    vn = v + 1 if v + 1 < offsets[A + 1] else offsets[A]
    vp = v - 1 if v > offsets[A] else offsets[A + 1] - 1
    for w in range(offsets[B], offsets[B + 1]):
        if math.hypot(wv[v, 0] - wv[w, 0], wv[v, 1] - wv[w, 1]) > tie:
            continue
        wn = w + 1 if w + 1 < offsets[B + 1] else offsets[B]
        wp = w - 1 if w > offsets[B] else offsets[B + 1] - 1
        for a in (vn, vp):
            ax, ay = wv[a, 0] - wv[v, 0], wv[a, 1] - wv[v, 1]
            la = math.hypot(ax, ay)
            for b in (wn, wp):
                bx, by = wv[b, 0] - wv[w, 0], wv[b, 1] - wv[w, 1]
                if ax * bx + ay * by > 0.999 * la * math.hypot(bx, by):
                    return False            # they share a face from this corner
        return True
    return False


@njit(cache=True)
def _supports(wv, offsets, A, v, ox, oy, slope):
    """True if vertex v is block A's deepest point towards B's face of outward normal (ox, oy),
    within ``slope``: neither of A's two edges at v runs into B (edge direction . normal
    >= -slope, i.e. tilted by less than asin(slope) towards the face).

    A vertex pressed into a face can only be pushed out along that face's normal if the rest
    of A lies behind it. Near B's corner a vertex can be nearer to the adjacent face's line
    than to the face it really rests on (two blocks' corners meeting on a joint: the lower
    block's corner sits 1 um from the upper block's free end face and 30 um into its joint
    face); a contact with the end face there would be a spring across the joint that locks the
    slip, growing with the shear. Edge-to-edge contacts (A's edge along B's face, slope 0)
    pass while the faces are within asin(slope) of parallel.
    """
    vn = v + 1 if v + 1 < offsets[A + 1] else offsets[A]
    vp = v - 1 if v > offsets[A] else offsets[A + 1] - 1
    for w in (vn, vp):
        ex, ey = wv[w, 0] - wv[v, 0], wv[w, 1] - wv[v, 1]
        if ex * ox + ey * oy < -slope * math.hypot(ex, ey):
            return False
    return True


# Over 60 lines and more than ten flat arguments: the narrow phase's loop over one pair's
# vertices and edges, kept whole so numba keeps its scalars in registers (calls per vertex
# would copy the arrays' descriptors and reference-count them)
@njit(cache=True)
def _vertex_candidates(A, B, wv, offsets, lo, hi, margin, covered, slope, out, n):
    """Append candidates (A, vertex, B, edge) of A's vertices near B to ``out``.

    The edge is chosen among B's faces that A's vertex supports (``_supports``): for a vertex
    outside B, those at the largest outward signed distance (the face(s) it is outside of);
    for a vertex inside B, the nearest supported face if it is at most ``margin`` deeper than
    the nearest face. Where faces tie (a vertex at or beside
    B's corner) the one that faces A's wedge best (most negative dot of B's normal with the
    normals of A's two edges at the vertex). A vertex outside B whose wedge does not face the
    edge (both dots >= -0.05: side by side) is no contact.

    A face of B that an intact bond glues to a neighbour (``covered``) cannot be touched: it is
    never chosen, and a vertex outside B whose nearest faces of B are all covered gets no
    contact (a vertex sliding past the corner between two bonded blocks must meet the next
    block's face, not the buried side face between them, which would lock the slip).
    """
    tie = 1e-3 * margin
    for v in range(offsets[A], offsets[A + 1]):
        x, y = wv[v, 0], wv[v, 1]
        if x < lo[B, 0] or x > hi[B, 0] or y < lo[B, 1] or y > hi[B, 1]:
            continue
        best = -np.inf
        for e in range(offsets[B], offsets[B + 1]):
            ox, oy = _outward(wv, offsets, B, e)
            best = max(best, (x - wv[e, 0]) * ox + (y - wv[e, 1]) * oy)
        if best > margin:
            continue
        vp = v - 1 if v > offsets[A] else offsets[A + 1] - 1
        a1x, a1y = _outward(wv, offsets, A, v)
        a2x, a2y = _outward(wv, offsets, A, vp)
        # nearest eligible face: outside B only the faces at `best`; inside, a supported face
        # at most a margin deeper than the nearest one (a vertex that just grazes a face it
        # does not support is the other block's vertex's contact, not one with a far face)
        low = best - tie if best >= 0.0 else best - margin
        near = -np.inf
        for e in range(offsets[B], offsets[B + 1]):
            ox, oy = _outward(wv, offsets, B, e)
            d = (x - wv[e, 0]) * ox + (y - wv[e, 1]) * oy
            if covered[e] or d < low or not _supports(wv, offsets, A, v, ox, oy, slope):
                continue
            near = max(near, d)
        if near == -np.inf:
            continue
        # among faces that face A's wedge equally (the collinear pieces of a side split where
        # neighbours meet it), the piece the vertex projects onto: the first piece of a split
        # side may lie far along it, and its segment test below would reject the contact
        be, bf, bseg = -1, np.inf, np.inf
        for e in range(offsets[B], offsets[B + 1]):
            ox, oy = _outward(wv, offsets, B, e)
            d = (x - wv[e, 0]) * ox + (y - wv[e, 1]) * oy
            if covered[e] or d < near - tie or not _supports(wv, offsets, A, v, ox, oy, slope):
                continue
            facing = min(ox * a1x + oy * a1y, ox * a2x + oy * a2y)
            seg = _to_segment(wv, offsets, B, e, x, y)
            if facing < bf - 1e-9 or (facing <= bf + 1e-9 and seg < bseg):
                be, bf, bseg = e, facing, seg
        if be < 0 or (best >= 0.0 and bf >= -0.05):
            continue
        f = be + 1 if be + 1 < offsets[B + 1] else offsets[B]
        ex, ey = wv[f, 0] - wv[be, 0], wv[f, 1] - wv[be, 1]
        ln2 = ex * ex + ey * ey
        s = ((x - wv[be, 0]) * ex + (y - wv[be, 1]) * ey) / ln2
        if _diagonal_at_crossing(wv, offsets, B, be, f, x, y, a1x, a1y, a2x, a2y, margin):
            continue
        if _point_touch(wv, offsets, A, v, B, tie):
            continue
        if (s < 0.0 or s > 1.0) and bseg > margin:   # near a corner: distance to the segment
            continue
        if n == out.shape[0]:
            return n, True
        out[n, 0], out[n, 1], out[n, 2], out[n, 3] = A, v, B, be
        n += 1
    return n, False


@njit(cache=True)
def narrow_phase(pairs, wv, offsets, lo, hi, margin, covered, slope=SUPPORT_SLOPE):
    """(m, 4) int64 candidates [A, vertex of A, B, first vertex of B's edge]."""
    out = np.empty((8 * pairs.shape[0] + 16, 4), np.int64)
    n = 0
    for p in range(pairs.shape[0]):
        for A, B in ((pairs[p, 0], pairs[p, 1]), (pairs[p, 1], pairs[p, 0])):
            full = True
            while full:
                n, full = _vertex_candidates(A, B, wv, offsets, lo, hi, margin, covered, slope,
                                             out, n)
                if full:                          # grow and redo this block's vertices
                    bigger = np.empty((2 * out.shape[0], 4), np.int64)
                    bigger[:n] = out[:n]
                    out = bigger
                    while n > 0 and out[n - 1, 0] == A and out[n - 1, 2] == B:
                        n -= 1
    return out[:n]
