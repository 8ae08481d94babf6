"""Point contacts (a vertex of block A against a face of block B), as flat arrays with headroom.

Geometry of contact k (all "local" vectors are in the owning block's frame at theta = 0;
``kinematics``)::

    x_a = pos[A] + R(theta_A) point_a        the vertex of A (the contact point)
    x_b = pos[B] + R(theta_B) point_b        a point on B's face (coincident with x_a at creation)
    n   = contact_normal(face, normal_b)     unit normal from A into B: B's face normal for a
                                             vertex against a face, the bisector of both faces'
                                             normals for two faces (both blocks agree on it)
    t   = (-n_y, n_x)
    u_n = (x_b - x_a) . n                    normal opening, m (> 0 open, < 0 overlap)
    u_s = (x_b - x_a) . t                    shear displacement of B relative to A, m

Stresses (compression positive) follow from the increments of u_n and u_s (``law.py``); the
force on B is ``L (sn n + ts t)``, the force on A its opposite, both at the contact's anchor
point: the vertex it belongs to (A's, or B's for the half of a shared edge that ends at B's
corner), midway between x_a and x_b when neither is a vertex. Equal, opposite, collinear
forces: linear and angular momentum are conserved exactly. When a contact slips or opens, the
other point is moved to sit across the normal from the anchor (x_b = x_a + u_n n for anchor A),
so x_b - x_a stays a normal gap: a sliding contact follows its vertex, and the increments
never mix a large slid distance into the normal (which a turning normal would otherwise do).
The rule depends on which block owns the corner, not on which is called A, so a scene and its
mirror image behave alike.

A shared edge p0-p1 between A and B gives two face contacts, each of half the edge's length:
the vertex of A at p0 against B's face, and the vertex of B at p1 against A's face.
"""
from __future__ import annotations

import dataclasses
from typing import NamedTuple

import numpy as np
from numba import njit

from ..step.kinematics import contact_normal
from .rounding import is_rounded, no_rounding, rounded_contact

__all__ = ["Contacts", "INTACT", "TENSION", "SHEAR", "UNBONDED", "ANCHOR_A", "ANCHOR_B",
           "ANCHOR_MID", "initial_contacts", "split_edges"]

# Contacts.anchor: the point a contact keeps when it slips or opens (``forces.contact_update``).
ANCHOR_A, ANCHOR_B, ANCHOR_MID = 0, 1, 2
# Contacts.broken: why the contact is at residual strength.
INTACT, TENSION, SHEAR, UNBONDED = 0, 1, 2, 3   # UNBONDED: made by the search, never bonded


_VECTORS = ("point_a", "point_b", "normal_b")
_DTYPES = {"block_a": np.int32, "block_b": np.int32, "vertex_a": np.int32,
           "edge_b": np.int32, "partner": np.int32, "material": np.int32, "broken": np.int8, "slipping": np.int8,
           "anchor": np.int8, "face": np.int8}


