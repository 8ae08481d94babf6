"""Rounded corners (``Model(rounding=d)``, ``dem_core/contact/rounding.py``): closed-form checks.

- d = 0 is the sharp-cornered model to the bit: the forces, poses and stresses of a small scene
  (a block sliding on a base, a tilted block sliding off its end) equal those stored from the
  code before the option existed (commit 408c697, ``tests/data/rounding_sharp_reference.npz``).
- A corner pressed onto a corner pushes along the line of the two arcs' centres with
  kn L (overlap), the overlap being 2 d minus the centres' distance.
- A corner driven round the end of a face turns its normal continuously, and the energy of the
  frictionless, undamped motion does not grow.
- Bad values raise ValueError naming them.
- ``rounding="auto"`` (the default): 1 % of the median edge on every block, less on a block
  with a sharp corner or a short edge (by the closed forms of the clearance and the largest
  rounding); sharp corners on deformable blocks; saved and loaded to the bit.
"""
import math
from pathlib import Path

import numpy as np
import pytest

from dem_core.contact.materials import Material
from dem_core.model import Model
from dem_core.contact.rounding import corner_centres
from dem_core.geometry.simple_blocks import from_polygons

REFERENCE = Path(__file__).parent / "data" / "rounding_sharp_reference.npz"
KN = 1e9
G = 9.81


def sliding_scene(**options):
    """A fixed base [0, 2] x [0, 1], a square sliding on it, and a square tilted by 10 deg on
    one corner near the base's end, both pressed 10-20 um in; gravity tilted 30 deg to +x,
    friction 20 deg, no damping (the scene of the stored reference)."""
    tilted = [(1.6 + 0.25 * math.cos(a), 1.25 - 1e-5 + 0.25 * math.sin(a)) for a in
              (math.radians(-80 + 90 * k) for k in range(4))]
    low = min(p[1] for p in tilted)
    tilted = [(x, y - low + 1.0 - 2e-5) for x, y in tilted]
    bs = from_polygons([[(0, 0), (2, 0), (2, 1), (0, 1)],
                        [(0.2, 1 - 1e-5), (0.7, 1 - 1e-5), (0.7, 1.5 - 1e-5), (0.2, 1.5 - 1e-5)],
                        tilted], groups={"base": [0]})
    m = Model(bs, {"flaw:*": Material(kn=KN, ks=KN, friction=20.0)}, density=2000,
              damping=0.0, new_contact_material="flaw:rock", search_margin=1e-3, **options)
    m.fix("base")
    th = math.radians(30)
    m.set_gravity(1.0, direction=(math.sin(th), -math.cos(th)))
    return m


def test_zero_rounding_is_the_sharp_model_to_the_bit():
    ref = np.load(REFERENCE)
    # the reference predates the division of interfaces: the contact lengths as made
    m = sliding_scene(rounding=0.0, divide_interfaces=False)
    m.cycle(2500)             # the tilted block slides off the base's end and falls
    c = m.contacts
    for name, now in (("force", m.state.force), ("pos", m.state.pos),
                      ("theta", m.state.theta), ("sn", c.sn[:c.n]), ("ts", c.ts[:c.n])):
        assert np.array_equal(now, ref[name]), name


def diamond(cx, cy, h):
    """A square of half-diagonal h standing on a corner (CCW from its right corner)."""
    return [(cx + h, cy), (cx, cy + h), (cx - h, cy), (cx, cy - h)]


def test_corner_on_corner_pushes_along_the_line_of_the_centres():
    """Two diamonds tip to tip, the upper one 3 mm to the right: the arcs' centres are d sqrt 2
    inside each tip; the contact normal is the line of the centres and the force
    kn L (2 d - |c_B - c_A|), whichever block the search calls A (one contact)."""
    d, dx, overlap = 0.01, 0.003, 1e-4
    # the upper tip's height above the lower one that gives the overlap
    rise = math.sqrt((2 * d - overlap) ** 2 - dx * dx) - 2 * math.sqrt(2) * d
    bs = from_polygons([diamond(0.0, 0.0, 0.5), diamond(dx, 1.0 + rise, 0.5)],
                       groups={"low": [0], "high": [1]})
    m = Model(bs, {"flaw:*": Material(kn=KN, ks=KN, friction=30.0)}, density=2000,
              new_contact_material="flaw:rock", search_margin=0.02, rounding=d)
    m.fix("low")
    m.fix("high")
    m.cycle(1)
    c = m.contacts
    assert c.n == 1
    lower = np.array([0.0, 0.5 - math.sqrt(2) * d])          # the arcs' centres
    upper = np.array([dx, 0.5 + rise + math.sqrt(2) * d])
    line = upper - lower
    dist = np.hypot(*line)
    assert dist == pytest.approx(2 * d - overlap, rel=1e-9)
    n = line / dist                                           # from the lower into the upper
    high_is_b = c.block_b[0] == 1
    force_on_high = m.state.force[1, :2]
    expected = KN * c.length[0] * overlap * n
    assert force_on_high == pytest.approx(expected, rel=1e-6)
    assert c.sn[0] == pytest.approx(KN * overlap, rel=1e-6)
    assert abs(c.ts[0]) < 1e-6 * c.sn[0]
    assert np.linalg.norm(force_on_high) > 0 and (high_is_b or not high_is_b)
    # the sharp model pushes along one block's face normal instead (45 deg off)
    sharp = Model(bs, {"flaw:*": Material(kn=KN, ks=KN, friction=30.0)}, density=2000,
                  new_contact_material="flaw:rock", search_margin=0.02, rounding=0.0)
    sharp.fix("low")
    sharp.fix("high")
    sharp.cycle(1)
    f = sharp.state.force[1, :2]
    assert abs(abs(f[0]) - abs(f[1])) < 1e-9 * np.hypot(*f)


