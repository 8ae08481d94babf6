"""Numbers that describe a block system: sizes, shapes, realized persistence."""
from __future__ import annotations

import numpy as np


def all_edge_lengths(bs) -> np.ndarray:
    """Length (m) of every distinct block edge: shared edges once, free-surface edges once."""
    free = bs.meta.get("free_edges")
    fl = np.hypot(*(free["p1"] - free["p0"]).T) if free is not None else np.zeros(0)
    return np.r_[bs.edge_length, fl]


def aspect_ratios(bs) -> np.ndarray:
    """sqrt(I_max / I_min) of each block's second moment of area about its centroid (1 = round)."""
    v, off = bs.vertices, bs.vertex_offsets
    owner = np.repeat(np.arange(bs.n_blocks), np.diff(off))
    nxt = np.arange(len(v)) + 1
    nxt[off[1:] - 1] = off[:-1]
    p, q = v - bs.centroid[owner], v[nxt] - bs.centroid[owner]
    cr = p[:, 0] * q[:, 1] - q[:, 0] * p[:, 1]
    n = bs.n_blocks
    ixx = np.bincount(owner, cr * (p[:, 1] ** 2 + p[:, 1] * q[:, 1] + q[:, 1] ** 2), n) / 12
    iyy = np.bincount(owner, cr * (p[:, 0] ** 2 + p[:, 0] * q[:, 0] + q[:, 0] ** 2), n) / 12
    ixy = np.bincount(owner, cr * (p[:, 0] * q[:, 1] + 2 * p[:, 0] * p[:, 1] + 2 * q[:, 0] * q[:, 1]
                                   + q[:, 0] * p[:, 1]), n) / 24
    mean, dif = 0.5 * (ixx + iyy), np.sqrt((0.5 * (ixx - iyy)) ** 2 + ixy ** 2)
    return np.sqrt((mean + dif) / np.maximum(mean - dif, 1e-300))


def realized_persistence(bs) -> dict:
    """Per joint set/line: joint edge length / total trace length in the regions."""
    out = {}
    for name, total in bs.meta.get("trace_length", {}).items():
        mats = [i for i, m in enumerate(bs.material_names) if m == f"joint:{name}"]
        length = bs.edge_length[np.isin(bs.edge_material, mats)].sum()
        out[name] = float(length / total) if total > 0 else float("nan")
    return out


def block_statistics(bs) -> dict:
    """Block count, edge and area sizes, aspect ratios, edges per material, persistence.

    Lengths in m, areas in m^2. ``mean_edge_length`` counts every distinct block edge once
    (shared and free-surface edges), which is how the Voronoi target edge length is meant.
    """
    el = all_edge_lengths(bs)
    ar = aspect_ratios(bs)
    counts = np.bincount(bs.edge_material, minlength=len(bs.material_names))
    return {
        "blocks": bs.n_blocks,
        "shared_edges": bs.n_edges,
        "mean_edge_length": float(el.mean()) if len(el) else float("nan"),
        "min_edge_length": float(el.min()) if len(el) else float("nan"),
        "mean_area": float(bs.area.mean()),
        "min_area": float(bs.area.min()),
        "total_area": float(bs.area.sum()),
        "mean_aspect_ratio": float(ar.mean()),
        "max_aspect_ratio": float(ar.max()),
        "edges_per_material": {m: int(c) for m, c in zip(bs.material_names, counts)},
        "realized_persistence": realized_persistence(bs),
        "sliver_control": dict(bs.meta.get("slivers", {})),
    }