class Contacts(NamedTuple):
    """Contact arrays of capacity ``cap``; the first ``count[0]`` rows are live.

    block_a, block_b : (cap,) int32. Vertex owner A and face owner B.
    vertex_a : (cap,) int32. Global vertex index of A's vertex, -1 if the point is not a vertex.
    edge_b : (cap,) int32. Global index of the first vertex of B's face, -1 if unknown.
    point_a, point_b : (cap, 2) float64, m. Local geometry (module docstring).
    normal_b : (cap, 2) float64. The A -> B direction fixed in B (for a face contact also A's
        face normal in A's frame: both were made unrotated; ``kinematics.contact_normal``).
    face : (cap,) int8. 1 for two faces in contact (the bisector normal), 0 for a vertex
        against a face (the face's normal).
    anchor : (cap,) int8. Which point the contact follows when it slips or opens: ANCHOR_A
        (A's vertex), ANCHOR_B (the point is a vertex of B), ANCHOR_MID (neither: midway).
    partner : (cap,) int32. The other half of the same shared edge (its row), -1 for a
        contact that is not half of an edge: the two carry the edge's stress as one linear
        interface element (``forces.edge_correction``).
    length : (cap,) float64, m. Length the contact represents.
    kn, ks : (cap,) float64, Pa/m. Stiffness (material in series with the blocks), set when the
        contact is made.
    material : (cap,) int32. Row of the material table.
    sn, ts : (cap,) float64, Pa. Normal (compression +) and shear stress the contact transmits.
    sn_elastic : (cap,) float64, Pa. Normal stress of the elastic spring, updated by increments:
        equal to ``sn`` while the contact is closed; below the tension limit the contact is
        separated (``sn`` = 0) and -sn_elastic / kn is how far it is open beyond the limit.
    un, us : (cap,) float64, m. Normal opening and shear displacement along the current normal
        at the last step (their increments drive the law).
    up : (cap,) float64, m. Plastic (slip) shear displacement so far.
    broken : (cap,) int8. INTACT, TENSION, SHEAR or UNBONDED.
    slipping : (cap,) int8. 1 if at the Coulomb limit in the last step.
    edge_x0 : (cap,) float64, m. The compressed length of the contact's edge element at the
        last step where the contact was closed (its whole length with both ends closed; 0: no
        edge element, or this end open), so that a compressed length that grows brings no
        shear with it (``forces.edge_correction``).
    damage : (cap,) float64. kappa, the damage variable of a softening bond (0 intact, 1
        fully softened; ``softening.py``); 0 for every other contact.
    work_fracture, work_friction : (cap,) float64, J/m. Plastic work the contact has spent so
        far on softening (fracture) and on slip against friction (per metre of thickness).
    count : (1,) int64. Live contacts.
    """

    block_a: np.ndarray
    block_b: np.ndarray
    vertex_a: np.ndarray
    edge_b: np.ndarray
    point_a: np.ndarray
    point_b: np.ndarray
    normal_b: np.ndarray
    face: np.ndarray
    anchor: np.ndarray
    partner: np.ndarray
    length: np.ndarray
    kn: np.ndarray
    ks: np.ndarray
    material: np.ndarray
    sn: np.ndarray
    ts: np.ndarray
    sn_elastic: np.ndarray
    un: np.ndarray
    us: np.ndarray
    up: np.ndarray
    broken: np.ndarray
    slipping: np.ndarray
    edge_x0: np.ndarray
    damage: np.ndarray
    work_fracture: np.ndarray
    work_friction: np.ndarray
    count: np.ndarray

    @classmethod
    def empty(cls, cap: int) -> "Contacts":
        arrs = {}
        for name in ARRAYS:
            shape = (cap, 2) if name in _VECTORS else (cap,)
            arrs[name] = np.zeros(shape, dtype=_DTYPES.get(name, np.float64))
        arrs["partner"][:] = -1
        return cls(**arrs, count=np.zeros(1, np.int64))

    @property
    def n(self) -> int:
        return int(self.count[0])

    @property
    def capacity(self) -> int:
        return int(self.block_a.shape[0])

    def with_capacity(self, cap: int) -> "Contacts":
        """A copy with room for ``cap`` contacts (the live rows are kept)."""
        return self.take(np.arange(self.n), cap)

    def take(self, rows, cap: int | None = None) -> "Contacts":
        """A Contacts holding only ``rows`` (in that order), of capacity ``cap`` (default
        1.5 x rows + 64)."""
        rows = np.asarray(rows, dtype=np.int64)
        cap = int(rows.size * 1.5) + 64 if cap is None else max(int(cap), rows.size)
        new = Contacts.empty(cap)
        for name in ARRAYS:
            getattr(new, name)[:rows.size] = getattr(self, name)[rows]
        new.count[0] = rows.size
        # partners follow their rows; a partner left out leaves its half alone
        where = np.full(self.n + 1, -1, np.int64)
        where[rows] = np.arange(rows.size)
        old = self.partner[rows].astype(np.int64)
        new.partner[:rows.size] = where[np.where(old >= 0, old, self.n)]
        new.edge_x0[:rows.size][new.partner[:rows.size] < 0] = 0.0      # no edge left
        return new

    def live(self, name: str) -> np.ndarray:
        """The live rows of one array (a view)."""
        return getattr(self, name)[:self.n]

    def state(self) -> np.ndarray:
        """(n,) int8: 0 intact, 1 slipping, 2 broken in tension, 3 broken in shear, 4 unbonded."""
        s = np.where(self.slipping[:self.n] > 0, 1, 0).astype(np.int8)
        b = self.broken[:self.n]
        s[b == TENSION] = 2
        s[b == SHEAR] = 3
        s[b == UNBONDED] = 4
        return s

    def position(self, pos, rot) -> np.ndarray:
        """(n, 2) world position of each contact point (the vertex of A), m."""
        a = self.block_a[:self.n]
        cos_a, sin_a = rot[a, 0], rot[a, 1]
        p = self.point_a[:self.n]
        return pos[a] + np.column_stack([cos_a * p[:, 0] - sin_a * p[:, 1],
                                         sin_a * p[:, 0] + cos_a * p[:, 1]])

    def normal(self, s, rnd=None) -> np.ndarray:
        """(n, 2) world unit normal of each contact from A into B at the pose ``s``
        (BlockState; ``kinematics.contact_normal``; with rounded corners ``rnd``, a
        ``rounding.Rounding``, that of the rounded shapes)."""
        out = np.empty((self.n, 2))
        _normals(self, s, no_rounding() if rnd is None else rnd, out)
        return out

    def to_dict(self) -> dict:
        return {f"contacts.{name}": getattr(self, name)[:self.n] for name in ARRAYS}

    @classmethod
    def from_dict(cls, d: dict, headroom: float = 1.5) -> "Contacts":
        n = len(d["contacts.block_a"])
        c = cls.empty(int(n * headroom) + 64)
        for name in ARRAYS:
            # (files before partners, or before softening: -1 and zeros)
            if f"contacts.{name}" in d or name not in _ADDED:
                getattr(c, name)[:n] = d[f"contacts.{name}"]
        c.count[0] = n
        return c


