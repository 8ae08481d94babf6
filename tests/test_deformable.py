"""Deformable blocks (``Model(deformable=...)``, ``dem_core/deformable/component.py``):
closed-form checks of the floating frame.

- Without the option (or with a deformable block that touches nothing) every rigid block's
  forces and poses are those of the all-rigid model, bit for bit.
- A deformable square on a fixed base under gravity settles, top against bottom, by
  rho g H^2 / (2 E') (E' = E / (1 - nu^2): a plane-strain column with free sides).
- A very stiff deformable block comes to rest where the rigid one does.
- Undamped, a deformable block dropped onto an elastic contact keeps its energy (frame and
  zones' kinetic, zones' and contacts' strain, gravity).
- Save / load and snapshot / restore keep the zones (a resumed run is the same to the bit).
- Bad input raises ValueError naming it.
"""
import json
import math

import numba

import numpy as np
import pytest

from dem_core.contact.materials import Material
from dem_core.model import Model
from dem_core.geometry.simple_blocks import from_polygons

RHO, G, H = 2000.0, 9.81, 1.0
GLUED = dict(cohesion=1e9, tensile_strength=1e9)


def column(E=1e7, nu=0.25, size=0.2, deformable=True, kn=1e10, ks=1e9, bases=1, **options):
    """A fixed base [-0.5, 1.5] x [-0.5, 0] (``bases`` blocks side by side) and a square
    [0, 1] x [0, H] on it (group "top"), gravity down."""
    xs = np.linspace(-0.5, 1.5, bases + 1)
    base = [[(x0, -0.5), (x1, -0.5), (x1, 0), (x0, 0)] for x0, x1 in zip(xs[:-1], xs[1:])]
    bs = from_polygons(base + [[(0, 0), (1, 0), (1, H), (0, H)]],
                       groups={"base": list(range(bases)), "top": [bases]})
    m = Model(bs, {"flaw:*": Material(kn=kn, ks=ks, friction=30.0, **GLUED)}, density=RHO,
              block_E=E, block_nu=nu, deformable={"top": size} if deformable else None,
              **options)
    m.fix("base")
    m.set_gravity(1.0)
    return m


def _frames_ratio(m):
    """The unbalanced ratio of ``m``'s frames alone (its world with an empty zone bundle)."""
    from dem_core.deformable.component import no_deformable
    from dem_core.output.monitor import model_ratio
    return model_ratio(m.world()._replace(zones=no_deformable()), m.gravity, m.load, m.cables,
                       m.liners)


def top_minus_bottom(m):
    """Mean vertical displacement of the top's gridpoints minus the bottom's (m)."""
    z = m.zone_state
    u = z.x[:, 1] - z.x0[:, 1]
    return u[z.x0[:, 1] > H / 2 - 1e-9].mean() - u[z.x0[:, 1] < -H / 2 + 1e-9].mean()


def two_stacks(deformable):
    """Two separate scenes in one model: a rigid block sliding on a base (tilted gravity),
    and block "far" on its own base; "far" deformable or not. Fixed dt, no damping."""
    polys = [[(0, 0), (2, 0), (2, 1), (0, 1)], [(0.2, 1), (0.7, 1), (0.7, 1.5), (0.2, 1.5)],
             [(10, 0), (12, 0), (12, 1), (10, 1)], [(10.5, 1), (11.5, 1), (11.5, 2), (10.5, 2)]]
    bs = from_polygons(polys, groups={"base": [0, 2], "far": [3]})
    m = Model(bs, {"flaw:*": Material(kn=1e9, ks=1e9, friction=20.0)}, density=2000,
              block_E=1e9, damping=0.0, dt=2e-5, new_contact_material="flaw:rock",
              deformable={"far": 0.3} if deformable else None,
              edge_elements=False)          # the contact model zones take
    m.fix("base")
    th = math.radians(30)
    m.set_gravity(1.0, direction=(math.sin(th), -math.cos(th)))
    return m


