"""Contact search, loading, verdicts, save/resume and input checks of the mechanics driver."""
import math

import numpy as np
import pytest

from dem_core.contact.contacts import UNBONDED
from dem_core.contact.materials import Material, material_table
from dem_core.model import Model, ModelUnstable
from dem_core.geometry.simple_blocks import brick_grid, from_polygons

G = 9.81
JOINT = Material(kn=1e9, ks=1e9, friction=30)


def dropped_block(gap=0.2):
    bs = from_polygons([[(0, 0), (4, 0), (4, 1), (0, 1)],
                        [(1, 1 + gap), (2, 1 + gap), (2, 1.5 + gap), (1, 1.5 + gap)]],
                       edge_material="joint:any", groups={"base": [0], "block": [1]})
    bs.material_names = ["joint:any"]
    return bs


def test_falling_block_is_caught_by_the_search_and_rests_on_the_base():
    m = Model(dropped_block(), {"joint:*": JOINT}, density=2000, damping=0.0)
    assert m.contacts.n == 0
    m.fix("base")
    m.set_gravity(1.0)
    # free fall over the 20 cm gap takes sqrt(2 0.2 / g) = 0.202 s
    m.cycle(int(0.19 / m.dt))
    assert m.state.vel[1, 1] == pytest.approx(-G * m.time, rel=1e-6)   # still free
    assert m.contacts.n >= 2                        # found before touching (within the margin)
    assert np.all(m.contacts.sn[:m.contacts.n] == 0)
    m.set_options(damping=0.8)
    r = m.solve(ratio=1e-4, max_steps=50_000)
    assert r.verdict == "equilibrium", r.reason
    c = m.contacts
    assert c.n >= 2 and np.all(c.broken[:c.n] == UNBONDED)
    # resting on the base: bottom at y = 1 less the elastic overlap m g / (kn L)
    overlap = m.props.mass[1] * G / (1e9 * 1.0)
    assert m.state.pos[1, 1] == pytest.approx(1.25 - overlap, abs=0.05 * overlap + 1e-9)
    assert (c.sn[:c.n] * c.length[:c.n]).sum() == pytest.approx(m.props.mass[1] * G, rel=1e-3)


def test_toppling_column_finds_new_contacts_and_keeps_history():
    # a slender column on a wide base, pushed sideways: it tips over its corner onto the base
    bs = from_polygons([[(0, 0), (6, 0), (6, 1), (0, 1)], [(1, 1), (1.4, 1), (1.4, 3), (1, 3)]],
                       edge_material="joint:any", groups={"base": [0], "column": [1]})
    m = Model(bs, {"joint:*": Material(kn=1e9, ks=1e9, friction=40)}, density=2000,
              damping=0.0)
    m.fix("base")
    m.set_gravity(1.0)
    # a clockwise push about the toe corner (1.4, 1): enough energy to pass over it
    m.state.omega[1] = -1.0
    m.state.vel[1] = (1.0, 0.2)
    m.cycle(int(1.5 / m.dt))
    m.set_options(damping=0.8)
    assert m.state.theta[1] < -1.2            # fell over towards +x (about -pi/2 + a bit)
    r = m.solve(ratio=1e-4, max_steps=80_000)
    assert r.verdict == "equilibrium", r.reason
    c = m.contacts
    # lying on its side: its long face on the base, centroid 0.2 m above it
    assert m.state.pos[1, 1] == pytest.approx(1.2, abs=0.01)
    assert (c.sn[:c.n] * c.length[:c.n]).sum() == pytest.approx(m.props.mass[1] * G, rel=1e-2)


def pushed_pair(friction=30.0):
    bs = brick_grid(2, 1, 1.0, 0.5)
    return Model(bs, {"flaw:*": Material(kn=1e9, ks=1e9, friction=friction)}, density=2000)


def test_save_and_resume_is_bit_for_bit(tmp_path):
    bs = brick_grid(6, 4, 0.1, 0.1, stagger=True)
    mat = {"flaw:*": Material(kn=1e10, ks=5e9, tensile_strength=2e3, cohesion=4e3,
                              friction=30)}
    a = Model(bs, mat, density=2500)
    a.fix([0, 1])                                   # an overhanging wall: it cracks
    a.set_gravity(40.0)
    a.add_history_point("top", (0.3, 0.4))
    a.cycle(700)
    path = tmp_path / "state.npz"
    a.save(path)
    b = Model.load(path)
    a.cycle(1500)
    b.cycle(1500)
    assert a.cracks.count[0] > 0                  # it did break, so the log is exercised
    for name in ("pos", "theta", "vel", "omega", "force"):
        assert np.array_equal(getattr(a.state, name), getattr(b.state, name)), name
    n = a.contacts.n
    assert n == b.contacts.n
    for name in ("sn", "ts", "us", "up", "broken"):
        assert np.array_equal(a.contacts.live(name), b.contacts.live(name)), name
    assert np.array_equal(a.crack_log()["x"], b.crack_log()["x"])
    assert a.history.as_arrays()["top.uy"].tolist() == b.history.as_arrays()["top.uy"].tolist()


def test_excavation_removes_blocks_and_their_contacts():
    bs = brick_grid(4, 3, 0.5, 0.5, groups={"cut": [10, 11]})
    m = Model(bs, {"flaw:*": Material(kn=1e9, ks=1e9, tensile_strength=1e5, cohesion=1e5,
                                      friction=30)}, density=2000)
    n0 = m.contacts.n
    m.remove("cut")
    c = m.contacts
    assert not np.isin(c.block_a[:c.n], [10, 11]).any()
    assert not np.isin(c.block_b[:c.n], [10, 11]).any()
    assert c.n < n0
    m.fix("bottom")
    m.set_gravity(1.0)
    r = m.solve(ratio=1e-4, max_steps=20_000)
    assert r.verdict == "equilibrium"
    assert np.all(m.state.pos[[10, 11]] == m.state.pos0[[10, 11]])


