"""Block-system invariants: exact area, convex CCW blocks, conforming shared edges, seeds."""
import json

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from dem_core.geometry import (GeometrySpec, JointSet, Region, Voronoi, block_statistics,
                               build_block_system, rectangle)
from test_geometry_helpers import full_check

SLOPE = [(0, 0), (1, 0), (1, 0.3), (0.7, 0.3), (0.4, 0.7), (0, 0.7)]
HOLE = [(0.2, 0.2), (0.3, 0.2), (0.3, 0.25), (0.2, 0.25)]


def test_rectangle_voronoi_invariants():
    regions = [rectangle("rock", 0, 0, 1, 0.5)]
    bs = build_block_system(GeometrySpec(regions, voronoi={"rock": Voronoi(0.03, seed=2)}))
    assert bs.n_blocks > 150
    full_check(bs, regions)
    assert bs.material_names == ["flaw:rock"]


def test_concave_region_with_hole_and_joints():
    regions = [Region("rock", SLOPE, holes=[HOLE])]
    spec = GeometrySpec(regions,
                        joint_sets=[JointSet("bed", 70, 0.1, dip_direction="left"),
                                    JointSet("cross", 20, 0.15, persistence=0.6, trace_length=0.12)],
                        voronoi={"rock": Voronoi(0.025, seed=3)})
    bs = build_block_system(spec)
    full_check(bs, regions)
    assert {"joint:bed", "joint:cross"} <= set(bs.material_names)


def test_two_regions_share_a_boundary_without_t_junctions():
    # Voronoi below, joint-bounded above; the shared line is cut differently on each side
    regions = [rectangle("lower", 0, 0, 1, 0.3), rectangle("upper", 0, 0.3, 1, 0.5, groups=["top"])]
    spec = GeometrySpec(regions, joint_sets=[JointSet("j", 90, 0.17, regions=["upper"])],
                        voronoi={"lower": Voronoi(0.04, seed=1)}, groups={"left": [(0, 0), (0.5, 0), (0.5, 1), (0, 1)]})
    bs = build_block_system(spec)
    full_check(bs, regions)
    mats = np.array(bs.material_names)[bs.edge_material]
    # the whole 1 m interface is contact, split wherever either side has a corner
    assert bs.edge_length[mats == "boundary:lower|upper"].sum() == pytest.approx(1.0, rel=1e-12)
    on_line = np.abs(bs.edge_p0[:, 1] - 0.3) < 1e-12
    assert np.all(mats[on_line & (np.abs(bs.edge_p1[:, 1] - 0.3) < 1e-12)] == "boundary:lower|upper")
    assert set(bs.groups["top"]) == set(bs.groups["upper"])
    assert np.all(bs.centroid[bs.groups["left"], 0] < 0.5)
    assert len(bs.groups["lower"]) + len(bs.groups["upper"]) == bs.n_blocks


@settings(max_examples=8, deadline=None)
@given(seed=st.integers(0, 2**31 - 1), edge=st.floats(0.04, 0.1),
       dip=st.floats(0, 90), k=st.sampled_from([0.0, 0.5, 1.0]))
def test_invariants_hold_for_random_scenes(seed, edge, dip, k):
    regions = [Region("rock", SLOPE, holes=[HOLE])]
    js = JointSet("j", dip, 0.13, persistence=k, trace_length=0.2 if 0 < k < 1 else None,
                  seed=seed, jitter=0.3)
    bs = build_block_system(GeometrySpec(regions, joint_sets=[js],
                                         voronoi={"rock": Voronoi(edge, seed=seed, relax_iterations=5)}))
    full_check(bs, regions)


def test_same_seed_same_blocks_other_seed_other_blocks():
    def build(seed):
        return build_block_system(GeometrySpec([Region("rock", SLOPE)],
                                               joint_sets=[JointSet("j", 60, 0.2, 0.5, 0.1, seed=seed)],
                                               voronoi={"rock": Voronoi(0.05, seed=seed)}))
    a, b, c = build(7), build(7), build(8)
    assert np.array_equal(a.vertices, b.vertices) and np.array_equal(a.vertex_offsets, b.vertex_offsets)
    assert np.array_equal(a.edge_material, b.edge_material)
    assert a.vertices.shape != c.vertices.shape or not np.allclose(a.vertices, c.vertices)


@pytest.mark.parametrize("edge, iters", [(0.02, 20), (0.04, 20), (0.03, 100)])
def test_mean_edge_length_near_target(edge, iters):
    bs = build_block_system(GeometrySpec([rectangle("r", 0, 0, 1, 0.5)],
                                         voronoi={"r": Voronoi(edge, relax_iterations=iters, seed=5)}))
    mean = block_statistics(bs)["mean_edge_length"]
    assert abs(mean / edge - 1) < 0.15, mean / edge


def test_sliver_control_bounds_edges_and_areas():
    vs = Voronoi(0.03, seed=11, relax_iterations=0)  # unrelaxed: many tiny edges to remove
    bs = build_block_system(GeometrySpec([rectangle("r", 0, 0, 1, 0.5)], voronoi={"r": vs}))
    st_ = block_statistics(bs)
    assert st_["sliver_control"]["collapsed_edges"] > 0
    edges = np.r_[bs.edge_length]
    # almost every edge is above the limit; the rest are ones pinned between corners/lines
    assert np.mean(edges >= vs.min_edge_fraction * vs.edge_length) > 0.995
    assert bs.area.min() >= vs.min_area_fraction * vs.edge_length ** 2 * 0.5
    full_check(bs, [rectangle("r", 0, 0, 1, 0.5)])


def test_size_field_makes_blocks_finer_in_the_zone():
    from dem_core.geometry import ZoneSizeField
    zone = [(0, 0), (0.3, 0), (0.3, 0.5), (0, 0.5)]
    vs = Voronoi(0.06, size_field=ZoneSizeField(zone, 0.02, 0.06, 0.2), seed=1)
    bs = build_block_system(GeometrySpec([rectangle("r", 0, 0, 1, 0.5)], voronoi={"r": vs}))
    fine = bs.area[bs.centroid[:, 0] < 0.25].mean()
    coarse = bs.area[bs.centroid[:, 0] > 0.6].mean()
    assert 4 < coarse / fine < 16  # (0.06 / 0.02)^2 = 9 for the target sizes
    full_check(bs, [rectangle("r", 0, 0, 1, 0.5)])


def test_spec_json_round_trip_rebuilds_identical_blocks():
    from dem_core.geometry import JointLine, ZoneSizeField
    spec = GeometrySpec([Region("rock", SLOPE, holes=[HOLE], groups=["all"])],
                        joint_sets=[JointSet("j", 60, 0.2, 0.5, 0.1, seed=3, dip_direction="left")],
                        joints=[JointLine("fault", [(0.05, 0.05), (0.5, 0.3), (0.9, 0.35)])],
                        voronoi={"rock": Voronoi(0.05, seed=4, size_field=ZoneSizeField(
                            [(0.6, 0), (1, 0), (1, 0.3)], 0.03, 0.05, 0.2))},
                        groups={"toe": [(0.7, 0), (1, 0), (1, 0.3), (0.7, 0.3)]})
    spec2 = GeometrySpec.from_dict(json.loads(json.dumps(spec.to_dict())))
    a, b = build_block_system(spec), build_block_system(spec2)
    assert np.array_equal(a.vertices, b.vertices)
    assert a.material_names == b.material_names and "joint:fault" in a.material_names
    assert np.array_equal(a.groups["toe"], b.groups["toe"])
