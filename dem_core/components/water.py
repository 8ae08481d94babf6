"""Water: hydrostatic pressure of a water table (``dem_core.workflow.water.WaterTable``) on the
contacts below it and on the exposed faces of blocks below it.

A contact's springs carry the effective normal stress sn' (the law's ``sn``; strength, slip
and cut-off work on it, ``law.py``); the water pushes its two blocks apart with p L along the
normal (n from A into B: +p L n on B, -p L n on A), at A's contact point (with rounded
corners, a rounded contact's station: where its arc touches, ``contact.division``). A block face on the
model's outer boundary, or bared by an excavation, gets the pressure's resultant
-integral(p n_out ds) over its wetted part (p linear along the face, integrated exactly), at
the resultant's point. The two together give a submerged block its buoyancy (gamma_w x
area): the contacts of an edge carry half its length each at its two ends, so a linear p is
summed exactly. Pressure at contacts is read from the table when the bundle is made (each
run of steps, at most ``Model.history.every`` steps; between searches no point moves more
than half the search margin); faces read it every step.

Which contacts: with ``on="joints"`` every contact whose material is not a flaw ("joint:...",
"boundary:...", new contacts) and broken flaws (cracks: a flaw that breaks during a run of
steps is wetted from the next run, at most ``Model.history.every`` steps later); with
``on="all"`` intact flaws too.
"""
from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit

from ..contact.contacts import Contacts
from ..contact.division import interface_stations
from ..contact.rounding import rounded_rows
from ..step.kinematics import body_point, contact_normal

__all__ = ["Water", "add_water", "water_bundle", "no_water", "exposed_faces"]


class Water(NamedTuple):
    """contacts : the model's Contacts (the same arrays); contact (nw,) int64 rows of it below
    the table; pressure (nw,) Pa, read at point (nw, 2) m, in A's body frame, where the push
    acts (A's contact point, or a rounded contact's station when the bundle was made);
    always (nw,) int8 (0: a flaw, wetted only once broken);
    face_block (nf,) int64; face_p0, face_p1 (nf, 2) m, a face's ends in its block's body
    frame (counter-clockwise, so the outward normal is (dy, -dx) / L); surface (m, 2) m the
    table's polyline (held flat beyond its ends); unit_weight (1,) N/m^3."""

    contacts: Contacts
    contact: np.ndarray
    pressure: np.ndarray
    point: np.ndarray
    always: np.ndarray
    face_block: np.ndarray
    face_p0: np.ndarray
    face_p1: np.ndarray
    surface: np.ndarray
    unit_weight: np.ndarray


def no_water(contacts) -> Water:
    """The empty bundle: no water table."""
    return Water(contacts, np.zeros(0, np.int64), np.zeros(0), np.zeros((0, 2)),
                 np.zeros(0, np.int8),
                 np.zeros(0, np.int64), np.zeros((0, 2)), np.zeros((0, 2)), np.zeros((2, 2)),
                 np.zeros(1))


def water_bundle(table, contacts, state, material_names, faces, corners=None) -> Water:
    """The bundle of ``table`` (WaterTable or None) for the live ``contacts`` at pose ``state``;
    ``faces`` = (block, p0, p1) from ``exposed_faces``; ``corners`` the Rounding (None:
    sharp corners)."""
    if table is None:
        return no_water(contacts)
    xy = contacts.position(state.pos, state.rot)
    local = contacts.point_a[:contacts.n].copy()
    if corners is not None and corners.radius > 0.0:
        rounded = rounded_rows(contacts, corners)
        if rounded.size:
            xy[rounded] = interface_stations(contacts, state, corners)[0][rounded]
            a = contacts.block_a[rounded]
            dx, dy = xy[rounded, 0] - state.pos[a, 0], xy[rounded, 1] - state.pos[a, 1]
            cos_a, sin_a = state.rot[a, 0], state.rot[a, 1]
            local[rounded] = np.column_stack([cos_a * dx + sin_a * dy, cos_a * dy - sin_a * dx])
    p = table.pressure(xy[:, 0], xy[:, 1])
    flaw = np.array([n.startswith("flaw:") for n in material_names] + [False], dtype=bool)
    mat = contacts.material[:contacts.n]
    always = np.ones(contacts.n, np.int8) if table.on == "all" else (~flaw[mat]).astype(np.int8)
    # an intact flaw (on="joints") is dry: left out here, it costs nothing in the step
    rows = np.flatnonzero((p > 0.0) & ((always != 0) | (contacts.broken[:contacts.n] != 0)))
    s = table.surface
    surf = np.array([[-1.0, float(s)], [1.0, float(s)]]) if isinstance(s, (int, float)) \
        else np.asarray(s, dtype=np.float64)
    return Water(contacts, rows.astype(np.int64), p[rows], local[rows], always[rows], *faces,
                 surf,
                 np.array([float(table.unit_weight)]))


