"""Held deformable blocks (a boundary on the zones' gridpoints) and the gmsh zone mesh.

Closed forms: a column held at its base settles rho g H^2 (1 - nu^2) / (2 E) under its own
weight (plane strain, uniaxial stress); a cantilever held at its left end deflects
q L^4 / (8 E' I) + q L^2 / (2 kappa G A) under its weight (Timoshenko, kappa = 5/6), the
zones converging at second order.
"""
import numpy as np
import pytest

from dem_core.geometry import GeometrySpec, build_block_system, rectangle
from dem_core.contact.materials import Material
from dem_core.model import Model
from dem_core.workflow.scene import Boundary, Scene, group_sides
from dem_core.deformable.zone_mesh import face_segments, mesh_polygons

E, NU, RHO = 1e9, 0.25, 2500.0
ROCK = {"flaw:*": Material(kn=1e10, ks=1e10, friction=30.0)}


def _one_block(width, height, size, **kw):
    bs = build_block_system(GeometrySpec([rectangle("rock", 0, 0, width, height)]))
    return Model(bs, ROCK, density=RHO, block_E=E, block_nu=NU, deformable={"*": size}, **kw)


def _settle(m, points, tol=1e-4, chunk=1000, max_chunks=60):
    z, prev = m.zone_state, 0.0
    for _ in range(max_chunks):
        m.cycle(chunk)
        u = float(np.mean(z.x[points, 1] - z.x0[points, 1]))
        if abs(u - prev) < tol * abs(u):
            return u
        prev = u
    raise AssertionError(f"not settled after {chunk * max_chunks} steps: {u}")


def test_column_held_at_its_base_settles_as_uniaxial_plane_strain():
    H = 10.0
    # (the check interval must be well under the column's quarter period, 150 steps here)
    m = _one_block(1.0, H, 0.25, damping=0.0, kinetic_damping=10)
    m.fix("rock", at="bottom")
    m.set_gravity(1.0)
    z = m.zone_state
    top = np.flatnonzero(np.abs(z.x0[:, 1] - z.x0[:, 1].max()) < 1e-9)
    u = _settle(m, top)
    exact = -RHO * 9.81 * H ** 2 * (1 - NU ** 2) / (2 * E)
    assert u == pytest.approx(exact, rel=0.02)
    base = np.abs(z.x0[:, 1] - z.x0[:, 1].min()) < 1e-9
    assert np.all(z.x[base] == z.x0[base])                      # held at the base only
    assert np.all(m.state.pos == m.blocks.centroid)              # the frame does not move
    # the reactions are not an unbalanced force: the column reaches equilibrium
    assert 0.0 < m.unbalanced_ratio() < 0.01        # measured 2.2e-3 (with reactions: ~1)


@pytest.mark.parametrize("size, low, high", [(0.5, 0.65, 0.75), (0.25, 0.90, 0.95),
                                             (0.125, 0.96, 1.0)])
def test_cantilever_held_at_its_left_end_converges_to_timoshenko(size, low, high):
    L, D = 10.0, 1.0
    m = _one_block(L, D, size, damping=0.0, kinetic_damping=100)
    m.fix("rock", at="left")
    m.set_gravity(1.0)
    z = m.zone_state
    tip = np.flatnonzero(np.abs(z.x0[:, 0] - z.x0[:, 0].max()) < 1e-9)
    q, Ep, G = RHO * 9.81 * D, E / (1 - NU ** 2), E / (2 * (1 + NU))
    exact = q * L ** 4 / (8 * Ep * D ** 3 / 12) + q * L ** 2 / (2 * 5 / 6 * G * D)
    # measured 0.695, 0.921, 0.978 of exact: errors fall about 4x per halving (second order)
    assert low < -_settle(m, tip) / exact < high


def test_held_sides_are_checked():
    m = _one_block(1.0, 1.0, 0.5)
    with pytest.raises(ValueError, match="sides"):
        m.fix("rock", at="middle")


def test_scene_boundaries_hold_the_sides_their_groups_touch():
    groups = {"base": {"touching": "bottom"}, "left side": {"touching": "left"},
              "right side": {"touching": "right"},
              "side walls": {"union": ["left side", "right side"]},
              "sides": {"minus": ["side walls", "base"]}, "top rock": {"inside": [[0, 0.5], [1, 0.5], [1, 1], [0, 1]]}}
    sc = Scene(GeometrySpec([rectangle("rock", 0, 0, 1, 1)]), ROCK, density=RHO, groups=groups,
               boundaries=[Boundary("base")])
    assert group_sides(sc, "base") == ["bottom"]
    assert group_sides(sc, "sides") == ["left", "right"]
    assert group_sides(sc, "top rock") is None and group_sides(sc, "nothing") is None


