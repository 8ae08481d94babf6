"""The Longtan block-toppling scene: the section, the two joint sets (dips, persistence per
column), rock bridges with flaws, the conventional counterpart's smeared bases, the points."""
import math

import numpy as np
import pytest
import shapely
from shapely.geometry import LineString, Point, Polygon

from comparisons.scenes import longtan as scene
from dem_core.geometry import build_block_system
from dem_core.geometry.stats import realized_persistence

FINE = scene.LongtanParams(edge_length=0.005, relax_iterations=5)


@pytest.fixture(scope="module")
def blocks():
    return build_block_system(scene.geometry(FINE))


def _edges(bs, name):
    k = bs.edge_material == bs.material_names.index(name)
    return bs.edge_p0[k], bs.edge_p1[k]


def test_section_is_0752_m_wide_with_the_stated_slope(blocks):
    run = scene.SLOPE_HEIGHT / math.tan(math.radians(scene.FACE_DIP))
    area = scene.WIDTH * scene.HEIGHT - 0.5 * scene.SLOPE_HEIGHT * run
    assert blocks.area.sum() == pytest.approx(area, rel=1e-9)
    assert blocks.bounds() == pytest.approx((0.0, 0.0, 0.752, scene.HEIGHT), abs=1e-12)
    (x0, y0), (x1, y1) = scene.face()
    assert math.degrees(math.atan2(y1 - y0, x0 - x1)) == pytest.approx(scene.FACE_DIP)


@pytest.mark.parametrize("name, sense", [("joint:columns", +1), ("joint:cross", -1)])
def test_both_sets_dip_60_columns_into_the_slope_cross_joints_with_the_face(blocks, name,
                                                                           sense):
    p0, p1 = _edges(blocks, name)
    d = p1 - p0
    d *= np.sign(d[:, 1])[:, None]                 # each edge pointing upwards
    # the face looks to +x: into the slope = going down towards -x = up towards +x
    assert np.all(sense * d[:, 0] > 0)
    assert np.degrees(np.arctan2(d[:, 1], sense * d[:, 0])) == pytest.approx(60.0, abs=1e-6)


def test_cross_joint_persistence_is_08_in_the_toe_column_and_07_elsewhere(blocks):
    k = realized_persistence(blocks)
    assert k["columns"] == pytest.approx(1.0)
    assert k["cross"] == pytest.approx(0.7, abs=0.02)
    assert k["cross_toe"] == pytest.approx(0.8, abs=0.03)
    # the toe column is the strip behind the continuous joint through the toe
    toe = Polygon(scene.toe_column(FINE))
    assert toe.buffer(1e-9).contains(Point(scene.face()[0]))
    p0, p1 = _edges(blocks, "joint:cross_toe")
    mid = 0.5 * (p0 + p1)
    assert shapely.contains_xy(toe.buffer(1e-9), mid[:, 0], mid[:, 1]).all()


def test_every_bridge_near_the_face_is_intact_rock_crossed_by_flaws(blocks):
    """The bridges are the gaps between the open parts along each cross-joint trace in the
    Voronoi zone; each holds flaw edges (intact rock that can break), no joint edge."""
    spec = scene.geometry(FINE)
    from dem_core.geometry.joints import traces_in_region

    flaws = [i for i, m in enumerate(blocks.material_names) if m.startswith("flaw:zone")]
    k = np.isin(blocks.edge_material, flaws)
    flaw_lines = shapely.linestrings(np.stack([blocks.edge_p0[k], blocks.edge_p1[k]], axis=1))
    tree = shapely.STRtree(flaw_lines)
    n_bridges = 0
    for region in spec.regions:
        if region.name not in spec.voronoi:
            continue
        for t in traces_in_region(region.name, region.polygon(), spec.joint_sets, []):
            if not t.name.startswith("cross"):
                continue
            line, ends = LineString(t.coords), np.r_[0.0, t.intervals.ravel(), t.length]
            for a, b in ends.reshape(-1, 2):
                if b - a < 0.8 * (1 - FINE.persistence_toe) * FINE.column_spacing / math.sin(
                        math.radians(60)):
                    continue                        # a stub cut by the face or the zone
                bridge = shapely.ops.substring(line, a + 1e-4, b - 1e-4)
                assert len(tree.query(bridge, predicate="intersects")) > 0
                n_bridges += 1
    assert n_bridges >= 10


def test_conventional_counterpart_smears_the_bridges_over_persistent_bases():
    p = FINE.with_(conventional=True)
    mats = scene.materials(p)
    assert mats["joint:cross"].cohesion == pytest.approx(0.474e6, rel=1e-3)
    assert mats["joint:cross_toe"].cohesion == pytest.approx(0.316e6, rel=1e-3)
    assert mats["joint:cross"].friction == 0.0 and not mats["flaw:*"].breakable
    damage = scene.materials(FINE)
    assert damage["joint:cross"].cohesion == 0.0 and damage["flaw:*"].breakable
    assert damage["flaw:*"].tensile_strength == pytest.approx(4.81e6)
    bs = build_block_system(scene.geometry(p.with_(edge_length=0.01)))
    assert realized_persistence(bs)["cross"] == pytest.approx(1.0)


def test_monitoring_points_are_inside_the_rock():
    rock = Polygon(scene.profile())
    assert all(rock.contains(Point(*xy)) for xy in scene.monitoring_points().values())


def test_softening_can_be_kept_to_the_voronoi_zone(blocks):
    """flaw_softening_regions="zone*": the zone's flaws soften, every other bond (the bridges
    of the joint-bounded rock, the region boundaries) keeps the brittle law."""
    from dem_core.contact.materials import material_for

    soft = FINE.with_(flaw_fracture_energy_I=300.0, flaw_fracture_energy_II=3000.0,
                      flaw_softening_regions="zone*")
    mats = scene.materials(soft)
    names = [n for n in blocks.material_names if n.startswith(("flaw:", "boundary:"))]
    zone = [n for n in names if n.startswith("flaw:zone")]
    assert zone and len(zone) < len(names)
    for n in names:
        m = material_for(n, mats)
        assert (m.fracture_energy_I, m.fracture_energy_II) == (
            (300.0, 3000.0) if n in zone else (0.0, 0.0)), n
    everywhere = scene.materials(soft.with_(flaw_softening_regions="*"))
    bonds = [n for n in names if material_for(n, everywhere).tensile_strength > 0]  # (not the
    assert len(bonds) > len(zone)                                 # toe column's side joints)
    assert all(material_for(n, everywhere).fracture_energy_I == 300.0 for n in bonds)
