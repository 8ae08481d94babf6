"""Voronoi tessellation of one region: seeds, Lloyd relaxation, cells clipped to the region.

Seeds
-----
- Fixed seeds (``edge_seeding``): a row along every region ring, offset ``0.75 h`` inwards at
  spacing ``sqrt(3) h``, and mirrored pairs at ``+-0.75 h`` on both sides of every joint
  segment. A row like that makes cell edges run along the boundary/joint, so the later exact
  clip and split leave few slivers. (h: local target edge length.)
- Free seeds: random (explicit seed) with density 1/h^2, as many as make the total number of
  cells ``integral dA / (CELL_AREA h^2)`` with CELL_AREA = 2.40 (see the constant below), so
  the mean edge length comes out near h.
- Lloyd relaxation moves each free seed to the centroid of its cell clipped to the region
  (density-weighted by h^-4 with a size field, the 2-D centroidal Voronoi density for cell
  size ~h); fixed seeds stay. Centroids are computed for all cells at once from the Voronoi
  ridges (each cell is a fan of triangles seed-ridge); only cells that cross the region
  boundary are clipped with shapely.
"""
from __future__ import annotations

import numpy as np
import shapely
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
from scipy.spatial import Delaunay, cKDTree

SQRT3 = np.sqrt(3.0)
# Target area per cell, in units of h^2. A regular hexagon of edge h has 1.5 sqrt(3) = 2.598 h^2,
# but relaxed Voronoi cells (with the short-edge clean-up) have a mean edge about 4 % longer than
# the hexagon of the same area (measured over 500-8000 cells, 20-100 iterations), so cells get
# 2.598 / 1.04^2 = 2.40 h^2 and the realized mean edge length comes out close to h.
CELL_AREA = 2.40
ROW_OFFSET = 0.75       # seed row distance from a boundary or joint, in units of h
ROW_SPACING = SQRT3     # seed spacing along a boundary or joint, in units of h
COINCIDENT = 1e-12      # Voronoi vertices closer than this (x the point extent) are one vertex


def _line_seeds(coords, vs, sides) -> np.ndarray:
    """Seeds along a polyline, offset to the left (+1) and/or right (-1) by ROW_OFFSET * h."""
    out = []
    for a, b in zip(coords[:-1], coords[1:]):
        d = b - a
        length = float(np.hypot(*d))
        if length == 0.0:
            continue
        h = vs.local_size(0.5 * (a + b))[0]
        n = max(1, int(round(length / (ROW_SPACING * h))))
        pts = a + ((np.arange(n) + 0.5) / n)[:, None] * d
        left = np.array([-d[1], d[0]]) / length
        off = ROW_OFFSET * vs.local_size(pts)[:, None]
        out += [pts + s * off * left for s in sides]
    return np.vstack(out) if out else np.zeros((0, 2))


def fixed_seeds(poly, joint_pieces, vs) -> np.ndarray:
    """Seed rows along the region rings and both sides of the joint segments (see module doc)."""
    if not vs.edge_seeding:
        return np.zeros((0, 2))
    rings = [poly.exterior] + list(poly.interiors)  # oriented: region is on the left of each
    cand = [_line_seeds(np.asarray(r.coords), vs, (1,)) for r in rings]
    cand += [_line_seeds(np.asarray(c), vs, (1, -1)) for c in joint_pieces]
    pts = np.vstack(cand)
    h = vs.local_size(pts)
    inside = shapely.contains_xy(poly, pts[:, 0], pts[:, 1])
    dist = shapely.distance(poly.boundary, shapely.points(pts))
    pts, h = pts[inside & (dist >= 0.5 * ROW_OFFSET * h)], h[inside & (dist >= 0.5 * ROW_OFFSET * h)]
    return _thin(pts, h, 0.8)


def _thin(pts, h, frac) -> np.ndarray:
    """Drop points closer than ``frac * h`` to an earlier kept point (greedy, in order)."""
    if len(pts) == 0:
        return pts
    tree = cKDTree(pts)
    keep = np.ones(len(pts), bool)
    for i in range(len(pts)):
        if keep[i]:
            for j in tree.query_ball_point(pts[i], frac * h[i]):
                if j > i:
                    keep[j] = False
    return pts[keep]


def target_cell_count(poly, vs, rng) -> float:
    """integral over the region of dA / (CELL_AREA h^2)."""
    if vs.size_field is None:
        return poly.area / (CELL_AREA * vs.edge_length ** 2)
    pts = random_points(poly, 20000, rng)
    return poly.area * float(np.mean(1.0 / (CELL_AREA * vs.local_size(pts) ** 2)))


