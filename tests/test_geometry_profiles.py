"""Slope and bench profiles, and the zone along the face (dem_core.geometry.profiles)."""
import numpy as np
import pytest
import shapely

from dem_core.geometry import (GeometrySpec, JointSet, Voronoi, bench_profile, build_block_system,
                               near_face_regions, slope_profile, zone_polygon_along_face)
from test_geometry_helpers import full_check


@pytest.mark.parametrize("dip", [30.0, 60.0, 75.0, 90.0])
def test_slope_profile_area_and_corners(dip):
    H, c, t, base = 0.2, 0.1, 0.08, 0.05
    run = 0.0 if dip == 90 else H / np.tan(np.radians(dip))
    width = c + run + t
    r = slope_profile(H, dip, c, t, base)
    expected = width * base + c * H + 0.5 * run * H
    assert r.polygon().area == pytest.approx(expected, rel=1e-12)
    ring = {tuple(np.round(p, 12)) for p in r.exterior}
    # origin at the bottom-left corner, crest at the left, toe bench to the right (faces +x)
    assert {(0.0, 0.0), (0.0, base + H), (round(c, 12), base + H),
            (round(c + run, 12), base), (round(width, 12), base)} <= ring
    mirrored = slope_profile(H, dip, c, t, base, facing="left")
    assert mirrored.polygon().area == pytest.approx(expected, rel=1e-12)
    flipped = shapely.transform(r.polygon(), lambda xy: np.column_stack([width - xy[:, 0], xy[:, 1]]))
    assert mirrored.polygon().symmetric_difference(flipped).area < 1e-15


def test_bench_profile_area_closed_form():
    h, n, dip, b, c, t, base = 0.1, 3, 70.0, 0.03, 0.1, 0.1, 0.05
    r_ = h / np.tan(np.radians(dip))
    width = c + n * r_ + (n - 1) * b + t
    # bench k from the top (k = 0..n-1) is a strip h high, c + k (run + berm) + run / 2 wide
    expected = width * base + h * sum(c + k * (r_ + b) + r_ / 2 for k in range(n))
    reg = bench_profile(h, n, dip, b, c, t, base)
    assert reg.polygon().area == pytest.approx(expected, rel=1e-12)
    assert len(reg.exterior) == 4 + 2 * n  # 4 on the model box (crest and toe ends), 2 per face
    assert bench_profile(h, 1, dip, b, c, t, base).polygon().area == \
        pytest.approx(slope_profile(h, dip, c, t, base).polygon().area, rel=1e-12)


@pytest.mark.parametrize("dip, depth", [(60.0, 0.03), (90.0, 0.02), (45.0, 0.05)])
def test_zone_along_single_face(dip, depth):
    H = 0.2
    r = slope_profile(H, dip, 0.15, 0.08, 0.05)
    zone, rest = near_face_regions(r, depth)
    s = np.sin(np.radians(dip))
    assert zone.polygon().area == pytest.approx(depth * H / s, rel=1e-12)
    assert zone.polygon().area + rest.polygon().area == pytest.approx(r.polygon().area, rel=1e-12)
    shared = zone.polygon().boundary.intersection(rest.polygon().boundary)
    assert shared.length == pytest.approx(H / s + depth / s, rel=1e-12)  # inner side + toe level
    assert rest.name == "rock" and zone.name == "face_zone"


def test_zone_along_benches_follows_every_face():
    h, n, dip, depth = 0.1, 3, 70.0, 0.02
    r = bench_profile(h, n, dip, 0.03, 0.1, 0.1, 0.05)
    zone = shapely.Polygon(zone_polygon_along_face(r, depth))
    zone_, rest = near_face_regions(r, depth)
    assert zone.area + rest.polygon().area == pytest.approx(r.polygon().area, rel=1e-12)
    nrm = np.array([-np.sin(np.radians(dip)), -np.cos(np.radians(dip))])  # into the rock
    c = np.asarray(r.exterior)
    faces = [(p, q) for p, q in zip(c, np.roll(c, -1, axis=0))
             if abs(p[1] - q[1]) > 1e-9 and 0 < p[0] < c[:, 0].max() and 0 < q[0] < c[:, 0].max()]
    assert len(faces) == n
    for p, q in faces:
        mid = 0.5 * (p + q)
        assert zone.contains(shapely.Point(mid + 0.5 * depth * nrm))
        assert not zone.contains(shapely.Point(mid + 1.5 * depth * nrm))


def test_slope_with_voronoi_zone_and_joints_dipping_into_the_slope():
    # thesis-style scene: joints dipping 80 deg into the slope at 10 mm, flaws only near the face
    r = slope_profile(0.2, 60.0, 0.1, 0.08, 0.05)
    zone, rest = near_face_regions(r, 0.03)
    js = JointSet("j", 80.0, 0.01, dip_direction="left")
    bs = build_block_system(GeometrySpec([zone, rest], joint_sets=[js],
                                         voronoi={"face_zone": Voronoi(0.006, seed=1)}))
    full_check(bs, [zone, rest])
    names = np.array(bs.material_names)[bs.edge_material]
    assert {"flaw:face_zone", "joint:j", "boundary:face_zone|rock"} <= set(names)
    # the joint contacts in the joint-bounded part cover its joint traces exactly
    rest_poly = rest.polygon()
    in_rest = np.isin(bs.edge_block_a, bs.groups["rock"]) & np.isin(bs.edge_block_b, bs.groups["rock"])
    traces = sum(shapely.intersection(shapely.LineString([p0, p1]), rest_poly).length
                 for _, p0, p1, _ in js.lines(rest_poly.bounds))
    assert bs.edge_length[in_rest & (names == "joint:j")].sum() == pytest.approx(traces, rel=1e-9)
    # the interface is all contact: inner side of the zone and its bottom at the toe level
    s = np.sin(np.radians(60.0))
    assert bs.edge_length[names == "boundary:face_zone|rock"].sum() == \
        pytest.approx((0.2 + 0.03) / s, rel=1e-12)


@pytest.mark.parametrize("kwargs, match", [
    (dict(height=0.0), "height"), (dict(face_dip_deg=0.0), "face_dip_deg"),
    (dict(face_dip_deg=95.0), "face_dip_deg"), (dict(crest_length=-0.1), "crest_length"),
    (dict(base_thickness=np.nan), "base_thickness"), (dict(facing="up"), "facing"),
])
def test_profile_bad_input(kwargs, match):
    args = dict(height=0.2, face_dip_deg=60.0, crest_length=0.1, toe_length=0.1, base_thickness=0.05)
    args.update(kwargs)
    with pytest.raises(ValueError, match=match):
        slope_profile(**args)


def test_zone_too_deep_raises():
    r = slope_profile(0.2, 60.0, 0.01, 0.08, 0.05)
    with pytest.raises(ValueError, match="depth"):
        near_face_regions(r, 0.05)  # the band would cross the left side of the model
    with pytest.raises(ValueError, match="n_benches"):
        bench_profile(0.1, 0, 70, 0.03, 0.1, 0.1, 0.05)
