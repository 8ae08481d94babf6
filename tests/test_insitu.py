"""In-situ stress (dem_core.workflow.insitu) in both methods:

- the traction of the field on a plane is the Mohr-circle closed form; depth is measured below
  a level, a polyline or the model's own top (a slope's profile);
- a layered Voronoi column under gravity, each contact given the geostatic field with
  k = 0.5, 1, 2, is in equilibrium at step 0: unbalanced ratio < 1e-3, no bond broken, and
  after 1,000 steps no block has moved 1e-3 of the column's elastic settlement under gravity;
- in a jointed slope given the same field (k = 0.5), the DEM and the continuum brought to
  equilibrium carry the same vertical stress along vertical lines behind the crest and through
  the face (RMS difference < 10 %);
- the thesis's initialisation (strong flaws under gravity, then the real strengths) leaves the
  model in equilibrium with its real strengths and no crack;
- bad fields are refused naming the item.
"""
import dataclasses
import json
import math

import numpy as np
import pytest

from dem_core.geometry import GeometrySpec, JointSet, Voronoi, rectangle, slope_profile
from dem_core.workflow.insitu import InSitu, model_top
from dem_core.workflow.recipes import strong_then_real
from dem_core.contact.materials import Material
from dem_core.units import STANDARD_GRAVITY as G
from dem_core.workflow.scene import Boundary, Scene, build_model
from dem_core.workflow.stages import Gravity, Solve, run_stages

RHO = 2600.0
SIDE_GROUPS = {"base": {"touching": "bottom"}, "left side": {"touching": "left"},
               "right side": {"touching": "right"},
               "side walls": {"union": ["left side", "right side"]},
               "sides": {"minus": ["side walls", "base"]}}
# smooth rigid walls: a block face flush with a wall slides along it but cannot turn (a roller
# at the centroid alone would let the wall blocks turn under the linear horizontal stress)
SMOOTH_WALLS = [Boundary("base"), Boundary("sides", x=True, y=False, rotation=True)]


@pytest.mark.parametrize("theta", [0.0, 0.3, 1.1, 2.0])
def test_traction_on_a_plane_is_the_mohr_circle(theta):
    f = InSitu(sxx=3e6, syy=1e6, sxy=0.5e6)
    nx, ny = math.cos(theta), math.sin(theta)
    sn, ts = f.traction(0.0, 0.0, nx, ny, top=np.array([[0.0, 0.0], [1.0, 0.0]]))
    c, s = math.cos(2 * theta), math.sin(2 * theta)
    assert sn == pytest.approx(2e6 + 1e6 * c + 0.5e6 * s, rel=1e-12)
    assert ts == pytest.approx(-1e6 * s + 0.5e6 * c, rel=1e-12)      # on t = (-ny, nx)


def test_depth_below_a_level_a_polyline_and_the_models_own_top():
    assert InSitu(gyy=1.0, surface=10.0).stress(0.0, 4.0)[1] == pytest.approx(6.0)
    f = InSitu(gyy=1.0, k=2.0, surface=((0.0, 10.0), (10.0, 20.0)))
    sxx, syy, _ = f.stress(np.array([5.0, -5.0, 5.0]), np.array([5.0, 5.0, 30.0]))
    assert np.allclose(syy, [10.0, 5.0, 0.0]) and np.allclose(sxx, 2 * syy)
    rock = slope_profile(20.0, 60, crest_length=20.0, toe_length=15.0, base_thickness=10.0)
    m = build_model(Scene(GeometrySpec([rock], joint_sets=[JointSet("j", 0.0, 5.0)]),
                          {"*": Material(kn=1e10, ks=1e10)}, density=RHO))
    top = model_top(m)
    x = np.linspace(0.0, 46.5, 40)
    crest, toe = 20.0, 20.0 + 20.0 / math.tan(math.radians(60))
    expected = np.interp(x, [0.0, crest, toe, 46.6], [30.0, 30.0, 10.0, 10.0])
    assert np.allclose(np.interp(x, top[:, 0], top[:, 1]), expected, atol=1e-9)


def column_scene():
    geo = GeometrySpec([rectangle("rock", 0.0, 0.0, 2.0, 6.0)],
                       joint_sets=[JointSet("bedding", 0.0, 0.5)],
                       voronoi={"rock": Voronoi(edge_length=0.25, seed=1, relax_iterations=10)})
    flaw = Material(kn=5e9, ks=2.5e9, tensile_strength=0.2e6, cohesion=0.3e6, friction=35.0)
    bed = Material(kn=5e9, ks=2.5e9, friction=30.0)
    return Scene(geo, {"flaw:*": flaw, "joint:*": bed}, density=RHO, groups=SIDE_GROUPS,
                 boundaries=SMOOTH_WALLS, solver={"mass_scaling": True, "damping": 0.8})


@pytest.fixture(scope="module")
def settlement():
    m = build_model(column_scene())
    r = run_stages(m, [Gravity(1.0), Solve(ratio=1e-6, max_steps=200_000)])[-1]
    assert r.verdict == "equilibrium"
    return float(np.abs(m.displacement()[:, 1]).max())