def random_points(poly, n, rng, vs=None) -> np.ndarray:
    """n random points in the polygon; with ``vs`` the density is proportional to 1/h^2."""
    xmin, ymin, xmax, ymax = poly.bounds
    out, got = [], 0
    hmin = None
    while got < n:
        m = max(1000, int(2.5 * (n - got) * (xmax - xmin) * (ymax - ymin) / poly.area))
        p = rng.uniform([xmin, ymin], [xmax, ymax], size=(m, 2))
        p = p[shapely.contains_xy(poly, p[:, 0], p[:, 1])]
        if vs is not None and vs.size_field is not None and len(p):
            h = vs.local_size(p)
            hmin = h.min() if hmin is None else min(hmin, h.min())
            p = p[rng.uniform(size=len(p)) < (hmin / h) ** 2]
        out.append(p)
        got += len(p)
    return np.vstack(out)[:n]


def _dummies(poly) -> np.ndarray:
    """Far points around the region so that every real Voronoi cell is bounded."""
    xmin, ymin, xmax, ymax = poly.bounds
    c = np.array([(xmin + xmax) / 2, (ymin + ymax) / 2])
    r = 3.0 * max(xmax - xmin, ymax - ymin)
    a = np.linspace(0.0, 2 * np.pi, 8, endpoint=False)
    return c + r * np.column_stack([np.cos(a), np.sin(a)])


def _dual(pts):
    """Delaunay triangles of ``pts`` (made CCW) and their circumcentres (the Voronoi vertices).

    The Voronoi diagram is read off the Delaunay triangulation (its dual) with array
    operations: scipy's ``Voronoi`` builds Python lists per cell, which is slow at 1e5 cells.
    """
    s = Delaunay(pts).simplices.copy()
    a, b, c = pts[s[:, 0]], pts[s[:, 1]], pts[s[:, 2]]
    ba, ca = b - a, c - a
    d = 2.0 * (ba[:, 0] * ca[:, 1] - ba[:, 1] * ca[:, 0])
    cw = d < 0
    s[cw, 1], s[cw, 2] = s[cw, 2], s[cw, 1].copy()
    nb, nc = (ba ** 2).sum(1), (ca ** 2).sum(1)
    cc = a + np.column_stack([ca[:, 1] * nb - ba[:, 1] * nc, ba[:, 0] * nc - ca[:, 0] * nb]) / d[:, None]
    return s, cc


def _fan_centroids(pts, s, cc, vs):
    """Centroids of the Voronoi cells of all points (density-weighted with a size field).

    CCW triangle (a, b, c) with circumcentre o gives a's cell the part (a, mid(ab), o, mid(ca)),
    taken as two signed triangles; summed over the triangles around a this is exactly a's
    (bounded) Voronoi cell, obtuse triangles included.
    """
    n = len(pts)
    acc = np.zeros((3, n))
    for k in range(3):
        ia, ib, ic = s[:, k], s[:, (k + 1) % 3], s[:, (k + 2) % 3]
        a = pts[ia]
        for p, q in ((0.5 * (a + pts[ib]), cc), (cc, 0.5 * (a + pts[ic]))):
            w = 0.5 * ((p[:, 0] - a[:, 0]) * (q[:, 1] - a[:, 1]) - (p[:, 1] - a[:, 1]) * (q[:, 0] - a[:, 0]))
            cen = (a + p + q) / 3.0
            if vs.size_field is not None:
                w = w * vs.local_size(cen) ** -4.0
            acc[0] += np.bincount(ia, w, n)
            acc[1] += np.bincount(ia, w * cen[:, 0], n)
            acc[2] += np.bincount(ia, w * cen[:, 1], n)
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.column_stack([acc[1], acc[2]]) / acc[0][:, None]


def cell_polygons(pts, s, cc, idx) -> np.ndarray:
    """shapely polygons (CCW) of the Voronoi cells of points ``idx`` (bounded cells only)."""
    idx = np.asarray(idx)
    if len(idx) == 0:
        return np.zeros(0, dtype=object)
    flat = s.ravel()
    want = np.zeros(len(pts), bool)
    want[idx] = True
    sel = np.nonzero(want[flat])[0]
    owner_pt, tri = flat[sel], sel // 3
    rank = np.full(len(pts), -1)
    rank[idx] = np.arange(len(idx))
    owner = rank[owner_pt]
    utri, inv = np.unique(tri, return_inverse=True)
    xy = _merge_coincident(cc[utri], COINCIDENT * np.ptp(pts, axis=0).max())[inv.ravel()]
    rel = xy - pts[owner_pt]
    order = np.lexsort((np.arctan2(rel[:, 1], rel[:, 0]), owner))
    xy, owner = xy[order], owner[order]
    # a merged vertex appears once per triangle that has it: keep one (same point, same angle,
    # so the copies are consecutive)
    dup = np.r_[False, (owner[1:] == owner[:-1]) & np.all(xy[1:] == xy[:-1], axis=1)]
    return shapely.polygons(shapely.linearrings(xy[~dup], indices=owner[~dup]))