def test_rigid_blocks_are_bit_for_bit_the_rigid_model():
    plain = two_stacks(False)
    assert plain.zone_state.point_offsets.size == 0          # no option: the empty bundle
    zoned = two_stacks(True)
    assert zoned.deformable_blocks.tolist() == [False, False, False, True]
    for m in (plain, zoned):
        m.cycle(800)
    rows = np.flatnonzero(plain.contacts.block_a[:plain.contacts.n] < 2)
    assert np.abs(plain.contacts.up[rows]).max() > 1e-4  # it slides (slip, reanchoring)
    assert np.abs(zoned.zone_state.x - zoned.zone_state.x0).max() > 0     # "far" deforms
    for name in ("sn", "ts", "un", "us"):
        assert np.array_equal(getattr(plain.contacts, name)[rows],
                              getattr(zoned.contacts, name)[rows]), name
    for name in ("force", "pos", "theta", "vel", "omega"):
        assert np.array_equal(getattr(plain.state, name)[:2], getattr(zoned.state, name)[:2])


def test_a_rigid_model_finds_contacts_without_the_deformed_points():
    """``detection.displacements`` calls its kernel with ``zones=None`` when no block is
    deformable: a signature of its own that leaves the deformed points out (a first search
    compiles in seconds, not tens of seconds); a deformable model at rest gives the same
    numbers through the deformed points."""
    from dem_core.contact import detection
    plain, zoned = two_stacks(False), two_stacks(True)
    rows = np.arange(plain.contacts.n)
    assert np.array_equal(plain.contacts.block_a[rows], zoned.contacts.block_a[rows])
    un0, us0 = detection.displacements(plain.contacts, plain.state, rows, plain.corners,
                                       plain.zone_state)
    un1, us1 = detection.displacements(zoned.contacts, zoned.state, rows, zoned.corners,
                                       zoned.zone_state)
    assert np.array_equal(un0, un1) and np.array_equal(us0, us1)
    assert {str(sig[-1]) == "none" for sig in detection._displacements.signatures} == {
        True, False}


def test_column_settles_by_rho_g_h2_over_2_e_prime():
    E, nu = 1e7, 0.25
    m = column(E, nu, damping=0.8)
    assert m.contacts.n == 10         # the 1 m edge in five 0.2 m pieces, a contact pair each
    m.cycle(4000)
    exact = -RHO * G * H ** 2 / (2 * E / (1 - nu ** 2))       # 0.92 mm
    assert top_minus_bottom(m) == pytest.approx(exact, rel=0.05)
    # the zones carry no rigid motion: mass-weighted mean displacement zero
    z = m.zone_state
    assert np.abs((z.mass[:, None] * (z.x - z.x0)).sum(0)).max() < 1e-12 * z.mass.sum()
    # twice as stiff: half the settlement
    stiff = column(2 * E, nu, damping=0.8)
    stiff.cycle(4000)
    assert top_minus_bottom(stiff) == pytest.approx(0.5 * top_minus_bottom(m), rel=0.02)
    # a solve stops when the zones too are still: their unbalanced forces count
    solved = column(E, nu, damping=0.8)
    solved.cycle(20)
    frames = _frames_ratio(solved)
    assert solved.unbalanced_ratio() > frames > 0
    r = solved.solve(ratio=1e-6, max_steps=20_000)
    assert r.verdict == "equilibrium"
    assert top_minus_bottom(solved) == pytest.approx(top_minus_bottom(m), rel=1e-3)
    # on three base blocks, whose corners meet the square's bottom face inside it (contacts
    # at points that are no vertex of the square), the same
    split = column(E, nu, bases=3, damping=0.8)
    split.cycle(4000)
    assert split.contacts.n > 10
    assert top_minus_bottom(split) == pytest.approx(top_minus_bottom(m), rel=0.02)
    # the rigid block's contacts carry the same weight, and it has no zones
    rigid = column(E, nu, deformable=False, damping=0.8)
    rigid.cycle(4000)
    assert rigid.zone_state.x.shape == (0, 2)
    w = RHO * G * H
    for mm in (m, rigid):
        c = mm.contacts
        assert (c.sn[:c.n] * c.length[:c.n]).sum() == pytest.approx(w, rel=1e-6)


