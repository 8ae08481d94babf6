"""Contact search: broad phase on a cell grid (``broad``), narrow phase vertex-against-edge
(``narrow``), then which contacts survive and which candidates become new contacts (here).

``update_contacts`` is run by the driver when some block has moved more than half the search
margin since the last search (``step.run_steps`` status 1):

1. Broad phase: axis-aligned boxes grown by the margin, binned on a uniform grid; a pair is
   reported once, by the cell holding the lower-left corner of the two boxes' overlap.
2. Narrow phase: each vertex of A against B: among the edges of B the vertex supports (A's
   edges at the vertex do not run into it, ``_supports``), the one with the largest signed
   distance (the nearest for a vertex inside B; at a corner tie, the edge facing A's wedge;
   among the collinear pieces of a side split by neighbours' corners, which tie, the piece the
   vertex projects onto); a candidate if that distance (or the distance to the edge's
   segment, near a corner) is below the margin and the vertex's wedge faces the edge.
3. Survivors keep their history: an intact bonded contact (its material has peak T or c
   above the residual, or is glued) always survives; any other survives while its gap is
   below the margin, its point still projects onto B's edge (within the margin) and its
   vertex still supports that edge.
   A point of a shared edge that is not a vertex of A survives its bond only while the two
   faces stay parallel (relative rotation below 0.2 rad).
4. A candidate becomes a new, unbonded contact with the material of the face of B it touches
   (``BlockProps.surface_material``: the joint, flaw or region boundary that face lies on; the
   model's ``new_contact_material`` for a face that was free at the start), unless a contact of the same block pair with a
   (anti)parallel normal already sits within the margin of it (so vertex-vertex touches and
   shared edges are not doubled, while a corner rolling over an edge gets its own contact).
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit

from .contacts import ANCHOR_A, INTACT, UNBONDED, Contacts
from ..step.kinematics import body_point, contact_normal, unrotate
from .boundary_points import deformed_points
from .rounding import corner_centre, follow_faces, is_rounded, no_rounding, rounded_contact
from .broad import boxes, grid_pairs, world_vertices
from .narrow import SUPPORT_SLOPE, _supports, narrow_phase

__all__ = ["update_contacts", "compact", "block_containing", "world_vertices", "grid_pairs",
           "SUPPORT_SLOPE"]



@njit(cache=True)
def _displacements(c, s, rows, rnd, zones):
    un = np.empty(rows.shape[0])
    us = np.empty(rows.shape[0])
    for i in range(rows.shape[0]):
        k = rows[i]
        a, b = c.block_a[k], c.block_b[k]
        xb, yb = body_point(s.pos, s.rot, b, c.point_b[k, 0], c.point_b[k, 1])
        if is_rounded(rnd, c, k):
            _, _, nx, ny, gap = rounded_contact(rnd, s, a, b, c.vertex_a[k], c.edge_b[k])
            xa, ya = corner_centre(rnd, s, a, c.vertex_a[k])
            un[i] = gap
        else:
            if zones is None:                # rigid blocks (numba drops the branch below)
                xa, ya = body_point(s.pos, s.rot, a, c.point_a[k, 0], c.point_a[k, 1])
            else:                          # points moved by the zones (forces.contact_update)
                xa, ya, xb, yb = deformed_points(k, c, s, zones)
            nx, ny = contact_normal(s, a, b, c.face[k], c.normal_b[k, 0], c.normal_b[k, 1])
            un[i] = (xb - xa) * nx + (yb - ya) * ny
        us[i] = (yb - ya) * nx - (xb - xa) * ny
    return un, us


def displacements(c: Contacts, s, rows, rnd=None, zones=None):
    """(u_n, u_s) of contacts ``rows`` at the pose ``s`` (m; ``contacts.py`` geometry; with
    rounded corners ``rnd``, ``rounding.py``; with deformable blocks ``zones``, the points the
    zones have moved, ``deformable/component.py``), as ``forces.contact_update`` sees them.
    Without deformable blocks the kernel is called with ``zones=None``, a signature of its own
    that leaves the deformed points out (a rigid scene's first search compiles several times
    faster: docs/performance.md, "The serial kernel and numba's pipelines")."""
    rnd = no_rounding() if rnd is None else rnd
    if zones is not None and zones.point_offsets.shape[0] == 0:
        zones = None
    return _displacements(c, s, np.asarray(rows, dtype=np.int64), rnd, zones)


@njit(cache=True)
def _rounded_points(c, s, rows, rnd):
    """Put B's point of rounded contacts ``rows`` across the normal from A's corner centre, at
    the rounded surfaces' touch (``rounding.py``): a new contact starts with no shear offset."""
    for k in rows:
        if not is_rounded(rnd, c, k):
            continue
        b = c.block_b[k]
        _, _, nx, ny, u_n = rounded_contact(rnd, s, c.block_a[k], b, c.vertex_a[k],
                                            c.edge_b[k])
        xc, yc = corner_centre(rnd, s, c.block_a[k], c.vertex_a[k])
        reach = u_n + rnd.arc[c.vertex_a[k]] + rnd.arc[c.edge_b[k]]
        c.point_b[k, 0], c.point_b[k, 1] = unrotate(s.rot, b, xc + reach * nx - s.pos[b, 0],
                                                    yc + reach * ny - s.pos[b, 1])


