"""Contact lengths from the current geometry: each interface divided among its contacts.

Two convex blocks touch along one straight stretch (their overlap) or at a point. The contacts
of a block pair whose normals lie within 25 deg of the first one's are on that stretch's line.
Sorted along its tangent t by their stations s (the point each contact's force acts at,
``forces._force_point``; with rounded corners the touch of the arc), they divide the stretch
[lo, hi] as UDEC's domains do, each taking half the distance to its neighbours::

    L_1 = (s_1 + s_2) / 2 - lo,   L_i = (s_{i+1} - s_{i-1}) / 2,   L_m = hi - (s_{m-1} + s_m) / 2

so the lengths sum to hi - lo whatever the blocks have slid. The stretch is the stations' own,
s_1 to s_m, carried on to where the two blocks' faces along the line stop overlapping (the
faces' ends at the vertices, with rounded corners too), by at most the search margin: an end of the overlap
farther out would have a contact of its own (a vertex on a face), unless the faces are open
there. A stretch is no shorter than the search margin (faces meeting end to end, or a corner
found within the margin before the faces overlap). Contacts closer than the search margin are
one station (the search makes no two contacts of a pair nearer than that), and share its
length in proportion to the lengths they had (the ends of two shared edges of one pair
meeting at a point stand for halves of different edges). A lone contact (a corner on a face,
a corner meeting a corner) keeps the length it was made with (``detection._new_rows``: half of
its edges, UDEC's domain), cut to the faces' overlap where they overlap by more than the
margin.

When: at every contact search (``update.search_contacts``), for each pair that holds a contact
made by the search (``UNBONDED``: a vertex has passed onto a face), and each pair still holding
only the shared edge it was built with once its lengths and its stretch differ by more than
0.1 % (its blocks have slid along it). A pair that still holds an intact bond is never divided:
the bond's length is its area of intact rock, and its blocks cannot slide past each other while
it holds (a stretch measured between their points would follow the bond's elastic shear, which
in a lab specimen of millimetre blocks is several per cent of an edge). The shared edges of blocks that have not slid keep their
halves (the overlap up to the elastic displacement), so the model's stored answers stay bit
for bit where nothing has slid. Between searches no block moves more than half the search
margin, so a contact in compression stands for its stretch to within the margin at each end.

Rounded corners (``rounding``) set a contact's normal, gap and station, not the length of the
interface: a rounded block touches only along its straight parts, d_A + d_B short of the faces'
overlap, and counting that would take (d_A + d_B) / L of every slid joint's cohesion, tension
and water force away (on the cross-jointed field slope 0.5-0.9 % of F). The arcs are a device
for the normal at corners (Cundall 1988); the joint's area is the rock's.

What a contact keeps: its stresses (sn, ts, the elastic normal stress), plastic slip, crack
state and material stay with its point; only the length it stands for changes, so forces
(length x stress) and stiffness (length x k) follow the new length. Stress is what the law and
the strength work on (a contact's history is of its point of the interface), and it is the one
quantity that does not depend on how the stretch is cut into contacts. The two halves of an
edge element (``Contacts.partner``) stay one element only while they are the pair's only two
contacts on the line; otherwise they become point contacts.
"""
from __future__ import annotations

import math

import warnings

import numpy as np
from numba import njit
from numba.core.errors import NumbaPerformanceWarning

from .contacts import ANCHOR_A, ANCHOR_B, INTACT, UNBONDED
from ..step.kinematics import body_point, contact_normal
from .rounding import is_rounded, no_rounding, rounded_contact

__all__ = ["divide_interfaces", "interface_stations"]

# contacts on one line: normals within 25 deg (as the search's merge rule, ``detection._accept``)
PARALLEL = 0.9
# a pair still holding only the shared edge it was built with is divided anew once its
# lengths and its stretch differ by more than this fraction (its blocks have slid)
DRIFT = 1e-3
# a face lies along the interface's line when it is within about 11 deg of it (the cos)
ALONG = 0.98


@njit(cache=True, parallel=True)   # no prange: the records' reference counting dropped (below)
def _stations(c, s, rnd, pts, nrm):
    """World station (the force's point, m) and unit normal of every live contact."""
    for k in range(c.count[0]):
        a, b = c.block_a[k], c.block_b[k]
        if is_rounded(rnd, c, k):
            xc, yc, nx, ny, _ = rounded_contact(rnd, s, a, b, c.vertex_a[k], c.edge_b[k])
            d = rnd.arc[c.vertex_a[k]]
            pts[k, 0], pts[k, 1] = xc + d * nx, yc + d * ny
        else:
            nx, ny = contact_normal(s, a, b, c.face[k], c.normal_b[k, 0], c.normal_b[k, 1])
            xa, ya = body_point(s.pos, s.rot, a, c.point_a[k, 0], c.point_a[k, 1])
            xb, yb = body_point(s.pos, s.rot, b, c.point_b[k, 0], c.point_b[k, 1])
            anchor = c.anchor[k]
            if anchor == ANCHOR_A:
                pts[k, 0], pts[k, 1] = xa, ya
            elif anchor == ANCHOR_B:
                pts[k, 0], pts[k, 1] = xb, yb
            else:
                pts[k, 0], pts[k, 1] = 0.5 * (xa + xb), 0.5 * (ya + yb)
        nrm[k, 0], nrm[k, 1] = nx, ny