ARRAYS = tuple(f for f in Contacts._fields if f != "count")
# arrays that model files written before them do not have
_ADDED = ("partner", "damage", "work_fracture", "work_friction", "edge_x0")


@njit(cache=True)
def _normals(c, s, rnd, out):
    for k in range(out.shape[0]):
        if is_rounded(rnd, c, k):
            _, _, out[k, 0], out[k, 1], _ = rounded_contact(rnd, s, c.block_a[k],
                                                            c.block_b[k], c.vertex_a[k],
                                                            c.edge_b[k])
        else:
            out[k, 0], out[k, 1] = contact_normal(s, c.block_a[k], c.block_b[k], c.face[k],
                                                  c.normal_b[k, 0], c.normal_b[k, 1])


@njit(cache=True)
def _vertex_and_edge(vertices, offsets, block_a, block_b, points, mids, normal_ab, tol):
    """Index of A's vertex at ``points`` and of B's edge through ``mids`` (-1 if none)."""
    m = block_a.shape[0]
    vertex_a = np.full(m, -1, np.int32)
    on_vertex_b = np.zeros(m, np.bool_)
    edge_b = np.full(m, -1, np.int32)
    for i in range(m):
        a, b = block_a[i], block_b[i]
        best = tol
        for j in range(offsets[a], offsets[a + 1]):
            d = np.hypot(vertices[j, 0] - points[i, 0], vertices[j, 1] - points[i, 1])
            if d <= best:
                best, vertex_a[i] = d, j
        for j in range(offsets[b], offsets[b + 1]):
            if np.hypot(vertices[j, 0] - points[i, 0], vertices[j, 1] - points[i, 1]) <= tol:
                on_vertex_b[i] = True
        for j in range(offsets[b], offsets[b + 1]):
            k = j + 1 if j + 1 < offsets[b + 1] else offsets[b]
            ex, ey = vertices[k, 0] - vertices[j, 0], vertices[k, 1] - vertices[j, 1]
            ln = np.hypot(ex, ey)
            ox, oy = ey / ln, -ex / ln          # outward normal of a CCW polygon's edge
            dist = abs((mids[i, 0] - vertices[j, 0]) * ox + (mids[i, 1] - vertices[j, 1]) * oy)
            along = ((mids[i, 0] - vertices[j, 0]) * ex + (mids[i, 1] - vertices[j, 1]) * ey) / ln
            # B's outward normal is minus the A -> B normal; of the collinear pieces of a split
            # side, the one the shared edge lies on
            if -(ox * normal_ab[i, 0] + oy * normal_ab[i, 1]) > 0.99 and dist <= tol and \
                    -tol <= along <= ln + tol:
                edge_b[i] = j
                break
    return vertex_a, on_vertex_b, edge_b