@njit(cache=True)
def _rounded_touches(s, cand, rnd):
    """(points, normals), (m, 2) each, world: where the rounded corner of candidates
    [A, vertex, B, edge] touches (the point of A's arc, ``rounding.py``) and the normal."""
    points = np.empty((cand.shape[0], 2))
    normals = np.empty((cand.shape[0], 2))
    for i in range(cand.shape[0]):
        xc, yc, nx, ny, _ = rounded_contact(rnd, s, cand[i, 0], cand[i, 2], cand[i, 1],
                                            cand[i, 3])
        d = rnd.arc[cand[i, 1]]
        points[i, 0], points[i, 1] = xc + d * nx, yc + d * ny
        normals[i, 0], normals[i, 1] = nx, ny
    return points, normals


@njit(cache=True)
def _fix_ring(edge_b, block_b, offsets):
    """Index of the end vertex of each contact's edge (wraps within the block's ring)."""
    out = np.empty(edge_b.shape[0], np.int64)
    for k in range(edge_b.shape[0]):
        e = edge_b[k]
        if e < 0:
            out[k] = -1
        else:
            b = block_b[k]
            out[k] = e + 1 if e + 1 < offsets[b + 1] else offsets[b]
    return out


# A kernel over flat arrays with more than ten of them: it runs once per search over all
# candidates, and the arrays are the columns of two sorted tables (a record would be built
# for one call only)
@njit(cache=True)
def _accept(keys_kept, px, py, nx, ny, cand_keys, cx, cy, cnx, cny, merge):
    """For sorted key arrays: accept candidates with no kept/accepted contact of the same pair
    within ``merge`` whose normal is parallel or antiparallel to the candidate's (25 deg)."""
    acc = np.zeros(cand_keys.shape[0], np.bool_)
    i0 = 0
    for j in range(cand_keys.shape[0]):
        key = cand_keys[j]
        while i0 < keys_kept.shape[0] and keys_kept[i0] < key:
            i0 += 1
        ok = True
        i = i0
        while i < keys_kept.shape[0] and keys_kept[i] == key:
            if math.hypot(px[i] - cx[j], py[i] - cy[j]) <= merge and \
                    abs(nx[i] * cnx[j] + ny[i] * cny[j]) > 0.9:
                ok = False
                break
            i += 1
        if ok:
            jj = j - 1
            while jj >= 0 and cand_keys[jj] == key:
                if acc[jj] and math.hypot(cx[jj] - cx[j], cy[jj] - cy[j]) <= merge and \
                        abs(cnx[jj] * cnx[j] + cny[jj] * cny[j]) > 0.9:
                    ok = False
                    break
                jj -= 1
        acc[j] = ok
    return acc


def compact(c: Contacts, rows) -> Contacts:
    """A Contacts holding only ``rows`` (in that order), with headroom."""
    return c.take(rows)


