"""Mechanics against closed forms: sliding block, elastic oscillation, free rotation.

Each test compares a measured number with its closed form and a tolerance that a wrong law,
wrong sign or wrong integrator would break.
"""
import math
import sys
from pathlib import Path

import numpy as np
import pytest

from dem_core.contact.materials import Material
from dem_core.model import Model
from dem_core.geometry.simple_blocks import from_polygons

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
from scenes import block_on_plane, bonded_pair, tilt  # noqa: E402  (benchmarks/scenes.py)

G = 9.81


@pytest.mark.parametrize("theta, friction", [(30.0, 20.0), (40.0, 10.0)])
def test_block_slides_with_coulomb_acceleration(theta, friction):
    # settled on its base first, as the closed form assumes: dropped with its full weight the
    # block rocks, and on edge elements (a kern of b/6) its heel lifts (+0.23 % on a at
    # 30 / 20 deg; settled +0.05 %)
    m = block_on_plane(friction)
    m.set_options(damping=0.8)
    tilt(m, 0.0)
    m.cycle(2000)
    m.set_options(damping=0.0)
    tilt(m, theta)
    m.cycle(1000)
    t1, v1 = m.time, m.state.vel[1, 0]
    m.cycle(6000)
    t2, v2 = m.time, m.state.vel[1, 0]
    a = (v2 - v1) / (t2 - t1)
    th, ph = math.radians(theta), math.radians(friction)
    expected = G * (math.sin(th) - math.cos(th) * math.tan(ph))
    assert a == pytest.approx(expected, rel=0.01)
    assert m.state.pos[1, 0] - m.state.pos0[1, 0] > 1.0          # it really slid (metres)
    assert abs(m.state.pos[1, 1] - m.state.pos0[1, 1]) < 1e-3     # on the plane, not through it


@pytest.mark.parametrize("friction, slides", [(33.0, False), (27.0, True)])
def test_block_stays_below_friction_angle_and_slides_above(friction, slides):
    # Settled first (a suddenly applied load overshoots and would slip dynamically), then
    # tilted to 30 deg with quasi-static damping.
    m = block_on_plane(friction)
    m.set_options(damping=0.8)
    tilt(m, 0.0)
    m.cycle(2000)
    tilt(m, 30.0)
    m.cycle(6000)
    u = np.hypot(*(m.state.pos[1] - m.state.pos0[1]))
    if slides:
        assert u > 0.05
    else:
        # only the elastic shear deflection m g sin(theta) / (ks L), about 1e-5 m, is allowed
        assert u < 5e-5
        assert m.contacts.slipping[:m.contacts.n].sum() == 0


def test_tipping_limit_is_not_confused_with_sliding():
    # a tall block (h/b = 2) on a rough plane at 30 deg: tan 30 < b/h, so it neither slides nor
    # topples; at 70 deg with friction 75 (no slip) tan 70 > b/h = 0.5 and it topples.
    m = block_on_plane(friction=75.0, width=0.5, height=1.0)
    tilt(m, 70.0)
    m.cycle(4000)
    assert abs(m.state.theta[1]) > 0.05                           # it rotates (topples)
    # At 20 deg the suddenly applied (undamped) load rocks the block on its corners, by up to
    # about 7e-4 rad: bounded, far below the toppling block's 0.05 rad.
    m2 = block_on_plane(friction=75.0, width=0.5, height=1.0)
    tilt(m2, 20.0)
    rocking = 0.0
    for _ in range(40):
        m2.cycle(100)
        rocking = max(rocking, abs(m2.state.theta[1]))
    assert rocking < 2e-3


def test_bonded_block_oscillates_with_spring_mass_period_and_keeps_energy():
    m = bonded_pair()
    m.fix("base")
    v0 = 0.01
    m.state.vel[1, 1] = v0
    k = 1e9 * 1.0                                   # kn x edge length, N/m per m
    period = 2 * math.pi * math.sqrt(m.props.mass[1] / k)
    n = int(20 * period / m.dt)
    t, vy, energy = np.empty(n), np.empty(n), np.empty(n)
    for i in range(n):
        m.cycle(1)
        t[i], vy[i] = m.time, m.state.vel[1, 1]
        energy[i] = m.kinetic_energy() + m.strain_energy()
    # period from the upward zero crossings of the (half-step) velocity
    up = np.flatnonzero((vy[:-1] < 0) & (vy[1:] >= 0))
    tc = t[up] - vy[up] * (t[up + 1] - t[up]) / (vy[up + 1] - vy[up])
    measured = np.diff(tc).mean()
    assert measured == pytest.approx(period, rel=0.02)
    e0 = 0.5 * m.props.mass[1] * v0 ** 2
    per = int(round(period / m.dt))
    first, last = energy[:per].mean(), energy[-per:].mean()
    assert first == pytest.approx(e0, rel=0.02)
    assert abs(last - first) / first < 0.01


def test_spinning_bonded_pair_keeps_angular_momentum():
    m = bonded_pair(kn=1e8, ks=5e7)
    w0 = 3.0
    c = m.state.pos.mean(axis=0)
    for i in range(2):           # rigid-body spin about the pair's centre
        r = m.state.pos[i] - c
        m.state.vel[i] = w0 * np.array([-r[1], r[0]])
        m.state.omega[i] = w0

    def ang_mom():
        s, p = m.state, m.props
        r = s.pos - (p.mass[:, None] * s.pos).sum(0) / p.mass.sum()
        return float((p.inertia * s.omega + p.mass * (r[:, 0] * s.vel[:, 1]
                                                       - r[:, 1] * s.vel[:, 0])).sum())

    L0 = ang_mom()
    m.cycle(3000)
    assert abs(m.state.theta[0]) > 1.0                          # it turned a lot
    assert ang_mom() == pytest.approx(L0, rel=1e-6)
    # the bond holds the blocks together: their distance stays ~1 m (centrifugal stretch only)
    assert np.hypot(*(m.state.pos[1] - m.state.pos[0])) == pytest.approx(1.0, abs=1e-3)


def test_free_block_under_gravity_keeps_spin_and_falls_parabolically():
    bs = from_polygons([[(0, 0), (2, 0), (2, 1), (0, 1)]])
    m = Model(bs, {"*": Material(kn=1e9, ks=1e9)}, density=2500, damping=0.0, dt=1e-3)
    m.state.omega[0] = 2.0
    m.set_gravity(1.0)
    m.cycle(1000)
    assert m.state.omega[0] == 2.0
    assert m.state.theta[0] == pytest.approx(2.0, rel=1e-9)
    assert m.state.pos[0, 1] - m.state.pos0[0, 1] == pytest.approx(-0.5 * G * 1.0, rel=1e-2)
