"""The block system: rigid convex polygons and their initial (shared-edge) contacts, as flat arrays.

This is the hand-over format between the geometry layer (which builds it from regions, joint
sets and Voronoi tessellation) and the mechanics (which turns it into masses, contacts and a
state), and it is what ``continuum_ref`` reads to mesh the same area.

Conventions
-----------
- SI units (m, m^2). Coordinates are (x, y) with y up.
- Block vertices are stored counter-clockwise, convex, without repeating the first vertex, in
  CSR form: the vertices of block ``b`` are ``vertices[vertex_offsets[b]:vertex_offsets[b+1]]``.
- A shared edge ``e`` lies between blocks ``edge_block_a[e]`` and ``edge_block_b[e]`` and runs
  from ``edge_p0[e]`` to ``edge_p1[e]``; ``edge_normal[e]`` is the unit normal pointing from
  block A into block B. ``edge_material[e]`` indexes ``material_names`` (a flaw of a region, a
  joint of a set, a boundary between regions), which the mechanics maps to a material table.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np


@dataclass
class BlockSystem:
    """Blocks (CSR polygons) and the shared edges between them.

    Attributes (nb blocks, nv vertices in all, ne shared edges)
    ----------
    vertices : (nv, 2) float64, m. CCW per block.
    vertex_offsets : (nb + 1,) int64. CSR offsets into ``vertices``.
    centroid : (nb, 2) float64, m.
    area : (nb,) float64, m^2.
    region_id : (nb,) int32. Index into ``region_names``.
    region_names : list[str].
    groups : dict[str, ndarray of int64]. Named block sets (a block may be in several), e.g.
        "upper shear box", "excavation stage 3"; every region name is also a group.
    edge_p0, edge_p1 : (ne, 2) float64, m. End points of each shared edge.
    edge_block_a, edge_block_b : (ne,) int64. The two blocks; normal points from A to B.
    edge_normal : (ne, 2) float64. Unit normal, A -> B.
    edge_length : (ne,) float64, m.
    edge_material : (ne,) int32. Index into ``material_names``.
    material_names : list[str]. e.g. "flaw:rock", "joint:bedding", "boundary:rock|weathered".
    """

    vertices: np.ndarray
    vertex_offsets: np.ndarray
    centroid: np.ndarray
    area: np.ndarray
    region_id: np.ndarray
    region_names: list
    groups: dict
    edge_p0: np.ndarray
    edge_p1: np.ndarray
    edge_block_a: np.ndarray
    edge_block_b: np.ndarray
    edge_normal: np.ndarray
    edge_length: np.ndarray
    edge_material: np.ndarray
    material_names: list
    meta: dict = field(default_factory=dict)

    @property
    def n_blocks(self) -> int:
        return int(self.vertex_offsets.size - 1)

    @property
    def n_edges(self) -> int:
        return int(self.edge_length.size)

    def block_vertices(self, b: int) -> np.ndarray:
        """The (k, 2) CCW vertices of block ``b`` (a view)."""
        return self.vertices[self.vertex_offsets[b]:self.vertex_offsets[b + 1]]

    def bounds(self) -> tuple:
        """(xmin, ymin, xmax, ymax) of all blocks, m."""
        lo, hi = self.vertices.min(axis=0), self.vertices.max(axis=0)
        return float(lo[0]), float(lo[1]), float(hi[0]), float(hi[1])

    def touching(self, side: str, tol: float | None = None) -> np.ndarray:
        """Blocks with a vertex on a side of the model's bounding box ("bottom", "top", "left",
        "right"), within ``tol`` m (default 1e-9 of the model size): the usual boundary groups
        (fixed base, roller sides)."""
        sides = {"left": (0, min), "right": (0, max), "bottom": (1, min), "top": (1, max)}
        if side not in sides:
            raise ValueError(f"side must be one of {sorted(sides)}, got {side!r}")
        axis, pick = sides[side]
        x0, y0, x1, y1 = self.bounds()
        tol = 1e-9 * max(x1 - x0, y1 - y0) if tol is None else float(tol)
        edge = pick(self.vertices[:, axis].min(), self.vertices[:, axis].max())
        near = np.abs(self.vertices[:, axis] - edge) <= tol
        owner = np.repeat(np.arange(self.n_blocks), np.diff(self.vertex_offsets))
        return np.unique(owner[near])


def group_blocks(blocks, group) -> np.ndarray:
    """Block indices of ``group``: a name of ``blocks.groups`` or an index array (ValueError
    naming an unknown group or an index out of range)."""
    if isinstance(group, str):
        if group not in blocks.groups:
            raise ValueError(f"no block group {group!r}; groups are {sorted(blocks.groups)}")
        idx = np.asarray(blocks.groups[group], dtype=np.int64)
    else:
        idx = np.atleast_1d(np.asarray(group, dtype=np.int64))
    if idx.size and (idx.min() < 0 or idx.max() >= blocks.n_blocks):
        raise ValueError(f"block index out of range 0..{blocks.n_blocks - 1}")
    return idx