def _new_rows(p, s, cand, wv, margin, cut):
    """Local geometry and length of new (unbonded) contacts from candidates: the length is
    half of A's two edges at the vertex, each projected on B's edge and, with ``cut``, cut to
    B's edge (what of them lies across from B's face), no less than the smaller of the search
    margin and a twentieth of the two edges (a corner meeting a corner stands for a point);
    without ``cut``, projected only and no less than a twentieth of the edges."""
    off, local = p.vertex_offsets, p.local_vertices
    A, v, B, e = cand[:, 0], cand[:, 1], cand[:, 2], cand[:, 3]
    f = np.where(e + 1 < off[B + 1], e + 1, off[B])
    el = local[f] - local[e]                       # B's edge in B's frame
    ln = np.hypot(el[:, 0], el[:, 1])
    t = el / ln[:, None]
    normal_b = np.column_stack([-t[:, 1], t[:, 0]])   # inward normal = A -> B direction
    th = s.theta[B]
    cos_b, sin_b = np.cos(th), np.sin(th)
    rel = wv[v] - s.pos[B]
    vb = np.column_stack([cos_b * rel[:, 0] + sin_b * rel[:, 1],
                          -sin_b * rel[:, 0] + cos_b * rel[:, 1]])
    point_b = local[e] + ((vb - local[e]) * t).sum(axis=1)[:, None] * t   # projection
    # length: half of A's two edges at the vertex, projected on B's edge (with ``cut``, cut to it)
    prev = np.where(v - 1 >= off[A], v - 1, off[A + 1] - 1)
    nxt = np.where(v + 1 < off[A + 1], v + 1, off[A])
    ta = np.column_stack([cos_b * t[:, 0] - sin_b * t[:, 1],
                          sin_b * t[:, 0] + cos_b * t[:, 1]])  # world
    e1, e2 = wv[nxt] - wv[v], wv[prev] - wv[v]
    l1, l2 = np.hypot(*e1.T), np.hypot(*e2.T)
    if cut:
        at = ((vb - local[e]) * t).sum(axis=1)      # the vertex along B's edge, 0..ln
        L = np.zeros(len(cand))
        for edge in (e1, e2):
            along = (edge * ta).sum(axis=1)
            lo, hi = np.minimum(at, at + along), np.maximum(at, at + along)
            L += 0.5 * np.maximum(0.0, np.minimum(hi, ln) - np.maximum(lo, 0.0))
        floor = np.minimum(0.05 * (l1 + l2), margin)
    else:                      # the lengths as made before the division (projected, not cut)
        L = 0.5 * (np.abs((e1 * ta).sum(axis=1)) + np.abs((e2 * ta).sum(axis=1)))
        floor = 0.05 * (l1 + l2)
    L = np.minimum(np.maximum(L, floor), ln)
    return point_b, normal_b, L


def update_contacts(c: Contacts, s, p, table, new_material: int, margin: float, rnd=None,
                    cut=False):
    """Survivors (with history) then new unbonded contacts (the last ``n_new`` rows, stiffness
    and stress still to be set); returns (Contacts, n_new).

    ``c`` Contacts, ``s`` BlockState, ``p`` BlockProps, ``table`` the MaterialTable,
    ``new_material`` the material id of a contact with a face that was free at the start,
    ``margin`` the search distance (m), ``rnd`` the corners' Rounding (None: sharp; with it
    gaps, normals and the new contacts' points are those of the rounded corners), ``cut``:
    new contacts' lengths cut to the face they touch (``_new_rows``; with the division).
    """
    rnd = no_rounding() if rnd is None else rnd
    if rnd.radius > 0.0:
        follow_faces(c, s, rnd)
    wv = world_vertices(s.pos, s.rot, p.vertex_offsets, p.local_vertices)
    lo, hi = boxes(wv, p.vertex_offsets, p.active, margin)
    cell = 2.0 * float(np.median(p.radius[p.active > 0])) + 2 * margin if p.active.any() else 1.0
    pairs = grid_pairs(lo, hi, p.active, cell)
    cand = narrow_phase(pairs, wv, p.vertex_offsets, lo, hi, margin,
                        covered_faces(c, table, len(p.local_vertices)))
    end = _fix_ring(c.edge_b[:c.n], c.block_b[:c.n], p.vertex_offsets)
    keep, px, py, qx, qy = _survives_kernel(c, s, p, end, table.bonded(), wv, margin,
                                            SUPPORT_SLOPE, rnd)
    kept = np.flatnonzero(keep)
    cand, kept = _new_candidates(c, s, p, wv, cand, kept, (px, py, qx, qy), margin, rnd)
    m = cand.shape[0]
    new = compact(c, kept)
    if new.capacity < new.n + m:
        new = new.with_capacity(int(1.5 * (new.n + m)) + 64)
    if m:
        _append(new, cand, s, p, wv, _touched_material(p, table, new_material, cand), rnd,
                margin, cut)
    return new, m