def interface_stations(c, s, rnd=None):
    """((n, 2) stations, (n, 2) normals) of the live contacts at the pose ``s`` (module
    docstring)."""
    n = c.n
    pts, nrm = np.empty((n, 2)), np.empty((n, 2))
    _stations(c, s, no_rounding() if rnd is None else rnd, pts, nrm)
    return pts, nrm


@njit(cache=True, inline="always")
def _corner(p, s, blk, j):
    """World point (m) of the end of a face at vertex j of block ``blk``: the vertex, with
    rounded corners too (a joint's length is the rock's, not the rounded shapes' straight
    parts: module docstring)."""
    return body_point(s.pos, s.rot, blk, p.local_vertices[j, 0], p.local_vertices[j, 1])


@njit(cache=True, inline="always")
def _next(p, blk, j):
    return j + 1 if j + 1 < p.vertex_offsets[blk + 1] else p.vertex_offsets[blk]


@njit(cache=True, inline="always")
def _prev(p, blk, j):
    return j - 1 if j > p.vertex_offsets[blk] else p.vertex_offsets[blk + 1] - 1


@njit(cache=True, inline="always")
def _face_span(p, s, blk, j, tx, ty, x0, y0, lo, hi):
    """(lo, hi) widened by the stations (along (tx, ty) from (x0, y0)) of the face of ``blk``
    from vertex j to the next, if that face lies along the line (within ``ALONG``)."""
    xa, ya = _corner(p, s, blk, j)
    xb, yb = _corner(p, s, blk, _next(p, blk, j))
    dx, dy = xb - xa, yb - ya
    ln = math.hypot(dx, dy)
    if ln == 0.0 or abs(dx * tx + dy * ty) < ALONG * ln:
        return lo, hi
    sa = (xa - x0) * tx + (ya - y0) * ty
    sb = (xb - x0) * tx + (yb - y0) * ty
    return min(lo, sa, sb), max(hi, sa, sb)


@njit(cache=True, inline="always")
def _overlap(c, p, s, on, m, tx, ty, x0, y0):
    """(lo, hi) stations of the stretch where the two blocks' faces along the line overlap,
    from the faces the contacts ``on[:m]`` name (B's face or, at its corner, the face beyond;
    A's faces at its vertex that lie along the line); (inf, -inf) when either block's face
    along the line is not known."""
    first_block = min(c.block_a[on[0]], c.block_b[on[0]])
    lo0, hi0, lo1, hi1 = math.inf, -math.inf, math.inf, -math.inf
    for i in range(m):
        k = on[i]
        a, b = c.block_a[k], c.block_b[k]
        e = np.int64(c.edge_b[k])
        if e >= 0:
            for f in (e, _prev(p, b, e), _next(p, b, e)):
                if b == first_block:
                    lo0, hi0 = _face_span(p, s, b, f, tx, ty, x0, y0, lo0, hi0)
                else:
                    lo1, hi1 = _face_span(p, s, b, f, tx, ty, x0, y0, lo1, hi1)
        va = np.int64(c.vertex_a[k])
        if va >= 0:
            for f in (va, _prev(p, a, va)):
                if a == first_block:
                    lo0, hi0 = _face_span(p, s, a, f, tx, ty, x0, y0, lo0, hi0)
                else:
                    lo1, hi1 = _face_span(p, s, a, f, tx, ty, x0, y0, lo1, hi1)
    return max(lo0, lo1), min(hi0, hi1)


