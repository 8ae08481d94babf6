"""Point contacts (a vertex of block A against an edge of block B), as flat arrays with headroom.

Geometry of contact k (all "local" vectors are in the owning block's frame at theta = 0)::

    x_a = pos[A] + R(theta_A) point_a        the vertex of A (the contact point)
    x_b = pos[B] + R(theta_B) point_b        a point on B's edge (coincident with x_a at creation)
    n   = R(theta_B) normal_b                unit normal from A into B (minus B's outward normal)
    t   = (-n_y, n_x)
    u_n = (x_b - x_a) . n                    normal opening, m (> 0 open, < 0 overlap)
    u_s = (x_b - x_a) . t                    shear displacement of B relative to A, m

Stresses (compression positive): ``sn = -kn u_n`` and ``ts = -ks (u_s - u_p)`` with ``u_p`` the
plastic (slip) part; the force on B is ``L (sn n + ts t)`` at ``x_a``, the force on A its
opposite. Applying both at ``x_a`` makes the forces the exact gradient of the spring energy
0.5 L (kn u_n^2 + ks (u_s - u_p)^2), so an elastic system conserves energy and angular momentum.

A shared edge p0-p1 between A and B gives two contacts, each of half the edge's length: the
vertex of A at p0 against B's edge, and the vertex of B at p1 against A's edge.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numba import njit

__all__ = ["Contacts", "INTACT", "TENSION", "SHEAR", "UNBONDED", "initial_contacts"]

# Contacts.broken: why the contact is at residual strength.
INTACT, TENSION, SHEAR, UNBONDED = 0, 1, 2, 3   # UNBONDED: made by the search, never bonded


@dataclass
class Contacts:
    """Contact arrays of capacity ``cap``; the first ``n`` rows are live.

    Attributes
    ----------
    n : int. Live contacts.
    block_a, block_b : (cap,) int32. Vertex owner A and edge owner B.
    vertex_a : (cap,) int32. Global vertex index of A's vertex, -1 if the point is not a vertex.
    edge_b : (cap,) int32. Global index of the first vertex of B's edge, -1 if unknown.
    point_a, point_b, normal_b : (cap, 2) float64. Local geometry (module docstring).
    length : (cap,) float64, m. Length the contact represents.
    kn, ks : (cap,) float64, Pa/m. Effective stiffness (material in series with the blocks).
    material : (cap,) int32. Row of the material table.
    sn, ts : (cap,) float64, Pa. Normal (compression +) and shear stress on B.
    un, us, up : (cap,) float64, m. Normal opening, total and plastic shear displacement.
    broken : (cap,) int8. INTACT, TENSION, SHEAR or UNBONDED.
    slipping : (cap,) int8. 1 if at the Coulomb limit in the last step.
    """

    n: int
    block_a: np.ndarray
    block_b: np.ndarray
    vertex_a: np.ndarray
    edge_b: np.ndarray
    point_a: np.ndarray
    point_b: np.ndarray
    normal_b: np.ndarray
    length: np.ndarray
    kn: np.ndarray
    ks: np.ndarray
    material: np.ndarray
    sn: np.ndarray
    ts: np.ndarray
    un: np.ndarray
    us: np.ndarray
    up: np.ndarray
    broken: np.ndarray
    slipping: np.ndarray

    ARRAYS = ("block_a", "block_b", "vertex_a", "edge_b", "point_a", "point_b", "normal_b",
              "length", "kn", "ks", "material", "sn", "ts", "un", "us", "up", "broken",
              "slipping")
    DTYPES = {"block_a": np.int32, "block_b": np.int32, "vertex_a": np.int32,
              "edge_b": np.int32, "material": np.int32, "broken": np.int8,
              "slipping": np.int8}

    @classmethod
    def empty(cls, cap: int) -> "Contacts":
        arrs = {}
        for name in cls.ARRAYS:
            shape = (cap, 2) if name in ("point_a", "point_b", "normal_b") else (cap,)
            arrs[name] = np.zeros(shape, dtype=cls.DTYPES.get(name, np.float64))
        return cls(n=0, **arrs)

    @property
    def capacity(self) -> int:
        return int(self.block_a.shape[0])

    def with_capacity(self, cap: int) -> "Contacts":
        """A copy with room for ``cap`` contacts (the live rows are kept)."""
        new = Contacts.empty(max(cap, self.n))
        for name in self.ARRAYS:
            getattr(new, name)[:self.n] = getattr(self, name)[:self.n]
        new.n = self.n
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

    def position(self, pos, theta) -> np.ndarray:
        """(n, 2) world position of each contact point (the vertex of A), m."""
        a = self.block_a[:self.n]
        c, s = np.cos(theta[a]), np.sin(theta[a])
        p = self.point_a[:self.n]
        return pos[a] + np.column_stack([c * p[:, 0] - s * p[:, 1], s * p[:, 0] + c * p[:, 1]])

    def to_dict(self) -> dict:
        return {f"contacts.{name}": getattr(self, name)[:self.n] for name in self.ARRAYS}

    @classmethod
    def from_dict(cls, d: dict, headroom: float = 1.5) -> "Contacts":
        n = len(d["contacts.block_a"])
        c = cls.empty(int(n * headroom) + 64)
        for name in cls.ARRAYS:
            getattr(c, name)[:n] = d[f"contacts.{name}"]
        c.n = n
        return c


@njit(cache=True)
def _vertex_and_edge(vertices, offsets, block_a, block_b, points, mids, normal_ab, tol):
    """Index of A's vertex at ``points`` and of B's edge through ``mids`` (-1 if none)."""
    m = block_a.shape[0]
    vertex_a = np.full(m, -1, np.int32)
    edge_b = np.full(m, -1, np.int32)
    for i in range(m):
        a, b = block_a[i], block_b[i]
        best = tol
        for j in range(offsets[a], offsets[a + 1]):
            d = np.hypot(vertices[j, 0] - points[i, 0], vertices[j, 1] - points[i, 1])
            if d <= best:
                best, vertex_a[i] = d, j
        for j in range(offsets[b], offsets[b + 1]):
            k = j + 1 if j + 1 < offsets[b + 1] else offsets[b]
            ex, ey = vertices[k, 0] - vertices[j, 0], vertices[k, 1] - vertices[j, 1]
            ln = np.hypot(ex, ey)
            ox, oy = ey / ln, -ex / ln          # outward normal of a CCW polygon's edge
            dist = abs((mids[i, 0] - vertices[j, 0]) * ox + (mids[i, 1] - vertices[j, 1]) * oy)
            # B's outward normal is minus the A -> B normal
            if -(ox * normal_ab[i, 0] + oy * normal_ab[i, 1]) > 0.99 and dist <= tol:
                edge_b[i] = j
                break
    return vertex_a, edge_b


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
    va, eb = _vertex_and_edge(np.asarray(bs.vertices, np.float64),
                              np.asarray(bs.vertex_offsets, np.int64), ca, cb, pts, mids, nrm, tol)
    m = 2 * ne
    c.block_a[:m], c.block_b[:m] = ca, cb
    c.vertex_a[:m], c.edge_b[:m] = va, eb
    c.point_a[:m] = pts - cent[ca]
    c.point_b[:m] = pts - cent[cb]
    c.normal_b[:m] = nrm
    c.length[:m] = 0.5 * np.repeat(np.asarray(bs.edge_length, np.float64), 2)
    c.material[:m] = np.repeat(np.asarray(bs.edge_material), 2)
    c.n = m
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