def _new_candidates(c, s, p, wv, cand, kept, survivor_points, margin, rnd):
    """(candidates to add, survivors in block-pair order): the narrow phase's candidates
    without those a surviving contact of the same pair already covers (``_accept``), and one
    contact per (vertex of A, block B): a vertex at B's corner is not in contact with both of
    B's faces there (a second contact would double the stiffness and lock motion)."""
    px, py, qx, qy = survivor_points
    nb = len(p.mass)
    keys = np.minimum(c.block_a[kept], c.block_b[kept]).astype(np.int64) * nb + \
        np.maximum(c.block_a[kept], c.block_b[kept])
    order = np.argsort(keys, kind="stable")
    kept, keys = kept[order], keys[order]
    ckeys = np.minimum(cand[:, 0], cand[:, 2]) * nb + np.maximum(cand[:, 0], cand[:, 2])
    corder = np.argsort(ckeys, kind="stable")
    cand, ckeys = cand[corder], ckeys[corder]
    # candidate normals: B's edge direction rotated (inward normal of B's edge, world frame)
    B, e = cand[:, 2], cand[:, 3]
    f = np.where(e + 1 < p.vertex_offsets[B + 1], e + 1, p.vertex_offsets[B])
    ed = wv[f] - wv[e]
    ed /= np.hypot(ed[:, 0], ed[:, 1])[:, None]
    if rnd.radius == 0.0:
        cp, cn = wv[cand[:, 1]], np.column_stack([-ed[:, 1], ed[:, 0]])
    else:                      # two corners touching make one contact, whichever is "A"
        cp, cn = _rounded_touches(s, cand, rnd)
    acc = _accept(keys, px[kept], py[kept], qx[kept], qy[kept], ckeys, cp[:, 0], cp[:, 1],
                  cn[:, 0], cn[:, 1], margin)
    have = c.vertex_a[kept].astype(np.int64) * nb + c.block_b[kept]
    acc &= ~np.isin(cand[:, 1] * nb + cand[:, 2], have[c.vertex_a[kept] >= 0])
    return cand[acc], kept


def _append(new, cand, s, p, wv, material, rnd, margin, cut):
    """Write the candidates ``cand`` (A, vertex, B, edge) as new unbonded, unstressed contacts
    of ``material`` after the live rows of ``new`` (which has the capacity)."""
    m = cand.shape[0]
    point_b, normal_b, L = _new_rows(p, s, cand, wv, margin, cut)
    r = slice(new.n, new.n + m)
    new.block_a[r], new.block_b[r] = cand[:, 0], cand[:, 2]
    new.vertex_a[r], new.edge_b[r] = cand[:, 1], cand[:, 3]
    new.point_a[r] = p.local_vertices[cand[:, 1]]
    new.point_b[r] = point_b
    new.normal_b[r] = normal_b
    new.length[r] = L
    new.face[r] = 0                           # a vertex against a face
    new.anchor[r] = ANCHOR_A
    new.partner[r] = -1
    new.material[r] = material
    new.broken[r] = UNBONDED
    new.slipping[r] = 0
    for name in ("sn", "ts", "sn_elastic", "us", "up", "un", "damage", "work_fracture",
                 "work_friction", "edge_x0"):
        getattr(new, name)[r] = 0.0
    new.count[0] += m
    if rnd.radius > 0.0:
        _rounded_points(new, s, np.arange(r.start, r.stop), rnd)


def _touched_material(p, table, default, cand):
    """Material of new contacts: the weakest (lowest residual friction) of the faces that meet
    at the contact, B's touched face and A's two faces at its vertex, among those that lay on
    a flaw, joint or region boundary at the start; free faces give ``new_contact_material``.

    At a corner-to-corner touch across a joint the joint face is then the one that counts,
    not the intact rock of the flaw faces next to it.
    """
    off = p.vertex_offsets
    A, v, e = cand[:, 0], cand[:, 1], cand[:, 3]
    prev = np.where(v - 1 >= off[A], v - 1, off[A + 1] - 1)
    faces = np.column_stack([p.surface_material[e], p.surface_material[v],
                             p.surface_material[prev]])
    faces = np.where(faces >= 0, faces, -1)
    friction = np.where(faces >= 0, table.res_tan_friction[np.maximum(faces, 0)], np.inf)
    pick = np.argmin(friction, axis=1)
    chosen = faces[np.arange(len(cand)), pick]
    return np.where(chosen >= 0, chosen, default).astype(np.int32)


