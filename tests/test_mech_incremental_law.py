"""The incremental contact law and the common normal of two faces in contact.

- a scene and its mirror image give mirrored displacements, rotations and verdicts (before the
  common normal, each half of a shared edge took its normal from one block's face, which turned
  with that block: a block resting just inside its friction limit held facing -x and crept
  without end facing +x);
- a strength change touches only the strength table: no stress, no position moves;
- a stiffness change keeps the stresses; new stiffness acts on increments;
- a contact can start with a given stress: a block whose contacts start with its weight is in
  equilibrium at step 0.
"""
import math

import numpy as np
import pytest

from dem_core.contact.materials import Material
from dem_core.model import Model
from dem_core.geometry.simple_blocks import brick_grid, from_polygons

G = 9.81


def resting_block(side, theta_deg, friction, kn=10e6, width=1.0, height=0.5):
    """A width x height block on a fixed base, gravity tilted by theta towards ``side`` (+1:
    the slope faces +x, -1: its mirror image). Contacts of kn = ks (Pa/m)."""
    s = float(side)
    base = [(0, 0), (20 * s, 0), (20 * s, 1), (0, 1)]
    block = [(2 * s, 1), ((2 + width) * s, 1), ((2 + width) * s, 1 + height), (2 * s, 1 + height)]
    bs = from_polygons([base, block], edge_material="joint:base",
                       groups={"base": [0], "block": [1]})
    m = Model(bs, {"joint:*": Material(kn=kn, ks=kn, friction=friction)}, density=2000,
              damping=0.8)
    m.fix("base")
    th = math.radians(theta_deg)
    m.set_gravity(1.0, direction=(s * math.sin(th), -math.cos(th)))
    return m


def test_a_scene_and_its_mirror_image_move_as_mirror_images():
    runs = {}
    for side in (+1, -1):
        m = resting_block(side, theta_deg=29.0, friction=30.0)
        res = m.solve(ratio=1e-6, max_steps=60_000)
        u = m.state.pos[1] - m.state.pos0[1]
        runs[side] = (res.verdict, u, m.state.theta[1])
    (v_p, u_p, r_p), (v_m, u_m, r_m) = runs[+1], runs[-1]
    assert v_p == v_m == "equilibrium"                  # both hold: 29 deg < friction 30 deg
    size = np.hypot(*u_p)
    assert size > 1e-5                                  # it did settle (m), so mirroring is tested
    assert u_p[0] == pytest.approx(-u_m[0], rel=1e-6, abs=1e-12 * size)
    assert u_p[1] == pytest.approx(u_m[1], rel=1e-6, abs=1e-12 * size)
    assert r_p == pytest.approx(-r_m, rel=1e-6, abs=1e-12)


def test_the_mirrored_block_slides_alike_beyond_its_friction_limit():
    ux, accel = [], []
    for side in (+1, -1):
        m = resting_block(side, theta_deg=40.0, friction=30.0)
        m.set_options(damping=0.0)
        m.cycle(500)
        t1, v1 = m.time, side * m.state.vel[1, 0]
        m.cycle(1000)                                   # about 14 m down the 20 m base
        accel.append((side * m.state.vel[1, 0] - v1) / (m.time - t1))
        ux.append(side * (m.state.pos[1, 0] - m.state.pos0[1, 0]))
    th, ph = math.radians(40.0), math.radians(30.0)
    assert accel[0] == pytest.approx(G * (math.sin(th) - math.cos(th) * math.tan(ph)),
                                     rel=0.01)          # Coulomb sliding
    assert ux[0] > 1.0
    assert ux[0] == pytest.approx(ux[1], rel=1e-9)       # downhill on both sides, alike


def loaded_column(block_E=2e9):
    """A 2 x 6 brick column on a fixed base row under 20 g, settled: bonded flaws (T, c high)."""
    bs = brick_grid(2, 7, 0.05, 0.05, stagger=True)
    flaw = Material(kn=5e9, ks=3e9, tensile_strength=2e6, cohesion=2e6, friction=35)
    m = Model(bs, {"flaw:*": flaw}, density=2500, block_E=block_E, block_nu=0.2)
    m.fix("bottom")
    m.set_gravity(20.0)
    m.solve(ratio=1e-7, max_steps=50_000)
    return m


def test_lowering_the_strength_of_a_loaded_model_moves_no_stress_and_no_block():
    ref, low = loaded_column(), loaded_column()      # deterministic: two identical models
    sn0, ts0, kn0 = ref.contacts.live("sn").copy(), ref.contacts.live("ts").copy(), \
        ref.contacts.live("kn").copy()
    low.set_material("flaw:*", tensile_strength=0.5e6, cohesion=0.6e6)
    assert np.array_equal(low.contacts.live("sn"), sn0)
    assert np.array_equal(low.contacts.live("ts"), ts0)
    assert np.array_equal(low.contacts.live("kn"), kn0)
    assert np.abs(sn0).max() < 0.4e6 and np.abs(ts0).max() < 0.3e6   # nothing will break
    ref.cycle(500)
    low.cycle(500)
    assert np.array_equal(low.state.pos, ref.state.pos)
    assert np.array_equal(low.contacts.live("sn"), ref.contacts.live("sn"))
    assert low.crack_counts() == {"tension": 0, "shear": 0}


def test_a_stiffness_change_keeps_the_stresses_and_acts_on_increments():
    m = loaded_column(block_E=None)
    sn0 = m.contacts.live("sn").copy()
    kn0 = m.contacts.live("kn").copy()
    pos0 = m.state.pos.copy()
    m.set_material("flaw:*", kn=10e9)
    assert np.array_equal(m.contacts.live("sn"), sn0)          # no jump
    assert np.allclose(m.contacts.live("kn"), 2 * kn0)
    m.solve(ratio=1e-7, max_steps=20_000)
    # the load did not change, so the blocks stay where they were and stresses stay in balance
    assert np.abs(m.state.pos - pos0).max() < 1e-3 * np.abs(sn0).max() / kn0.min()
    assert m.contacts.live("sn").sum() == pytest.approx(sn0.sum(), rel=1e-4)


def test_contacts_started_with_the_weight_are_in_equilibrium_at_step_zero():
    bs = from_polygons([[(0, 0), (4, 0), (4, 1), (0, 1)], [(1, 1), (2, 1), (2, 1.5), (1, 1.5)]],
                       edge_material="joint:base", groups={"base": [0], "block": [1]})
    kn = 1e9
    m = Model(bs, {"joint:*": Material(kn=kn, ks=kn, friction=30)}, density=2000, damping=0.0)
    m.fix("base")
    m.set_gravity(1.0)
    weight = 2000 * 0.5 * G                            # N/m over a 1 m contact
    m.set_contact_stress(weight / 1.0)
    m.cycle(1)
    assert m.unbalanced_ratio() < 1e-3
    m.cycle(1000)
    settlement = weight / kn                           # what it would sink without the stress
    assert abs(m.state.pos[1, 1] - m.state.pos0[1, 1]) < 1e-3 * settlement
