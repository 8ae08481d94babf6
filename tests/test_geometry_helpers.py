"""Independent checks of a BlockSystem's geometry, shared by the geometry tests (no tests here)."""
import numpy as np
import shapely


def block_loops(bs):
    return [bs.block_vertices(b) for b in range(bs.n_blocks)]


def assert_convex_ccw_no_duplicates(bs):
    for b, xy in enumerate(block_loops(bs)):
        assert len(xy) >= 3, f"block {b} has {len(xy)} vertices"
        e = np.roll(xy, -1, axis=0) - xy
        ln = np.hypot(*e.T)
        assert ln.min() > 0, f"block {b} repeats a vertex"
        assert len(np.unique(xy, axis=0)) == len(xy), f"block {b} has duplicate vertices"
        en = np.roll(e, -1, axis=0)
        cross = (e[:, 0] * en[:, 1] - e[:, 1] * en[:, 0]) / (ln * np.roll(ln, -1))
        assert cross.min() > -1e-9, f"block {b} has a reflex (or clockwise) vertex: {cross.min()}"
        assert shapely.Polygon(xy).is_valid and shapely.Polygon(xy).exterior.is_ccw, f"block {b}"


def assert_edges_conform(bs, regions_union):
    """Every block edge is either shared by exactly two blocks (listed in bs.edge_*), with the
    same end points in both, or lies on the outer boundary of the regions."""
    seen = {}
    for b, xy in enumerate(block_loops(bs)):
        for p, q in zip(xy, np.roll(xy, -1, axis=0)):
            key = (tuple(p), tuple(q))
            assert key not in seen, f"edge {key} twice in the same direction"
            seen[key] = b
    listed = set()
    for e in range(bs.n_edges):
        a, b = bs.edge_block_a[e], bs.edge_block_b[e]
        p0, p1 = tuple(bs.edge_p0[e]), tuple(bs.edge_p1[e])
        assert seen.get((p0, p1)) == a and seen.get((p1, p0)) == b, f"edge {e} end points do not match"
        listed |= {(p0, p1), (p1, p0)}
        # normal A -> B: unit, perpendicular, pointing towards B
        n = bs.edge_normal[e]
        d = np.subtract(p1, p0)
        assert abs(np.hypot(*n) - 1) < 1e-12 and abs(n @ d) < 1e-9 * np.hypot(*d)
        assert n @ (bs.centroid[b] - bs.centroid[a]) > 0
        assert abs(bs.edge_length[e] - np.hypot(*d)) < 1e-15 + 1e-12 * np.hypot(*d)
    boundary = regions_union.boundary
    for (p, q), b in seen.items():
        if (p, q) in listed:
            continue
        mid = shapely.Point(0.5 * (np.add(p, q)))
        assert boundary.distance(mid) < 1e-9 and boundary.distance(shapely.Point(p)) < 1e-9, \
            f"edge {p}-{q} of block {b} is neither shared nor on the boundary (T-junction?)"


def assert_area_exact(bs, area):
    assert abs(bs.area.sum() - area) <= 1e-9 * area, (bs.area.sum(), area)
    assert np.all(bs.area > 0)


def full_check(bs, regions):
    union = shapely.union_all([r.polygon() for r in regions])
    assert_area_exact(bs, sum(r.polygon().area for r in regions))
    assert_convex_ccw_no_duplicates(bs)
    assert_edges_conform(bs, union)