def _merge_coincident(xy, tol) -> np.ndarray:
    """Points closer than ``tol`` replaced by one of them (exactly equal coordinates).

    Co-circular seeds (every mirrored seed pair next to another across a joint, a regular
    seed row) give several Delaunay triangles with the same circumcentre, which round-off
    scatters by ~1e-17 m. Left apart, two such vertices of a cell have angles around its seed
    that differ by round-off only, so sorting by angle may reverse them: the ring gets a
    zero-width spike, is invalid, and GEOS then misjudges its orientation (seen with a
    horizontal joint, where the spike is the cell's highest point).
    """
    pairs = cKDTree(xy).query_pairs(tol, output_type="ndarray")
    if len(pairs) == 0:
        return xy
    g = coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(len(xy),) * 2)
    _, lab = connected_components(g, directed=False)
    first = np.full(lab.max() + 1, len(xy))
    np.minimum.at(first, lab, np.arange(len(xy)))
    return xy[first[lab]]


def _boundary_cells(pts, s, cc, poly, ring_xy) -> np.ndarray:
    """Mask of cells that may stick out of the region (a vertex outside or a ring vertex in)."""
    out_t = ~shapely.contains_xy(poly, cc[:, 0], cc[:, 1])
    mark = np.zeros(len(pts), bool)
    mark[s[out_t].ravel()] = True
    mark[cKDTree(pts).query(ring_xy)[1]] = True  # the cell containing a ring vertex
    return mark


def relax(poly, fixed, free, vs) -> np.ndarray:
    """Lloyd relaxation of the free seeds (fixed seeds stay); returns the new free seeds."""
    shapely.prepare(poly)
    dummies = _dummies(poly)
    ring_xy = shapely.get_coordinates(poly.boundary)
    nf = len(fixed)
    sl = slice(nf, nf + len(free))
    for _ in range(vs.relax_iterations):
        pts = np.vstack([fixed, free, dummies])
        s, cc = _dual(pts)
        cen = _fan_centroids(pts, s, cc, vs)[sl]
        mark = np.nonzero(_boundary_cells(pts, s, cc, poly, ring_xy)[sl])[0]
        if len(mark):
            clipped = shapely.intersection(cell_polygons(pts, s, cc, mark + nf), poly)
            cen[mark] = shapely.get_coordinates(shapely.centroid(clipped))
        ok = np.isfinite(cen).all(axis=1)
        ok[ok] = shapely.contains_xy(poly, cen[ok, 0], cen[ok, 1])
        free = np.where(ok[:, None], cen, free)
    return free


def _snake_order(pts, cell) -> np.ndarray:
    """Row-by-row (boustrophedon) order of points on a grid of size ``cell``."""
    if len(pts) == 0:
        return np.zeros(0, int)
    g = np.floor((pts - pts.min(axis=0)) / cell).astype(np.int64)
    return np.lexsort((np.where(g[:, 1] % 2 == 0, g[:, 0], -g[:, 0]), g[:, 1]))


def seeds(poly, joint_pieces, vs) -> np.ndarray:
    """All seeds of the region: fixed rows first, then the relaxed free seeds."""
    rng = np.random.default_rng(vs.seed)
    fixed = fixed_seeds(poly, joint_pieces, vs)
    # a region piece smaller than half a cell still gets its one block (0 seeds: a hole)
    n_free = max(0 if len(fixed) else 1,
                 int(round(target_cell_count(poly, vs, rng) - len(fixed))))
    free = random_points(poly, n_free, rng, vs) if n_free else np.zeros((0, 2))
    free = free[_snake_order(free, vs.edge_length * 4.0)]  # locality speeds up Qhull
    if len(free) and vs.relax_iterations:
        free = relax(poly, fixed, free, vs)
    return np.vstack([fixed, free])


def voronoi_cells(poly, seed_xy) -> tuple:
    """The Voronoi cells of ``seed_xy`` clipped to ``poly``: (inside, clipped) polygon arrays.

    Cells properly inside the region are used as they are (convex); the others are clipped and
    may come out non-convex where the region is concave (the caller splits those).
    """
    shapely.prepare(poly)
    pts = np.vstack([seed_xy, _dummies(poly)])
    s, cc = _dual(pts)
    cells = cell_polygons(pts, s, cc, np.arange(len(seed_xy)))
    inside = shapely.contains_properly(poly, cells)
    clipped = shapely.get_parts(shapely.intersection(cells[~inside], poly))
    clipped = clipped[(shapely.get_type_id(clipped) == 3) & (shapely.area(clipped) > 0)]
    return cells[inside], clipped