def test_strength_change_between_stages_makes_a_hanging_block_fall():
    # a block glued under a fixed ceiling by tension: holds at T, drops when T is lowered
    bs = brick_grid(1, 2, 1.0, 0.5)
    m = Model(bs, {"flaw:*": Material(kn=1e9, ks=1e9, tensile_strength=2e4, cohesion=2e4,
                                      friction=30)}, density=2000)
    m.fix("top")
    m.set_gravity(1.0)                  # needs sn = -m g / L = -9.8 kPa > -20 kPa: holds
    r = m.solve(ratio=1e-5, max_steps=20_000)
    assert r.verdict == "equilibrium" and m.cracks.count[0] == 0
    m.set_material("flaw:*", tensile_strength=5e3)
    r = m.solve(ratio=1e-5, max_steps=6000, failure_displacement=0.2)
    assert r.verdict == "failed"
    assert m.crack_counts()["tension"] == 2


def test_verdict_failed_for_a_sliding_block_and_moving_for_slow_creep():
    bs = from_polygons([[(0, 0), (20, 0), (20, 1), (0, 1)], [(2, 1), (3, 1), (3, 1.5), (2, 1.5)]],
                       edge_material="joint:b", groups={"base": [0], "block": [1]})
    m = Model(bs, {"joint:*": Material(kn=1e9, ks=1e9, friction=20)}, density=2000)
    m.fix("base")
    th = math.radians(35)
    m.set_gravity(1.0, direction=(math.sin(th), -math.cos(th)))
    r = m.solve(ratio=1e-6, max_steps=6000)
    assert r.verdict == "failed", r.reason
    m2 = Model(bs, {"joint:*": Material(kn=1e9, ks=1e9, friction=40)}, density=2000)
    m2.fix("base")
    m2.set_gravity(1.0, direction=(math.sin(th), -math.cos(th)))
    r2 = m2.solve(ratio=1e-5, max_steps=60_000)
    assert r2.verdict == "equilibrium", r2.reason


def test_servo_holds_a_constant_normal_force_while_the_base_shears():
    # direct shear in miniature: a lower box moves in x, the upper block is servo-loaded
    bs = brick_grid(1, 2, 1.0, 0.5, groups={"lower": [0], "upper": [1]})
    m = Model(bs, {"flaw:*": Material(kn=1e9, ks=1e9, friction=30)}, density=2000)
    N = 5e4
    m.fix("upper", y=False)              # the upper box: no x motion, no rotation
    m.servo("upper", force=N, direction=(0.0, -1.0))
    m.set_velocity("lower", vx=0.01, vy=0.0)
    m.cycle(4000)
    c = m.contacts
    normal = (c.sn[:c.n] * c.length[:c.n]).sum()
    shear = abs((c.ts[:c.n] * c.length[:c.n]).sum())
    assert normal == pytest.approx(N, rel=0.01)
    assert shear == pytest.approx(N * math.tan(math.radians(30)), rel=0.02)


def test_bad_input_is_refused_before_compute():
    bs = brick_grid(2, 1, 1.0, 1.0)
    for bad in (dict(kn=-1.0, ks=1e9), dict(kn=1e9, ks=1e9, friction=90.0),
                dict(kn=float("nan"), ks=1e9), dict(kn=1e9, ks=1e9, cohesion=-5.0)):
        with pytest.raises(ValueError, match="kn|friction|cohesion"):
            Model(bs, {"flaw:*": Material(**bad)}, density=2000)
    with pytest.raises(ValueError, match="density"):
        Model(bs, {"flaw:*": JOINT}, density=float("nan"))
    with pytest.raises(ValueError, match="no material"):
        Model(bs, {"joint:*": JOINT}, density=2000)
    with pytest.raises(ValueError, match="no block group"):
        Model(bs, {"flaw:*": JOINT}, density=2000).fix("nowhere")
    with pytest.raises(ValueError, match="damping"):
        Model(bs, {"flaw:*": JOINT}, density=2000, damping=1.5)
    table = material_table(["flaw:a", "joint:b"], {"*": JOINT, "joint:*": JOINT},
                           unbreakable="flaw:*")
    assert table.breakable.tolist() == [0, 1]


def test_instability_is_reported_with_the_block_and_cause():
    bs = brick_grid(2, 2, 0.1, 0.1)
    m = Model(bs, {"flaw:*": Material(kn=1e12, ks=1e12)}, density=2500, dt=1e-3)
    m.fix("bottom")
    m.set_gravity(1.0)
    with pytest.raises(ModelUnstable, match=r"block \d+.*critical step"):
        m.cycle(2000)


def test_a_squeezed_thin_block_is_named_as_the_cause():
    """A block whose contacts overlap by more than a tenth of its width (area / (2 radius)):
    the diagnosis says so, with the overlap, instead of blaming the time step."""
    bs = brick_grid(3, 1, 1.0, 0.2)                  # three 1 m x 0.2 m bricks side by side
    m = Model(bs, {"flaw:*": Material(kn=1e9, ks=1e9)}, density=2500)
    c = m.contacts
    mine = np.flatnonzero((c.block_a[:c.n] == 1) | (c.block_b[:c.n] == 1))
    assert "squeezed" not in m.diagnose(1)
    width = bs.area[1] / (2.0 * m.props.radius[1])
    c.un[mine[0]] = -0.2 * width                     # overlap a fifth of the width
    c.sn[mine[0]] = 1e9 * 0.2 * width
    msg = m.diagnose(1)
    assert "squeezed block" in msg and "0.2 of its width" in msg