def test_a_stiff_deformable_block_rests_where_the_rigid_one_does():
    poses = []
    for deformable in (False, True):
        bs = from_polygons([[(-1, -0.5), (2, -0.5), (2, 0), (-1, 0)],
                            [(0, 0), (1, 0), (1, 0.6), (0, 0.6)]], groups={"base": [0]})
        m = Model(bs, {"flaw:*": Material(kn=1e9, ks=5e8, friction=40.0)}, density=RHO,
                  block_E=1e12 if deformable else None, damping=0.8, mass_scaling=True,
                  deformable={"*": 1.0} if deformable else None,   # 1 m: edges not split
                  edge_elements=False)      # the contact model zones take
        m.fix("base")
        m.set_gravity(1.0, direction=(math.sin(math.radians(20)), -math.cos(math.radians(20))))
        m.cycle(3000)
        poses.append(np.r_[m.state.pos[1] - m.state.pos0[1], m.state.theta[1]])
    rigid, zoned = poses
    assert np.abs(rigid[:2]).max() > 1e-6              # it moved under the tilted gravity
    assert np.abs(zoned[:2] - rigid[:2]).max() < 5e-3 * np.abs(rigid[:2]).max()
    assert abs(zoned[2] - rigid[2]) < 5e-3 * abs(rigid[2]) + 1e-9


def total_energy(m):
    return m.kinetic_energy() + m.strain_energy() + m.gravity_energy()


def test_undamped_deformable_block_keeps_its_energy():
    """Gravity switched on at rest: the block bounces on its contacts, its zones vibrate.
    The energy (kinetic at the half steps) wavers by O(dt) and does not drift."""
    spread = []
    for safety, every in ((0.2, 125), (0.1, 250)):
        m = column(E=2e7, size=0.25, damping=0.0, kn=1e8, ks=1e8, safety=safety)
        energies, kinetic = [], []
        for _ in range(60):
            m.cycle(every)
            energies.append(total_energy(m))
            kinetic.append(m.kinetic_energy())
        z = m.zone_state
        scale = max(kinetic)                               # the motion's energy
        assert scale > 0 and float(np.abs(z.v).max()) > 0  # the frame and the zones move
        spread.append(max(abs(e) for e in energies) / scale)
        assert abs(np.mean(energies[-10:])) < 0.01 * scale  # no drift
    assert spread[1] < 0.03
    assert spread[1] == pytest.approx(0.5 * spread[0], rel=0.3)   # first order in dt


def test_save_load_and_snapshot_keep_the_zones(tmp_path):
    m = column(damping=0.5)
    m.cycle(300)
    snap = m.snapshot()
    path = tmp_path / "m.npz"
    m.save(path)
    back = Model.load(path)
    assert back.deformable == {"top": 0.2}
    m.cycle(300)
    back.cycle(300)
    x_after = m.zone_state.x.copy()
    assert np.array_equal(back.zone_state.x, x_after)
    assert np.array_equal(back.state.pos, m.state.pos)
    m.restore(snap)
    m.cycle(300)
    assert np.array_equal(m.zone_state.x, x_after)