def exposed_faces(blocks, active, tol=None) -> tuple:
    """(block, p0, p1) of every exposed piece of an active block's edges, in body coordinates:
    an edge minus the shared edges (``BlockSystem.edge_*``) it has with other active blocks,
    so the model's outer boundary and the faces an excavation bared."""
    v, off, cen = blocks.vertices, blocks.vertex_offsets, blocks.centroid
    tol = 1e-9 * float(np.ptp(v, axis=0).max()) if tol is None else tol
    ea, eb = blocks.edge_block_a, blocks.edge_block_b
    live = (active[ea] != 0) & (active[eb] != 0)
    mine = {}
    for e in np.flatnonzero(live):
        for b in (ea[e], eb[e]):
            mine.setdefault(int(b), []).append(e)
    out_b, out_0, out_1 = [], [], []
    for b in np.flatnonzero(active != 0):
        poly = v[off[b]:off[b + 1]]
        shared = mine.get(int(b), [])
        for i in range(len(poly)):
            p, q = poly[i], poly[(i + 1) % len(poly)]
            for t0, t1 in _uncovered(p, q, blocks.edge_p0[shared], blocks.edge_p1[shared], tol):
                out_b.append(b)
                out_0.append(p + t0 * (q - p) - cen[b])
                out_1.append(p + t1 * (q - p) - cen[b])
    return (np.asarray(out_b, np.int64), np.asarray(out_0, float).reshape(-1, 2),
            np.asarray(out_1, float).reshape(-1, 2))


def _uncovered(p, q, e0, e1, tol):
    """Pieces [t0, t1] of segment p -> q not covered by the segments e0 -> e1 lying on it."""
    d = q - p
    L2 = float(d @ d)
    nrm = np.array([-d[1], d[0]]) / np.sqrt(L2)
    on = (np.abs((e0 - p) @ nrm) < tol) & (np.abs((e1 - p) @ nrm) < tol)
    ta, tb = ((e0[on] - p) @ d) / L2, ((e1[on] - p) @ d) / L2
    cover = sorted(zip(np.minimum(ta, tb), np.maximum(ta, tb)))
    pieces, t = [], 0.0
    eps = tol / np.sqrt(L2)
    for lo, hi in cover:
        if lo > t + eps:
            pieces.append((t, min(lo, 1.0)))
        t = max(t, hi)
        if t >= 1.0 - eps:
            break
    if t < 1.0 - eps:
        pieces.append((t, 1.0))
    return [(a, b) for a, b in pieces if b - a > eps]


@njit(cache=True, inline="always")
def _height(surface, x):
    """Height of the polyline ``surface`` above x (flat beyond its ends); a scan, as a water
    table has few points (cheaper than a call of ``np.interp`` here: docs/performance.md,
    "Support elements")."""
    m = surface.shape[0]
    if x <= surface[0, 0]:
        return surface[0, 1]
    for i in range(1, m):
        if x <= surface[i, 0]:
            x0, y0, x1, y1 = surface[i - 1, 0], surface[i - 1, 1], surface[i, 0], surface[i, 1]
            return y0 + (y1 - y0) * (x - x0) / (x1 - x0)
    return surface[m - 1, 1]


@njit(cache=True, inline="always")
def _push(s, b, fx, fy, x, y):
    s.force[b, 0] += fx
    s.force[b, 1] += fy
    s.force[b, 2] += (x - s.pos[b, 0]) * fy - (y - s.pos[b, 1]) * fx


@njit(cache=True)
def add_water(w, s, p):
    """Water forces on contacts and exposed faces (module docstring), N/m."""
    c = w.contacts
    for r in range(w.contact.shape[0]):
        k = w.contact[r]
        if w.always[r] == 0 and c.broken[k] == 0:
            continue
        a, b = c.block_a[k], c.block_b[k]
        xa, ya = body_point(s.pos, s.rot, a, w.point[r, 0], w.point[r, 1])
        nx, ny = contact_normal(s, a, b, c.face[k], c.normal_b[k, 0], c.normal_b[k, 1])
        f = w.pressure[r] * c.length[k]
        _push(s, b, f * nx, f * ny, xa, ya)
        _push(s, a, -f * nx, -f * ny, xa, ya)
    gw = w.unit_weight[0]
    for j in range(w.face_block.shape[0]):
        b = w.face_block[j]
        if p.active[b] == 0:
            continue
        x0, y0 = body_point(s.pos, s.rot, b, w.face_p0[j, 0], w.face_p0[j, 1])
        x1, y1 = body_point(s.pos, s.rot, b, w.face_p1[j, 0], w.face_p1[j, 1])
        p0 = gw * (_height(w.surface, x0) - y0)
        p1 = gw * (_height(w.surface, x1) - y1)
        if p0 <= 0.0 and p1 <= 0.0:
            continue
        force, t = _wet_resultant(p0, p1)
        dx, dy = x1 - x0, y1 - y0               # |d| = L: force = resultant per length x L
        # outward normal (dy, -dx) / L, pressure pushes inward: -force L n_out
        _push(s, b, -force * dy, force * dx, x0 + t * dx, y0 + t * dy)


@njit(cache=True, inline="always")
def _wet_resultant(p0, p1):
    """(mean pressure over the whole face, Pa; position 0..1 of the resultant) of the positive
    part of the linear pressure p0 -> p1 along a face."""
    if p0 >= 0.0 and p1 >= 0.0:
        return 0.5 * (p0 + p1), (p0 + 2.0 * p1) / (3.0 * (p0 + p1))
    tc = p0 / (p0 - p1)                         # where p = 0
    if p0 > 0.0:
        return 0.5 * tc * p0, tc / 3.0
    return 0.5 * (1.0 - tc) * p1, tc + 2.0 * (1.0 - tc) / 3.0