def covered_faces(c: Contacts, table, n_vertices: int) -> np.ndarray:
    """(nv,) bool: the block face starting at each vertex is glued to a neighbour by an intact
    bond (an intact contact of a bonded material has that face as its edge)."""
    covered = np.zeros(n_vertices, np.bool_)
    eb = c.edge_b[:c.n]
    bond = (c.broken[:c.n] == INTACT) & table.bonded()[c.material[:c.n]] & (eb >= 0)
    covered[eb[bond]] = True
    return covered


def sort_for_locality(c: Contacts) -> Contacts:
    """Contacts ordered by their lower block index: neighbours in memory touch nearby blocks."""
    order = np.argsort(np.minimum(c.block_a[:c.n], c.block_b[:c.n]), kind="stable")
    return compact(c, order)


@njit(cache=True)
def _survives_kernel(c, s, p, edge_end, bonded, wv, margin, slope, rnd):
    """Which live contacts survive the search (module docstring, 3), and each one's world
    point (px, py) and normal (qx, qy). A rounded contact (``rounding.py``) is judged by its
    rounded gap and normal, with A's corner centre for its point (px, py: where it touches)."""
    nc = c.count[0]
    keep = np.zeros(nc, np.bool_)
    px = np.empty(nc)
    py = np.empty(nc)
    qx = np.empty(nc)
    qy = np.empty(nc)
    for k in range(nc):
        a, b = c.block_a[k], c.block_b[k]
        xb, yb = body_point(s.pos, s.rot, b, c.point_b[k, 0], c.point_b[k, 1])
        if is_rounded(rnd, c, k):
            xa, ya, nx, ny, gap = rounded_contact(rnd, s, a, b, c.vertex_a[k], c.edge_b[k])
            d = rnd.arc[c.vertex_a[k]]
            px[k], py[k] = xa + d * nx, ya + d * ny          # the touch
        else:
            xa, ya = body_point(s.pos, s.rot, a, c.point_a[k, 0], c.point_a[k, 1])
            nx, ny = contact_normal(s, a, b, c.face[k], c.normal_b[k, 0], c.normal_b[k, 1])
            gap = (xb - xa) * nx + (yb - ya) * ny
            px[k], py[k] = xa, ya
        qx[k], qy[k] = nx, ny
        if not (p.active[a] and p.active[b]):
            continue
        if c.broken[k] == INTACT and bonded[c.material[k]]:
            keep[k] = True
            continue
        # a point of a shared edge that is not a vertex of A (vertex_a < 0) is a contact only
        # while the two faces stay parallel (initial contacts: all blocks start at theta = 0)
        va = c.vertex_a[k]
        if va < 0 and abs(s.theta[a] - s.theta[b]) > 0.2:
            continue
        if gap > margin:
            continue
        e, f = c.edge_b[k], edge_end[k]
        if e >= 0:
            ex, ey = wv[f, 0] - wv[e, 0], wv[f, 1] - wv[e, 1]
            ln = math.hypot(ex, ey)
            proj = ((xa - wv[e, 0]) * ex + (ya - wv[e, 1]) * ey) / ln
            if proj < -margin or proj > ln + margin:
                continue
        # the vertex must still be A's deepest point towards the face (``_supports``): else
        # the face is stale (A's edge now runs into it) and the search picks the right one
        if va >= 0 and not _supports(wv, p.vertex_offsets, a, va, -nx, -ny, slope):
            continue
        keep[k] = True
    return keep, px, py, qx, qy


def block_containing(props, pos, rot, xy) -> int:
    """The active block whose polygon contains ``xy`` (else the nearest centroid)."""
    d = np.hypot(*(pos - xy).T)
    off, local = props.vertex_offsets, props.local_vertices
    for b in np.argsort(d):
        if d[b] > props.radius[b] * 1.0001 and d[b] > d.min() + 2 * props.radius.max():
            break
        if not props.active[b]:
            continue
        c, s = rot[b]
        v = local[off[b]:off[b + 1]]
        w = pos[b] + np.column_stack([c * v[:, 0] - s * v[:, 1], s * v[:, 0] + c * v[:, 1]])
        e = np.roll(w, -1, axis=0) - w
        r = xy - w
        if np.all(e[:, 0] * r[:, 1] - e[:, 1] * r[:, 0] >= -1e-12 * props.radius[b] ** 2):
            return int(b)
    act = np.flatnonzero(props.active > 0)
    return int(act[np.argmin(d[act])])
