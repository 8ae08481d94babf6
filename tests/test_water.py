"""Water in the DEM: buoyancy, the Hoek & Bray plane failure with a water-filled tension crack,
exposed faces; bad water tables refused."""
import json
import math

import numpy as np
import pytest
from scipy.optimize import brentq

from dem_core.components.water import exposed_faces
from dem_core.geometry import GeometrySpec, rectangle
from dem_core.geometry.regions import Region
from dem_core.workflow.limit import search_failure
from dem_core.contact.materials import Material
from dem_core.workflow.scene import Boundary, Scene, build_model
from dem_core.workflow.stages import Gravity, Solve, run_stages
from dem_core.workflow.water import GAMMA_WATER, WaterTable

G = 9.81


def block_on_base(level):
    geo = GeometrySpec([rectangle("base", 0, 0, 4, 1), rectangle("block", 1, 1, 2, 1.5)])
    sc = Scene(geo, {"*": Material(kn=1e9, ks=1e9, friction=30.0)}, density=2500.0,
               boundaries=[Boundary("base")], points={"block": (1.5, 1.25)},
               stages=[Gravity(1.0), WaterTable(level), Solve(ratio=1e-7, max_steps=50_000)])
    return sc


@pytest.mark.parametrize("level, wet_height", [(3.0, 0.5), (1.2, 0.2)])
def test_a_submerged_block_weighs_its_buoyant_weight(level, wet_height):
    sc = block_on_base(level)
    m = build_model(sc)
    rec = run_stages(m, sc.stages)[-1]
    assert rec.verdict == "equilibrium"
    c = m.contacts
    on_block = (c.live("block_a") == m.group("block")[0]) | (c.live("block_b") ==
                                                             m.group("block")[0])
    carried = float((c.live("sn") * c.live("length"))[on_block].sum())   # effective, N/m
    buoyant = (2500.0 * 0.5 - 1000.0 * wet_height) * G * 1.0
    assert carried == pytest.approx(buoyant, rel=1e-5)    # to the solve ratio
    assert abs(rec.points["block"][0]) < 1e-9                 # the side pressures cancel


def test_exposed_faces_are_the_outline_and_what_an_excavation_bares():
    m = build_model(block_on_base(3.0))
    faces = exposed_faces(m.blocks, m.props.active)
    length = np.hypot(*(faces[2] - faces[1]).T)
    # the base's outline less the 1 m the block covers, and the block's top and sides
    assert length.sum() == pytest.approx(2 * (4 + 1) - 1 + 1 + 2 * 0.5, rel=1e-12)
    m.remove("block")
    faces = exposed_faces(m.blocks, m.props.active)
    assert np.hypot(*(faces[2] - faces[1]).T).sum() == pytest.approx(10.0, rel=1e-12)


PSI, PHI, COHESION = 30.0, 35.0, 10e3         # plane dip, friction, cohesion (Pa)
LP, TOP = 10.0, 10.0                          # plane length to the crack, top height (m)


def plane_failure_scene():
    """Hoek & Bray (1981, ch. 7) plane failure with a vertical tension crack: a block slides
    on a plane dipping PSI from the toe (0, 0); the crack at the plane's upper end is the
    block's free back face, 5 m deep; the face dips 60 deg. The interface keeps its cohesion
    when it slips (the rigid-plastic joint of limit equilibrium)."""
    ps = math.radians(PSI)
    xc, yc = LP * math.cos(ps), LP * math.sin(ps)
    block = Region("block", [(0, 0), (xc, yc), (xc, TOP), (TOP / math.tan(math.radians(60)),
                                                             TOP)])
    base = Region("base", [(-2, -2 * math.tan(ps) - 3), (14, -2 * math.tan(ps) - 3),
                           (14, 14 * math.tan(ps)), (-2, -2 * math.tan(ps))])
    mat = Material(kn=1e10, ks=1e10, cohesion=COHESION, residual_cohesion=COHESION,
                   friction=PHI)
    return Scene(GeometrySpec([base, block]), {"*": mat}, density=2500.0,
                 boundaries=[Boundary("base")], points={"block": (5.0, 6.0)},
                 stages=[Gravity(1.0), Solve(ratio=1e-6, max_steps=50_000)],
                 solver={"damping": 0.8})


def crack_table(zw):
    """Water in the crack to depth zw, draining along the plane to the toe (Hoek & Bray)."""
    ps = math.radians(PSI)
    return WaterTable(((0.0, 0.0), (LP * math.cos(ps), LP * math.sin(ps) + zw)))


def hoek_bray_fos(zw, weight):
    ps, ph = math.radians(PSI), math.radians(PHI)
    u = 0.5 * GAMMA_WATER * zw * LP                  # uplift on the plane (triangle)
    v = 0.5 * GAMMA_WATER * zw ** 2                  # push in the crack
    return (COHESION * LP + (weight * math.cos(ps) - u - v * math.sin(ps)) * math.tan(ph)) / (
        weight * math.sin(ps) + v * math.cos(ps))


def test_a_block_with_a_water_filled_tension_crack_slides_at_the_limit_equilibrium_depth():
    sc = plane_failure_scene()
    m = build_model(sc)
    weight = 2500.0 * G * float(m.props.mass[m.group("block")].sum() / 2500.0)
    z_lim = brentq(lambda z: hoek_bray_fos(z, weight) - 1.0, 0.0, 5.0)
    assert hoek_bray_fos(0.0, weight) > 1.1 and 1.0 < z_lim < 4.5
    assert run_stages(m, sc.stages)[-1].verdict == "equilibrium"
    rec = search_failure(m, np.arange(0.5, 5.0, 0.5), lambda mm, a, b: mm.set_water(
        crack_table(b)), ratio=1e-6, max_steps=20_000, failure_displacement=0.02,
        refine_to=0.02)
    assert rec.failure_level is not None
    assert rec.last_stable_level == pytest.approx(z_lim, rel=0.02), (rec.level, z_lim)


@pytest.mark.parametrize("bad, words", [
    (dict(surface=[[0.0, 1.0], [2.0, 3.0], [1.0, 2.0]]), "folds back"),
    (dict(surface=float("nan")), "must be finite"),
    (dict(surface=2.0, unit_weight=-1.0), "unit_weight"),
    (dict(surface=2.0, on="flaws"), "on="),
])
def test_bad_water_tables_are_refused_naming_the_item(tmp_path, bad, words):
    d = block_on_base(3.0).to_dict()
    d["stages"] = [dict(kind="water", **bad)]
    (tmp_path / "bad.json").write_text(json.dumps(d).replace("NaN", "NaN"))
    with pytest.raises(ValueError, match=words):
        Scene.load(tmp_path / "bad.json")