def split_edges(bs, max_length):
    """``bs`` with every shared edge e longer than ``max_length[e]`` (m; inf: kept) split into
    n = ceil(L / max_length) equal edges between the same blocks, with the same normal and
    material: the contacts of deformable blocks, one pair per boundary segment of their zones
    (UDEC: a contact at each boundary gridpoint). A split edge's inner points are no block's
    vertices: their contacts are anchored midway (points, ``ANCHOR_MID``)."""
    L = np.asarray(bs.edge_length, np.float64)
    lim = np.asarray(max_length, np.float64)
    n = np.ones(len(L), np.int64)
    cut = np.isfinite(lim)
    n[cut] = np.maximum(1, np.ceil(L[cut] / lim[cut] - 1e-9)).astype(np.int64)
    if np.all(n == 1):
        return bs
    idx = np.repeat(np.arange(len(L)), n)
    k = np.arange(n.sum()) - np.repeat(np.cumsum(n) - n, n)
    p0, p1 = np.asarray(bs.edge_p0, np.float64), np.asarray(bs.edge_p1, np.float64)
    d = (p1 - p0)[idx]
    q0 = p0[idx] + (k / n[idx])[:, None] * d
    q1 = np.where((k == n[idx] - 1)[:, None], p1[idx], p0[idx] + ((k + 1) / n[idx])[:, None] * d)
    return dataclasses.replace(bs, edge_p0=q0, edge_p1=q1, edge_block_a=bs.edge_block_a[idx],
                               edge_block_b=bs.edge_block_b[idx],
                               edge_normal=bs.edge_normal[idx], edge_length=(L / n)[idx],
                               edge_material=bs.edge_material[idx])


def initial_contacts(bs, headroom: float = 1.5) -> Contacts:
    """Two contacts per shared edge of a BlockSystem (stiffness set by the caller).

    Local points and normals are relative to each block's centroid at theta = 0.
    """
    ne = bs.n_edges
    c = Contacts.empty(int(2 * ne * headroom) + 64)
    tol = 1e-6 * float(np.sqrt(np.median(bs.area))) if bs.n_blocks else 0.0
    a, b = bs.edge_block_a.astype(np.int64), bs.edge_block_b.astype(np.int64)
    n = np.asarray(bs.edge_normal, dtype=np.float64)
    p0, p1 = np.asarray(bs.edge_p0, np.float64), np.asarray(bs.edge_p1, np.float64)
    mid = 0.5 * (p0 + p1)
    # rows 2e: vertex of A at p0 against B's edge; rows 2e+1: vertex of B at p1 against A's edge
    ca = np.empty(2 * ne, np.int64)
    cb = np.empty(2 * ne, np.int64)
    ca[0::2], ca[1::2] = a, b
    cb[0::2], cb[1::2] = b, a
    pts = np.empty((2 * ne, 2))
    pts[0::2], pts[1::2] = p0, p1
    nrm = np.empty((2 * ne, 2))
    nrm[0::2], nrm[1::2] = n, -n
    mids = np.repeat(mid, 2, axis=0)
    cent = np.asarray(bs.centroid, np.float64)
    va, vb, eb = _vertex_and_edge(np.asarray(bs.vertices, np.float64),
                              np.asarray(bs.vertex_offsets, np.int64), ca, cb, pts, mids, nrm, tol)
    m = 2 * ne
    c.block_a[:m], c.block_b[:m] = ca, cb
    c.vertex_a[:m], c.edge_b[:m] = va, eb
    c.point_a[:m] = pts - cent[ca]
    c.point_b[:m] = pts - cent[cb]
    c.normal_b[:m] = nrm
    c.face[:m] = 1                    # face against face: both blocks unrotated at the start
    c.anchor[:m] = np.where(va >= 0, ANCHOR_A, np.where(vb, ANCHOR_B, ANCHOR_MID))
    c.partner[0:m:2], c.partner[1:m:2] = np.arange(1, m, 2), np.arange(0, m, 2)
    c.length[:m] = 0.5 * np.repeat(np.asarray(bs.edge_length, np.float64), 2)
    c.material[:m] = np.repeat(np.asarray(bs.edge_material), 2)
    c.count[0] = m
    return c


def surface_materials(c: Contacts, n_vertices: int) -> np.ndarray:
    """(n_vertices,) material id of the block face starting at each vertex, -1 if free.

    Every face of a shared edge is B's edge of one of the edge's two initial contacts, so the
    initial contacts label every face that touches another block at the start.
    """
    out = np.full(n_vertices, -1, np.int32)
    eb = c.edge_b[:c.n]
    known = eb >= 0
    out[eb[known]] = c.material[:c.n][known]
    return out
