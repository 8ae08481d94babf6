"""Small block systems without the geometry layer: brick grids and hand-made polygons.

These are legitimate public geometry for lab-style scenes (a column, a block on a plane, a
brick specimen) and for tests of the mechanics. Each returns a ``BlockSystem``; shared edges are
the collinear overlaps of antiparallel edges of different blocks.
"""
from __future__ import annotations

import numpy as np
import shapely

from .blocks import BlockSystem

__all__ = ["from_polygons", "brick_grid"]


def _polygon_area_centroid(p):
    x, y = p[:, 0], p[:, 1]
    xn, yn = np.roll(x, -1), np.roll(y, -1)
    cross = x * yn - xn * y
    area = 0.5 * cross.sum()
    cx = ((x + xn) * cross).sum() / (6.0 * area)
    cy = ((y + yn) * cross).sum() / (6.0 * area)
    return area, np.array([cx, cy])


def _shared_edges(polys, tol):
    """Collinear overlaps of antiparallel edges of different blocks (brute force, small systems)."""
    p0 = np.concatenate([p for p in polys])
    p1 = np.concatenate([np.roll(p, -1, axis=0) for p in polys])
    owner = np.concatenate([np.full(len(p), b) for b, p in enumerate(polys)])
    d = p1 - p0
    length = np.hypot(d[:, 0], d[:, 1])
    u = d / length[:, None]
    out = []
    for i in range(len(p0)):
        j = np.arange(i + 1, len(p0))
        j = j[(owner[j] != owner[i]) & (u[j] @ u[i] < -1 + 1e-9)]
        # collinear: both ends of edge j on the line of edge i
        nrm = np.array([u[i, 1], -u[i, 0]])
        j = j[(np.abs((p0[j] - p0[i]) @ nrm) < tol) & (np.abs((p1[j] - p0[i]) @ nrm) < tol)]
        for k in j:
            s0, s1 = sorted([(p0[k] - p0[i]) @ u[i], (p1[k] - p0[i]) @ u[i]])
            lo, hi = max(0.0, s0), min(length[i], s1)
            if hi - lo > tol:
                out.append((owner[i], owner[k], p0[i] + lo * u[i], p0[i] + hi * u[i], nrm))
    return out


def _checked_polygon(i, p) -> np.ndarray:
    """Polygon ``i`` as an (k, 2) float array; ValueError naming it unless it has >= 3 finite
    vertices, a non-zero area and no edges that cross (shapely's validity)."""
    try:
        p = np.asarray(p, dtype=np.float64)
    except (TypeError, ValueError):
        raise ValueError(f"polygon {i} is not a list of (x, y) points: {p!r}") from None
    if p.ndim != 2 or p.shape[1] != 2 or len(p) < 3 or not np.all(np.isfinite(p)):
        raise ValueError(f"polygon {i} needs at least 3 finite (x, y) vertices, got "
                         f"{p.tolist()}")
    poly = shapely.Polygon(p)
    if not poly.is_valid:
        raise ValueError(f"polygon {i} is not a simple polygon ({shapely.is_valid_reason(poly)}"
                         f"): {p.tolist()}")
    if not poly.area > 0:
        raise ValueError(f"polygon {i} has no area: {p.tolist()}")
    return p


PENETRATION = 0.01       # overlaps thinner than this x the smaller block's size are contacts


def _check_no_overlap(polys) -> None:
    """ValueError naming the first two polygons that overlap: the overlap's thickness (2 x
    area / perimeter) exceeds ``PENETRATION`` x the smaller polygon's size (square root of its
    area). Sharing an edge or a corner is fine, and so is a block pressed slightly into another
    (an initial contact penetration, as the contact tests set up)."""
    shapes = shapely.polygons([shapely.linearrings(p) for p in polys])
    if len(shapes) < 2:
        return
    a, b = shapely.STRtree(shapes).query(shapes, predicate="intersects")
    keep = a < b
    a, b = a[keep], b[keep]
    lens = shapely.intersection(shapes[a], shapes[b])
    area, perimeter = shapely.area(lens), shapely.length(lens)
    thick = np.where(perimeter > 0, 2.0 * area / np.maximum(perimeter, 1e-300), 0.0)
    size = np.sqrt(np.minimum(shapely.area(shapes[a]), shapely.area(shapes[b])))
    bad = np.flatnonzero(thick > PENETRATION * size)
    if bad.size:
        k = bad[np.lexsort((b[bad], a[bad]))[0]]
        raise ValueError(f"polygons {a[k]} and {b[k]} overlap (area {area[k]:.3g} m^2, "
                         f"{thick[k]:.3g} m thick): {polys[a[k]].tolist()} and "
                         f"{polys[b[k]].tolist()}")