def test_gmsh_zone_mesh_of_a_thin_column():
    col = np.array([[0, 0], [0.01, 0], [0.01, 0.33], [0, 0.33]]) - [0.005, 0.165]
    (pts, tri, faces), = mesh_polygons([col], [0.0025])
    assert [len(f) - 1 for f in faces] == face_segments(col, 0.0025).tolist() == [4, 132, 4, 132]
    p = pts[tri]
    twice = ((p[:, 1, 0] - p[:, 0, 0]) * (p[:, 2, 1] - p[:, 0, 1])
             - (p[:, 2, 0] - p[:, 0, 0]) * (p[:, 1, 1] - p[:, 0, 1]))
    assert np.all(twice > 0)                                     # counter-clockwise
    assert 0.5 * twice.sum() == pytest.approx(0.0033, rel=1e-12)    # covers the block
    edges = np.linalg.norm(p - np.roll(p, -1, axis=1), axis=2)
    quality = 2 * np.sqrt(3) * twice / (edges ** 2).sum(axis=1)     # 1 for equilateral
    assert quality.min() > 0.5 and edges.max() < 1.3 * 0.0025
    for j, f in enumerate(faces):                               # equal segments, in order
        seg = np.diff(pts[f], axis=0)
        assert np.allclose(seg, (col[(j + 1) % 4] - col[j]) / (len(f) - 1), atol=1e-12)
    again, = mesh_polygons([col], [0.0025])                    # same mesh every call
    assert np.array_equal(again[0], pts) and np.array_equal(again[1], tri)


def test_gmsh_zone_mesh_refuses_bad_input():
    sq = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], float)
    with pytest.raises(ValueError, match="polygon 0: zone size"):
        mesh_polygons([sq], [0.0])
    with pytest.raises(ValueError, match="counter-clockwise"):
        mesh_polygons([sq[::-1]], [0.5])


def test_a_history_point_on_a_held_block_follows_its_zones():
    m = _one_block(1.0, 10.0, 0.25, damping=0.0, kinetic_damping=10)
    m.fix("rock", at="bottom")
    m.add_history_point("top", (0.5, 10.0 - 1e-6))
    m.set_gravity(1.0)
    m.cycle(3000)
    z = m.zone_state
    top = np.flatnonzero(np.abs(z.x0[:, 1] - z.x0[:, 1].max()) < 1e-9)
    uy = float(np.mean(z.x[top, 1] - z.x0[top, 1]))
    assert uy < -1e-4                                   # the frame is held; the zones moved
    assert m.point_motion("top")[1] == pytest.approx(uy, rel=0.01)


def test_slipping_and_open_contacts_between_deformable_columns_keep_the_energy():
    """Two columns held at their base, a broken frictionless joint between them (it opens and
    slides every step), gravity tilted 10 degrees, no damping: the total energy stays put (a
    moved contact point once added a spurious increment each step: E grew to 10 % of KE)."""
    from dem_core.geometry import JointSet
    bs = build_block_system(GeometrySpec([rectangle("rock", 0, 0, 0.02, 0.33)],
                                         joint_sets=[JointSet("j", 90, 0.01)]))
    joint = Material(kn=700e9, ks=600e9, friction=0.0)
    m = Model(bs, {"joint:j": joint, "flaw:*": joint}, density=2426.0, block_E=2.6e9,
              block_nu=0.16, deformable={"*": 0.005}, damping=0.0, safety=0.25)
    m.fix(m.blocks.touching("bottom"), at="bottom")
    m.set_gravity(10.0, direction=(np.sin(np.radians(10)), -np.cos(np.radians(10))))
    worst, ke = 0.0, 0.0
    for _ in range(5):
        m.cycle(2000)
        worst = max(worst, abs(m.kinetic_energy() + m.strain_energy() + m.gravity_energy()))
        ke = max(ke, m.kinetic_energy())
    c = m.contacts
    assert np.any(c.sn[:c.n] == 0.0) and np.any(c.sn[:c.n] > 0.0)    # open and closed ones
    assert ke > 0.01 and worst < 1e-3 * ke               # measured: 5e-6 of 0.03 J/m


def test_conventional_scene_has_joint_blocks_deformable_and_optionally_plastic():
    from comparisons.scenes import adhikary
    from dem_core.workflow.scene import build_model, conventional
    sc = adhikary.scene(adhikary.AdhikaryParams(edge_length=0.006))
    conv = conventional(sc, 0.005, plastic=True)
    assert sc.geometry.voronoi and not conv.geometry.voronoi      # the scene is not changed
    assert conv.solver["zone_strength"]["rock"] == dict(cohesion=1.6e6, friction=37.0,
                                                        tensile_strength=1.1e6)
    m = build_model(conv)
    assert m.n_blocks < 60 and m.deformable_blocks.all()         # the beds, not the flaws
    assert np.isfinite(m.zone_state.strength[:, 0]).all()
    # every block touches the base: held at its base gridpoints, the walls' in x
    assert m.zone_state.held.all() and (m.zone_state.point_held == 3).any()
    with pytest.raises(ValueError, match="rigid blocks"):
        conventional(Scene(sc.geometry, sc.materials, density=1.0), 0.005)
