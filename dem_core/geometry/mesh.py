"""A conforming polygon mesh: shared vertex ids, T-junctions removed, the edge table.

Blocks that meet along an edge must have the same two end vertices there (that is what makes a
shared edge a contact). Where the corner of one block lies on the straight edge of another
(a T-junction, e.g. at a joint tip or along a region boundary), that corner is inserted into the
other block as a straight (180 degree) vertex.
"""
from __future__ import annotations

from itertools import chain

import numpy as np
import shapely
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
from scipy.spatial import cKDTree


def polygons_to_csr(polys) -> tuple:
    """CCW exterior coordinates of shapely polygons (no repeated end point) as (xy, offsets).

    Orientation comes from the signed (shoelace) area, not GEOS's ring test, which looks at the
    highest vertex only and can be fooled there by a zero-width spike of round-off size.
    """
    polys = np.asarray(polys, dtype=object)
    xy, idx = shapely.get_coordinates(shapely.get_exterior_ring(polys), return_index=True)
    last = np.r_[idx[1:] != idx[:-1], True]
    xy, idx = xy[~last], idx[~last]
    counts = np.bincount(idx, minlength=len(polys))
    off = np.r_[0, np.cumsum(counts)].astype(np.int64)
    area, _ = polygon_area_centroid(xy, off)
    cw = np.repeat(area < 0, counts)
    if cw.any():  # reverse the clockwise rings, keeping their first vertex
        start, n = np.repeat(off[:-1], counts), np.repeat(counts, counts)
        pos = np.arange(len(xy))
        xy = xy[np.where(cw, start + (start - pos) % n, pos)]
    return xy, off


def polygon_area_centroid(xy, offsets) -> tuple:
    """Area (m^2, positive for CCW) and centroid of CSR polygons (shoelace, vectorised)."""
    n = len(offsets) - 1
    owner = np.repeat(np.arange(n), np.diff(offsets))
    nxt = np.arange(len(xy)) + 1
    nxt[offsets[1:] - 1] = offsets[:-1]
    # relative to the first vertex of each block, for round-off
    x0 = xy[offsets[:-1]][owner]
    p, q = xy - x0, xy[nxt] - x0
    cr = p[:, 0] * q[:, 1] - q[:, 0] * p[:, 1]
    a2 = np.bincount(owner, cr, minlength=n)
    cx = np.bincount(owner, cr * (p[:, 0] + q[:, 0]), minlength=n)
    cy = np.bincount(owner, cr * (p[:, 1] + q[:, 1]), minlength=n)
    area = 0.5 * a2
    with np.errstate(invalid="ignore", divide="ignore"):
        cen = np.column_stack([cx, cy]) / (3.0 * a2[:, None]) + xy[offsets[:-1]]
    return area, cen


class BlockMesh:
    """Blocks as lists of vertex ids into ``X`` (CCW), with a region index per block."""

    def __init__(self, X, blocks, region, tol):
        self.X = np.asarray(X, float)
        self.blocks = blocks
        self.region = list(region)
        self.tol = tol

    @classmethod
    def from_csr(cls, xy, offsets, region, tol) -> "BlockMesh":
        """Merge vertices closer than ``tol`` (m), drop repeated consecutive vertices."""
        uniq, inv = np.unique(xy, axis=0, return_inverse=True)
        inv = inv.ravel()
        pairs = cKDTree(uniq).query_pairs(tol, output_type="ndarray")
        if len(pairs):
            g = coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(len(uniq),) * 2)
            _, lab = connected_components(g, directed=False)
            X = np.zeros((lab.max() + 1, 2))
            X[lab] = uniq
        else:
            lab, X = np.arange(len(uniq)), uniq
        ids = lab[inv].tolist()
        blocks, keep_region = [], []
        for b, (a, e) in enumerate(zip(offsets[:-1], offsets[1:])):
            loop = ids[a:e]
            loop = [v for k, v in enumerate(loop) if v != loop[k - 1]] if len(loop) > 1 else loop
            if len(loop) >= 3:
                blocks.append(loop)
                keep_region.append(region[b])
        mesh = cls(X, blocks, keep_region, tol)
        mesh.fix_t_junctions()
        return mesh

    # -- tables -------------------------------------------------------------------------------
    def csr(self) -> tuple:
        lens = np.fromiter((len(b) for b in self.blocks), np.int64, len(self.blocks))
        ids = np.fromiter(chain.from_iterable(self.blocks), np.int64, int(lens.sum()))
        return ids, np.r_[0, np.cumsum(lens)].astype(np.int64)

    def area_centroid(self) -> tuple:
        ids, off = self.csr()
        return polygon_area_centroid(self.X[ids], off)

    def edge_table(self) -> dict:
        """Shared and free edges.

        Returns dict with ``shared`` (m, 4) [block_a, block_b, v0, v1] where v0 -> v1 is the
        edge in block A's CCW order (so the outward normal of A points into B) and A < B, and
        ``free`` (k, 3) [block, v0, v1] for edges used by one block only.
        """
        ids, off = self.csr()
        nb = len(off) - 1
        owner = np.repeat(np.arange(nb), np.diff(off))
        nxt = np.arange(len(ids)) + 1
        nxt[off[1:] - 1] = off[:-1]
        v0, v1 = ids, ids[nxt]
        nv = len(self.X)
        key = np.minimum(v0, v1) * nv + np.maximum(v0, v1)
        order = np.argsort(key, kind="stable")
        ks = key[order]
        _, start, counts = np.unique(ks, return_index=True, return_counts=True)
        if np.any(counts > 2):
            bad = order[start[counts > 2][0]]
            raise RuntimeError(f"edge {self.X[v0[bad]]}-{self.X[v1[bad]]} is used by more than "
                               "two blocks: blocks overlap (a bug in the geometry build)")
        two = start[counts == 2]
        ia, ib = order[two], order[two + 1]
        shared = np.column_stack([owner[ia], owner[ib], v0[ia], v1[ia]])
        one = order[start[counts == 1]]
        free = np.column_stack([owner[one], v0[one], v1[one]])
        return {"shared": shared, "free": free}

    # -- repair -------------------------------------------------------------------------------
    def fix_t_junctions(self) -> int:
        """Insert vertices that lie on another block's edge into that block. Returns count."""
        free = self.edge_table()["free"]
        if len(free) == 0:
            return 0
        segs = np.stack([self.X[free[:, 1]], self.X[free[:, 2]]], axis=1)
        tree = shapely.STRtree(shapely.linestrings(segs))
        cand = np.unique(free[:, 1:])
        pi, ei = tree.query(shapely.points(self.X[cand]), predicate="dwithin", distance=self.tol)
        inserts = {}
        for p, e in zip(cand[pi], ei):
            b, a, c = free[e]
            if p == a or p == c:
                continue
            d = self.X[c] - self.X[a]
            t = float((self.X[p] - self.X[a]) @ d / (d @ d))
            if 0.0 < t < 1.0:
                inserts.setdefault((int(b), int(a), int(c)), []).append((t, int(p)))
        for (b, a, c), lst in inserts.items():
            loop = self.blocks[b]
            k = next(i for i in range(len(loop)) if loop[i] == a and loop[(i + 1) % len(loop)] == c)
            self.blocks[b] = loop[:k + 1] + [p for _, p in sorted(lst)] + loop[k + 1:]
        return sum(len(v) for v in inserts.values())