@pytest.mark.parametrize("k", [0.5, 1.0, 2.0])
def test_a_layered_column_given_the_geostatic_field_is_in_equilibrium_at_step_0(k, settlement):
    m = build_model(column_scene())
    run_stages(m, [Gravity(1.0), InSitu.geostatic(RHO, k)])
    c = m.contacts
    xy, nr = c.position(m.state.pos, m.state.rot), c.normal(m.state)
    flat = c.live("material") == m.table.names.index("joint:bedding")   # sn = rho g depth
    assert flat.sum() > 50 and np.all(np.abs(nr[flat, 1]) == 1.0)
    assert np.allclose(c.live("sn")[flat], RHO * G * (6.0 - xy[flat, 1]), rtol=1e-9)
    m.cycle(1)
    assert m.unbalanced_ratio() < 1e-3
    m.cycle(999)
    assert m.crack_counts() == {"tension": 0, "shear": 0}
    assert np.abs(m.displacement()).max() < 1e-3 * settlement


SP = 1.0


def slope_scene():
    rock = slope_profile(20.0, 60, crest_length=20.0, toe_length=15.0, base_thickness=10.0,
                         name="rock")
    geo = GeometrySpec([rock], joint_sets=[JointSet("bedding", 0.0, SP),
                                           JointSet("cross", 90.0, SP)])
    mat = Material(kn=2e10, ks=1e10, friction=45.0, cohesion=5e6, tensile_strength=5e6)
    return Scene(geo, {"*": mat}, density=2500.0, block_E=10e9, block_nu=0.25,
                 groups=SIDE_GROUPS, boundaries=SMOOTH_WALLS,
                 solver={"mass_scaling": True, "damping": 0.8})


def test_dem_and_continuum_carry_the_same_vertical_stress_in_a_jointed_slope():
    pytest.importorskip("dolfinx")
    from continuum_ref import _dolfinx05 as dx
    from continuum_ref.from_scene import (apply_boundaries, apply_insitu, mesh_from_scene,
                                          scene_bounds)
    from continuum_ref.materials import Elastic
    from continuum_ref.model import ContinuumModel

    sc = slope_scene()
    field = InSitu.geostatic(2500.0, 0.5)
    m = build_model(sc)
    rec = run_stages(m, [Gravity(1.0), field, Solve(ratio=1e-6, max_steps=100_000)])[-1]
    assert rec.verdict == "equilibrium" and np.abs(m.displacement()).max() > 0
    plain = dataclasses.replace(sc.geometry, joint_sets=[])    # the continuum has no joints
    cm = ContinuumModel(mesh_from_scene(sc, 0.5, geometry=plain), Elastic(10e9, 0.25), 2500.0)
    apply_boundaries(cm, sc, scene_bounds(sc))
    cm.set_gravity(1.0)
    apply_insitu(cm, sc, field)
    initial = cm.stress()[:, 1].copy()
    assert cm.equilibrate().converged
    syy = -cm.stress()[:, 1]
    assert np.abs(syy + initial).max() > 0.05 * np.abs(initial).max()   # the field moved

    c, n = m.contacts, m.contacts.n
    xy, nr = c.position(m.state.pos, m.state.rot), c.normal(m.state)
    top = model_top(m)
    depth = np.interp(xy[:n, 0], top[:, 0], top[:, 1]) - xy[:n, 1]
    for x0 in (10.0, 25.0):                  # behind the crest; through the middle of the face
        on = (np.abs(nr[:, 1]) > 0.99) & (np.abs(xy[:n, 0] - x0) <= SP / 2 + 1e-9) & \
            (depth > 2 * SP)
        _, cells = dx.cells_containing(cm.mesh, xy[:n][on] - [0.0, 0.01])
        assert np.all(cells >= 0) and on.sum() > 20
        dem, cont = c.sn[:n][on], syy[cells]
        assert np.linalg.norm(dem - cont) / np.linalg.norm(cont) < 0.10, x0


def test_the_thesis_initialisation_leaves_real_strengths_in_equilibrium():
    sc = column_scene()
    m = build_model(sc)
    stages = strong_then_real(sc.materials, ["flaw:*"], factor=100.0)
    recs = run_stages(m, stages)
    assert [r.kind for r in recs] == ["change_material", "gravity", "solve", "change_material"]
    assert recs[2].verdict == "equilibrium"
    assert m.materials["flaw:*"] == sc.materials["flaw:*"]
    assert m.crack_counts() == {"tension": 0, "shear": 0}
    m.cycle(1)
    assert m.unbalanced_ratio() < 1e-3


@pytest.mark.parametrize("bad, words", [
    (dict(gyy=2.5e4, k=-0.5), "k = sh / sv"),
    (dict(gyy=float("nan")), "gyy"),
    (dict(gyy=2.5e4, k=1.0, sxx=1e5), "either k or sxx"),
    (dict(gyy=2.5e4, surface=[[0.0, 10.0], [5.0, 12.0], [3.0, 11.0]]), "folds back"),
])
def test_bad_fields_are_refused_naming_the_item(tmp_path, bad, words):
    d = column_scene().to_dict()
    d["stages"] = [dict(kind="insitu", **bad)]
    (tmp_path / "bad.json").write_text(json.dumps(d))
    with pytest.raises(ValueError, match=words):
        Scene.load(tmp_path / "bad.json")