def corner_on_base(d, cx, overlap, friction):
    """A fixed base [0, 1] x [0, 1] and a diamond (half-diagonal 5 cm, rotation held) whose
    rounded tip, at x = cx, is ``overlap`` into the base's top; (model, the tip's vertex)."""
    h = 0.05
    bs = from_polygons([[(0, 0), (1, 0), (1, 1), (0, 1)], diamond(cx, 1.0 + h, h)])
    arc_low = corner_centres(bs.vertex_offsets, bs.vertices, d)[bs.vertex_offsets[1] + 3, 1] - d
    bs = from_polygons([[(0, 0), (1, 0), (1, 1), (0, 1)],
                        diamond(cx, 1.0 + h - (arc_low - (1.0 - overlap)), h)],
                       groups={"base": [0], "block": [1]})
    m = Model(bs, {"flaw:*": Material(kn=KN, ks=KN, friction=friction)}, density=2000,
              damping=0.0, new_contact_material="flaw:rock", search_margin=1e-3, rounding=d)
    m.fix("base")
    return m, bs.vertex_offsets[1] + 3


def test_a_corner_turns_round_the_end_of_a_face_continuously():
    """The diamond's tip is moved (prescribed) along the top to the base's corner, then round
    it on a circle about the base's corner centre, keeping the overlap: the normal is the line
    of the centres, -(sin phi, cos phi), turning in small steps from the top face's normal, and
    the stress stays kn (overlap) (no jump where the face ends). The sharp model keeps the top
    face's normal there."""
    d, overlap, dt = 0.003, 2e-6, 1e-5
    m, tip = corner_on_base(d, 0.99, overlap, friction=0.0)
    m.set_options(dt=dt)
    m.fix("block")
    corner = np.array([1.0 - d, 1.0 - d])                  # the base's corner centre
    radius = 2 * d - overlap
    # the tip's centre: along the top to above the corner, then round it by 40 deg
    path = [corner + (x, radius) for x in np.linspace(0.99 - (1 - d), 0.0, 200)]
    path += [corner + radius * np.array([math.sin(p), math.cos(p)])
             for p in np.linspace(0.0, math.radians(40), 400)[1:]]
    offset = -m.corners.centre[tip]                       # centroid - tip's centre
    normals, stresses = [], []
    for target in path[1:]:
        v = (target + offset - m.state.pos[1]) / dt
        m.set_velocity("block", vx=float(v[0]), vy=float(v[1]), omega=0.0)
        m.cycle(1)
        c = m.contacts
        k = [j for j in range(c.n) if c.vertex_a[j] == tip][0]
        normals.append(c.normal(m.state, m.corners)[k])
        stresses.append(c.sn[k])
    normals = np.array(normals)
    phi = math.radians(40)
    assert normals[0] == pytest.approx([0.0, -1.0], abs=1e-9)
    # (the last step's forces were computed at the pose before it)
    assert normals[-1] == pytest.approx([-math.sin(phi), -math.cos(phi)], abs=2e-3)
    turns = np.arccos(np.clip((normals[1:] * normals[:-1]).sum(axis=1), -1, 1))
    assert turns.max() < math.radians(0.5)
    assert np.array(stresses[5:]) == pytest.approx(KN * overlap, rel=2e-2)
    # sharp corners: the tip is held by the top face's line past its end
    m, tip = corner_on_base(0.0, 0.99, overlap, friction=0.0)
    m.set_options(dt=dt)
    m.state.pos[1] += (path[-1] + offset) - m.state.pos[1]
    m.cycle(1)
    c = m.contacts
    k = [j for j in range(c.n) if c.vertex_a[j] == tip][0]
    assert c.normal(m.state)[k] == pytest.approx([0.0, -1.0], abs=1e-12)