def from_polygons(polygons, edge_material="flaw:rock", groups=None, region_name="rock",
                  tol=1e-9) -> BlockSystem:
    """A BlockSystem from convex polygons (any orientation; stored CCW). ValueError naming
    the polygon(s) for a polygon with fewer than 3 vertices, no area, non-finite or crossing
    edges, and for two polygons that overlap (more than a contact penetration: ``PENETRATION``).

    Parameters
    ----------
    polygons : list of (k, 2) array-like, m
    edge_material : str or callable(a, b) -> str
        Material name of the shared edge between blocks a and b.
    groups : dict[str, list[int]], optional
        Named block sets; ``region_name`` (all blocks) is added.
    tol : float
        Collinearity / overlap tolerance, m.
    """
    polys = []
    for i, p in enumerate(polygons):
        p = _checked_polygon(i, p)
        area, _ = _polygon_area_centroid(p)
        if area < 0:
            p = p[::-1].copy()
        polys.append(p)
    _check_no_overlap(polys)
    nb = len(polys)
    ac = [_polygon_area_centroid(p) for p in polys]
    shared = _shared_edges(polys, tol)
    names, mat_ids = [], []
    for a, b, *_ in shared:
        name = edge_material(int(a), int(b)) if callable(edge_material) else edge_material
        if name not in names:
            names.append(name)
        mat_ids.append(names.index(name))
    g = {k: np.asarray(v, dtype=np.int64) for k, v in (groups or {}).items()}
    g[region_name] = np.arange(nb, dtype=np.int64)
    ne = len(shared)
    edge = lambda i: np.array([s[i] for s in shared], dtype=np.float64).reshape(ne, 2)  # noqa: E731
    p0, p1 = edge(2), edge(3)
    return BlockSystem(
        vertices=np.concatenate(polys),
        vertex_offsets=np.concatenate([[0], np.cumsum([len(p) for p in polys])]).astype(np.int64),
        centroid=np.array([c for _, c in ac]).reshape(nb, 2),
        area=np.array([a for a, _ in ac]),
        region_id=np.zeros(nb, dtype=np.int32),
        region_names=[region_name],
        groups=g,
        edge_p0=p0, edge_p1=p1,
        edge_block_a=np.array([s[0] for s in shared], dtype=np.int64),
        edge_block_b=np.array([s[1] for s in shared], dtype=np.int64),
        edge_normal=edge(4),
        edge_length=np.hypot(*(p1 - p0).T) if ne else np.zeros(0),
        edge_material=np.array(mat_ids, dtype=np.int32),
        material_names=names or ([edge_material] if isinstance(edge_material, str) else []),
    )


def brick_grid(nx, ny, dx, dy, origin=(0.0, 0.0), stagger=False, edge_material="flaw:rock",
               groups=None) -> BlockSystem:
    """An nx by ny grid of dx by dy rectangles (``stagger``: brick bond, odd rows shifted dx/2).

    Named groups "bottom", "top", "left", "right" hold the blocks of the outer rows/columns.
    """
    x0, y0 = origin
    polys, row_of = [], []
    for j in range(ny):
        shift = 0.5 * dx if (stagger and j % 2) else 0.0
        if shift == 0.0:
            xs = [x0 + i * dx for i in range(nx + 1)]
        else:  # half bricks at both ends
            xs = [x0] + [x0 + shift + i * dx for i in range(nx)] + [x0 + nx * dx]
        for i in range(len(xs) - 1):
            ya, yb = y0 + j * dy, y0 + (j + 1) * dy
            polys.append([(xs[i], ya), (xs[i + 1], ya), (xs[i + 1], yb), (xs[i], yb)])
            row_of.append(j)
    row_of = np.array(row_of)
    xmin = np.array([p[0][0] for p in polys])
    xmax = np.array([p[1][0] for p in polys])
    g = {"bottom": np.flatnonzero(row_of == 0), "top": np.flatnonzero(row_of == ny - 1),
         "left": np.flatnonzero(np.isclose(xmin, x0)),
         "right": np.flatnonzero(np.isclose(xmax, x0 + nx * dx))}
    g.update(groups or {})
    return from_polygons(polys, edge_material=edge_material, groups=g,
                         tol=1e-9 * max(dx, dy))