@pytest.mark.parametrize("kw, word", [
    (dict(deformable={"top": -0.1}), "-0.1"),
    (dict(deformable={"top": float("nan")}), "nan"),
    (dict(deformable={"nowhere": 0.2}), "nowhere"),
    (dict(deformable={"top": 0.2}, block_E=None), "block_E"),
    (dict(deformable=["top"]), "dict"),
    (dict(deformable={"*": 0.2}, rounding=0.01), "rounding"),
])
def test_bad_input_is_refused_naming_it(kw, word):
    bs = from_polygons([[(0, 0), (1, 0), (1, 1), (0, 1)], [(0, 1), (1, 1), (1, 2), (0, 2)]],
                       groups={"top": [1]})
    args = dict(block_E=1e9)
    args.update(kw)
    with pytest.raises(ValueError, match=word.replace("[", r"\[")):
        Model(bs, {"flaw:*": Material(kn=1e9, ks=1e9, friction=30.0)}, density=RHO, **args)


@pytest.mark.skipif(numba.config.NUMBA_NUM_THREADS < 2, reason="needs 2 threads")
def test_deformable_voronoi_specimen_threaded_is_bit_for_bit_serial(monkeypatch):
    """Every block of a Voronoi specimen deformable: the threaded contact kernel gives the
    serial numbers, and every contact of the tessellation acts on both blocks' zones."""
    from dem_core.contact.boundary_points import contact_sides as _sides
    from dem_core.contact.contacts import ANCHOR_MID
    from dem_core.geometry import GeometrySpec, Voronoi, build_block_system, rectangle

    monkeypatch.setattr("dem_core.step.threads.parallel.MIN_CONTACTS", 0)
    monkeypatch.setattr("dem_core.step.threads.region.MIN_CONTACTS", 0)
    bs = build_block_system(GeometrySpec(
        [rectangle("rock", 0, 0, 0.1, 0.05), rectangle("base", 0, -0.01, 0.1, 0)],
        voronoi={"rock": Voronoi(edge_length=0.006, seed=2)}))
    flaw = Material(kn=1e10, ks=5e9, tensile_strength=2e4, cohesion=4e4, friction=35)
    runs = []
    for threads in (1, 2):
        m = Model(bs, {"flaw:*": flaw, "boundary:*": flaw}, density=2500.0, threads=threads,
                  block_E=1e9, deformable={"rock": 0.004})
        m.fix("base")
        m.set_gravity(300.0)
        m.cycle(1000)
        runs.append(m)
    one, two = runs
    assert np.abs(one.zone_state.x - one.zone_state.x0).max() > 1e-7
    for name in ("pos", "theta"):
        assert np.array_equal(getattr(one.state, name), getattr(two.state, name))
    assert np.array_equal(one.zone_state.x, two.zone_state.x)
    c, rock = one.contacts, one.deformable_blocks
    for k in range(c.n):
        ea, qa0, qa1, eb, qb0, qb1 = _sides(one.zone_state, k, c, one.state)
        assert (ea >= 0) == rock[c.block_a[k]] and (eb >= 0) == rock[c.block_b[k]]
        if c.anchor[k] != ANCHOR_MID:              # a split edge's inner contacts are points
            assert (qa1 > qa0 or ea < 0) and (qb1 > qb0 or eb < 0)   # a stretch


def test_a_scene_makes_its_regions_deformable():
    from dem_core.geometry import GeometrySpec, rectangle
    from dem_core.workflow.scene import Boundary, Scene, build_model

    geo = GeometrySpec([rectangle("base", 0, -0.02, 0.1, 0), rectangle("rock", 0, 0, 0.1, 0.2)])
    sc = Scene(geo, {"*": Material(kn=1e10, ks=5e9, friction=35, **GLUED)}, density=2500.0,
               block_E=1e9, boundaries=[Boundary("base")], solver={"deformable": {"rock": 0.05}})
    again = Scene.from_dict(json.loads(json.dumps(sc.to_dict())))
    m = build_model(again)
    rock = m.group("rock")
    assert m.deformable == {"rock": 0.05}
    assert m.deformable_blocks[rock].all() and m.deformable_blocks.sum() == rock.size
    m.set_gravity(50.0)
    m.cycle(500)
    assert np.abs(m.zone_state.x - m.zone_state.x0).max() > 0