def test_energy_does_not_grow_as_a_corner_slides_off_a_face_end():
    """Frictionless and undamped, gravity tilted 45 deg to the base's end: the diamond slides
    off the end, its rounded tip turning round the base's rounded corner as it leaves. Kinetic
    (whole-step velocities) + spring + gravity energy does not grow."""
    m, tip = corner_on_base(0.003, 0.995, 2e-6, friction=0.0)
    m.fix("block", x=False, y=False, rotation=True)
    m.set_gravity(1.0, direction=(1.0, -1.0))
    energies = []
    vel_before, pos_before = m.state.vel[1].copy(), m.state.pos[1].copy()
    for _ in range(800):
        m.cycle(1)
        v = 0.5 * (vel_before + m.state.vel[1])
        gravity = -m.props.mass[1] * ((pos_before - m.state.pos0[1]) @ m.gravity)
        energies.append(0.5 * m.props.mass[1] * (v @ v) + m.strain_energy() + gravity)
        vel_before, pos_before = m.state.vel[1].copy(), m.state.pos[1].copy()
    assert m.state.pos[1, 0] > m.state.pos0[1, 0] + 0.01           # it left the top
    energies = np.array(energies)
    drop = -m.props.mass[1] * ((m.state.pos[1] - m.state.pos0[1]) @ m.gravity)
    assert energies.max() - energies[0] < 1e-3 * abs(drop)


@pytest.mark.parametrize("bad", [-1e-3, float("nan"), float("inf"), "a", 0.2])
def test_bad_rounding_raises_naming_the_value(bad):
    bs = from_polygons([[(0, 0), (1, 0), (1, 1), (0, 1)], [(0, 1), (1, 1), (1, 1.5), (0, 1.5)]])
    with pytest.raises(ValueError, match="rounding") as err:
        Model(bs, {"flaw:*": Material(kn=KN, ks=KN, friction=30.0)}, density=2000,
              rounding=bad)
    assert repr(bad) in str(err.value)


def wedge(x0, angle_deg, length=1.0):
    """A triangle with one corner of ``angle_deg`` at (x0, 0) and a right angle (CCW)."""
    a = math.radians(angle_deg)
    return [(x0, 0.0), (x0 + length, 0.0), (x0 + length, length * math.tan(a))]


def test_auto_rounds_each_block_by_its_own_corners_and_edges():
    # d = 1 % of the median edge; a block whose sharpest corner (a) would hang clear of a face
    # by more than a right angle's d (sqrt 2 - 1) takes d (sqrt 2 - 1) / (1/sin(a/2) - 1);
    # one with an edge the radius would consume, half its largest rounding
    polys = [[(0, 0), (1, 0), (1, 1), (0, 1)] for _ in range(4)]
    polys = [[(x + 2 * i, y) for x, y in p] for i, p in enumerate(polys)]
    polys += [wedge(10.0, 20.0), [(12, 0), (13, 0), (13, 1e-4), (12, 1e-4)]]
    bs = from_polygons(polys)
    m = Model(bs, {"flaw:*": Material(kn=KN, ks=KN, friction=30.0)}, density=2000)
    off = m.props.vertex_offsets
    edges = np.concatenate([np.hypot(*np.diff(np.vstack([p, p[:1]]), axis=0).T)
                            for p in map(np.asarray, polys)])
    d = 0.01 * np.median(edges)
    arc = m.corners.arc
    for b in range(4):
        assert np.all(arc[off[b]:off[b + 1]] == pytest.approx(d, rel=1e-12))
    clear = 1 / math.sin(math.radians(10.0)) - 1
    assert arc[off[4]] == pytest.approx(d * (math.sqrt(2) - 1) / clear, rel=1e-9)
    assert arc[off[5]] == pytest.approx(0.5 * 1e-4 / 2, rel=1e-9)     # L / (cot 45 + cot 45)
    # the wedge's 20 deg corner stands off its face by the right angle's clearance, no more
    assert arc[off[4]] * clear == pytest.approx(d * (math.sqrt(2) - 1), rel=1e-9)


def test_auto_is_sharp_on_deformable_blocks_and_survives_save_and_load(tmp_path):
    bs = from_polygons([[(0, 0), (1, 0), (1, 1), (0, 1)], [(0, 1), (1, 1), (1, 2), (0, 2)]])
    mats = {"flaw:*": Material(kn=KN, ks=KN, friction=30.0)}
    soft = Model(bs, mats, density=2000, block_E=1e9, deformable={"*": 0.5})
    assert soft.corners.radius == 0.0 and soft.options.rounding == 0.0
    m = Model(bs, mats, density=2000)
    assert m.options.rounding == "auto" and m.corners.radius == pytest.approx(0.01)
    m.save(tmp_path / "m.npz")
    back = Model.load(tmp_path / "m.npz")
    assert np.array_equal(back.corners.arc, m.corners.arc)
    assert np.array_equal(back.corners.centre, m.corners.centre)
