"""Joint sets and lines: columns, traces, realized persistence, materials on the traces."""
import numpy as np
import pytest

from dem_core.geometry import (GeometrySpec, JointLine, JointSet, Region, Voronoi,
                               block_statistics, build_block_system, rectangle)
from test_geometry_helpers import full_check


def _joint_edges(bs, name):
    return bs.edge_material == bs.material_names.index(f"joint:{name}")


@pytest.mark.parametrize("dip, spacing, offset, expected", [
    (90, 0.2, 0.1, 6),      # vertical joints at x = 0.1, 0.3, ..., 0.9: six columns
    (90, 0.25, 0.0, 4),     # joints at x = 0.25, 0.5, 0.75 (x = 0 and 1 are the sides)
    (0, 0.1, 0.05, 6),      # bedding joints at y = 0.05, 0.15, ..., 0.45: six beds
])
def test_persistent_set_cuts_rectangle_into_columns(dip, spacing, offset, expected):
    regions = [rectangle("rock", 0, 0, 1, 0.5)]
    bs = build_block_system(GeometrySpec(regions, joint_sets=[JointSet("j", dip, spacing, offset=offset)]))
    assert bs.n_blocks == expected
    assert np.sum(_joint_edges(bs, "j")) == expected - 1
    full_check(bs, regions)


def test_dip_direction_left_dips_into_a_slope_facing_right():
    js = JointSet("j", 60, 0.1, dip_direction="left")
    u = js.direction()
    assert u[0] < 0 and u[1] < 0 and np.degrees(np.arctan2(-u[1], -u[0])) == pytest.approx(60)
    assert JointSet("j", 60, 0.1).direction()[0] > 0
    assert abs(js.normal() @ u) < 1e-15


def _distance_to_nearest_joint(js, xy):
    c = (xy - np.asarray(js.origin)) @ js.normal() - js.offset
    return np.abs(c - js.spacing * np.round(c / js.spacing))


@pytest.mark.parametrize("k", [1.0, 0.5])
def test_joint_contacts_lie_on_their_traces_in_voronoi_region(k):
    regions = [Region("rock", [(0, 0), (1, 0), (1, 0.3), (0.6, 0.6), (0, 0.6)])]
    js = JointSet("j", 65, 0.13, persistence=k, trace_length=0.15 if k < 1 else None, offset=0.02,
                  dip_direction="left")
    bs = build_block_system(GeometrySpec(regions, joint_sets=[js], voronoi={"rock": Voronoi(0.03, seed=2)}))
    on = _joint_edges(bs, "j")
    assert on.sum() > 20
    for p in (bs.edge_p0[on], bs.edge_p1[on]):
        assert _distance_to_nearest_joint(js, p).max() < 1e-9
    # and no flaw edge lies along a joint trace (the cut really follows the joints)
    flaw = ~on
    both = (_distance_to_nearest_joint(js, bs.edge_p0[flaw]) < 1e-9) & \
           (_distance_to_nearest_joint(js, bs.edge_p1[flaw]) < 1e-9)
    if k == 1.0:
        assert not both.any()
    full_check(bs, regions)


@pytest.mark.parametrize("k, trace", [(0.5, 0.2), (0.25, 0.1), (0.8, 0.3)])
def test_realized_persistence_on_long_traces(k, trace):
    # horizontal beds 4 m long in a Voronoi region: tips snap to cell edges
    regions = [rectangle("rock", 0, 0, 4, 0.4)]
    js = JointSet("j", 0, 0.2, persistence=k, trace_length=trace, offset=0.1, seed=3)
    bs = build_block_system(GeometrySpec(regions, joint_sets=[js], voronoi={"rock": Voronoi(0.03, seed=1)}))
    assert block_statistics(bs)["realized_persistence"]["j"] == pytest.approx(k, abs=0.05)
    # every snapped joint segment is covered by joint contacts, and nothing else is
    realized = sum(np.hypot(*np.diff(c, axis=0).T).sum() for _, c in bs.meta["joint_segments"])
    assert bs.edge_length[_joint_edges(bs, "j")].sum() == pytest.approx(realized, rel=1e-9)
    full_check(bs, regions)


def test_realized_persistence_exact_without_voronoi():
    regions = [rectangle("rock", 0, 0, 4, 0.4)]
    js = JointSet("j", 0, 0.2, persistence=0.6, bridge_length=0.1, offset=0.1, phase=0.0)
    bs = build_block_system(GeometrySpec(regions, joint_sets=[js]))
    # 2 lines, 4 m each, pattern of 0.15 m joint + 0.1 m bridge from x = 0: 16 periods exactly
    assert block_statistics(bs)["realized_persistence"]["j"] == pytest.approx(0.6, rel=1e-12)
    mats = np.array(bs.material_names)[bs.edge_material]
    assert bs.edge_length[mats == "flaw:rock"].sum() == pytest.approx(2 * 4 * 0.4, rel=1e-12)
    full_check(bs, regions)


def test_zero_persistence_leaves_no_joint_edges_in_voronoi_region():
    regions = [rectangle("rock", 0, 0, 1, 0.5)]
    js = JointSet("j", 30, 0.1, persistence=0.0)
    bs = build_block_system(GeometrySpec(regions, joint_sets=[js], voronoi={"rock": Voronoi(0.05)}))
    assert _joint_edges(bs, "j").sum() == 0


def test_joint_line_polyline_cuts_voronoi_cells_exactly():
    import shapely
    regions = [rectangle("rock", 0, 0, 1, 0.5)]
    pts = [(0.0, 0.1), (0.4, 0.25), (1.0, 0.3)]
    bs = build_block_system(GeometrySpec(regions, joints=[JointLine("fault", pts)],
                                         voronoi={"rock": Voronoi(0.04, seed=4)}))
    on = _joint_edges(bs, "fault")
    line = shapely.LineString(pts)
    assert bs.edge_length[on].sum() == pytest.approx(line.length, rel=1e-9)
    assert max(line.distance(shapely.Point(p)) for p in np.r_[bs.edge_p0[on], bs.edge_p1[on]]) < 1e-9
    full_check(bs, regions)


def test_jitter_moves_joints_within_bounds_reproducibly():
    regions = [rectangle("rock", 0, 0, 1, 0.5)]
    js = JointSet("j", 90, 0.2, offset=0.1, jitter=0.5, seed=9)
    a = build_block_system(GeometrySpec(regions, joint_sets=[js]))
    xs = np.sort(np.unique(a.edge_p0[:, 0]))
    assert len(xs) == 5 and not np.allclose(xs, [0.1, 0.3, 0.5, 0.7, 0.9])
    assert np.all(np.abs(xs - [0.1, 0.3, 0.5, 0.7, 0.9]) <= 0.25 * 0.2 + 1e-12)
    b = build_block_system(GeometrySpec(regions, joint_sets=[js]))
    assert np.array_equal(a.vertices, b.vertices)