@njit(cache=True, inline="always")
def _divide_group(g0, g1, order, c, p, s, pts, nrm, margin, made, on, st, first):
    """Divide one block pair's contacts ``order[g0:g1]`` (module docstring); ``made``: the
    pair holds a contact made by the search; ``on``, ``st``, ``first``: scratch of at least
    g1 - g0 (+ 1) entries. Returns whether a length changed."""
    k0 = order[g0]
    tx, ty = -nrm[k0, 1], nrm[k0, 0]
    x0, y0 = pts[k0, 0], pts[k0, 1]
    m = 0
    for i in range(g0, g1):               # the contacts on the line, sorted by station
        k = order[i]
        if abs(nrm[k, 0] * nrm[k0, 0] + nrm[k, 1] * nrm[k0, 1]) < PARALLEL:
            continue
        sk = (pts[k, 0] - x0) * tx + (pts[k, 1] - y0) * ty
        j = m
        while j > 0 and st[j - 1] > sk:
            st[j], on[j] = st[j - 1], on[j - 1]
            j -= 1
        st[j], on[j] = sk, k
        m += 1
    if m < 2 and not made:
        return False
    lo, hi = st[0], st[m - 1]
    face_lo, face_hi = _overlap(c, p, s, on, m, tx, ty, x0, y0)
    known = face_hi - face_lo > -math.inf
    if m == 1 or hi - lo <= margin:
        # one station: a corner on a face keeps the length it was made with (half of its
        # edges: UDEC's domain), cut to the faces' overlap where they overlap by more than
        # the margin
        if not known or face_hi - face_lo <= margin:
            return False                  # (faces meeting at a point: a corner's length)
        changed = False
        for i in range(m):
            if c.length[on[i]] > face_hi - face_lo:
                c.length[on[i]] = face_hi - face_lo
                changed = True
        return changed
    if known:
        lo = max(face_lo, lo - margin)
        hi = min(face_hi, hi + margin)
        # a vertex slid past the other face's end (kept by the search within the margin,
        # which then makes no contact at the end itself) stands for that end
        for i in range(m):
            st[i] = min(max(st[i], lo), hi)
    if hi - lo < margin:                  # faces meeting end to end, or about to overlap
        mid = 0.5 * (lo + hi)
        lo, hi = mid - 0.5 * margin, mid + 0.5 * margin
    if not hi - lo > 0.0:
        return False
    if not made:                          # the shared edge it was built with, if not slid
        old = 0.0
        for i in range(m):
            old += c.length[on[i]]
        if abs(old - (hi - lo)) <= DRIFT * (hi - lo):
            return False
    # stations: runs of sorted s closer than the margin (the search makes no two contacts of
    # a pair nearer than that); first[j] the first sorted contact of station j
    ns = 0
    for i in range(m):
        if i == 0 or st[i] - st[i - 1] > margin:
            first[ns] = i
            ns += 1
    first[ns] = m
    changed = False
    for j in range(ns):
        i0, i1 = first[j], first[j + 1]
        left = max(lo, 0.5 * (st[i0 - 1] + st[i0])) if j > 0 else lo
        right = min(hi, 0.5 * (st[i1 - 1] + st[i1])) if j < ns - 1 else hi
        span = max(0.0, right - left)
        # a station's contacts share it as they shared the interface (the two ends of two
        # shared edges meeting there stand for halves of different edges)
        total = 0.0
        for i in range(i0, i1):
            total += c.length[on[i]]
        for i in range(i0, i1):
            k = on[i]
            share = span * c.length[k] / total if total > 0.0 else span / (i1 - i0)
            if c.length[k] != share:
                c.length[k] = share
                changed = True
    # an edge element is its two halves spanning the line; anything else: point contacts
    for i in range(m):
        k = on[i]
        q = c.partner[k]
        if q >= 0 and not (m == 2 and (q == on[0] or q == on[1])):
            c.partner[q] = -1
            c.partner[k] = -1
            c.edge_x0[q] = 0.0
            c.edge_x0[k] = 0.0
    return changed


# parallel=True without a prange (as ``forces.chunk_forces``): numba's parfor pass then drops the
# reference counting of the records' arrays around the inlined per-pair helpers, 20x faster
# (benchmarks/division_cost.py); its warning that it found nothing to parallelise is silenced
warnings.filterwarnings("ignore", category=NumbaPerformanceWarning,
                        message=r"(?s).*parallel=True.*no transformation for parallel")


@njit(cache=True, parallel=True)
def _divide(order, keys, c, p, s, pts, nrm, margin, bond):
    n = order.shape[0]
    widest, g0 = 1, 0                     # the largest pair: the scratch's size
    while g0 < n:
        g1 = g0 + 1
        while g1 < n and keys[order[g1]] == keys[order[g0]]:
            g1 += 1
        widest = max(widest, g1 - g0)
        g0 = g1
    on = np.empty(widest, np.int64)
    st = np.empty(widest)
    first = np.empty(widest + 1, np.int64)
    changed = False
    g0 = 0
    while g0 < n:
        g1 = g0 + 1
        while g1 < n and keys[order[g1]] == keys[order[g0]]:
            g1 += 1
        made, held = False, False
        for i in range(g0, g1):
            k = order[i]
            made = made or c.broken[k] == UNBONDED
            held = held or (c.broken[k] == INTACT and bond[c.material[k]])
        if not held and (made or g1 - g0 >= 2) and \
                _divide_group(g0, g1, order, c, p, s, pts, nrm, margin, made, on, st,
                              first):
            changed = True
        g0 = g1
    return changed


def divide_interfaces(c, s, p, bonded, rnd=None, margin=0.0) -> bool:
    """Set the lengths of the contacts ``c`` (Contacts, in place) of every block pair whose
    contact set has changed since it was built, from the pose ``s`` (BlockState) of the blocks
    ``p`` (BlockProps) (module docstring); ``bonded`` (nm,) bool, the materials whose intact
    contacts are bonds (``MaterialTable.bonded``); ``margin`` the search margin (m). Returns
    whether a length changed (the time step must follow)."""
    n = c.n
    if n == 0:
        return False
    rnd = no_rounding() if rnd is None else rnd
    pts, nrm = interface_stations(c, s, rnd)
    a, b = c.block_a[:n].astype(np.int64), c.block_b[:n].astype(np.int64)
    keys = np.minimum(a, b) * p.mass.shape[0] + np.maximum(a, b)
    order = np.argsort(keys, kind="stable")
    return bool(_divide(order, keys, c, p, s, pts, nrm, float(margin),
                        np.asarray(bonded, np.bool_)))
