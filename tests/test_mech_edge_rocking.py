"""An edge element with one end open (docs/mechanics.md, "Edge elements"): a block that rocks
on its base without toppling must not gain energy, and one that slides with its heel lifted
must slide at Coulomb's acceleration.

A tall block, b = 0.5 m wide and h = 1 m high, on a fixed base, undamped:

- at 20 degrees with friction 75 it neither slides nor topples (tan 20 = 0.36 < b/h = 0.5):
  the suddenly applied gravity rocks it on its base, lifting the heel. Until 2026-12-01 the
  closed end's shear stress was spread over the compressed length, a spring whose stiffness
  the rocking itself varies: the block gained energy and toppled after about 11 s.
- at 30 degrees with friction 20 it slides with a = g (sin 30 - cos 30 tan 20), the heel
  lifted all the while: the base's shear resultant must reach Coulomb's limit tan(phi) N on
  the compressed part (a lumped closed end would carry tan(phi) times its own peak stress
  over half the base, far more).
"""
import math
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
from scenes import block_on_plane, tilt  # noqa: E402  (benchmarks/scenes.py)

G = 9.81


def tall_block(friction, theta):
    m = block_on_plane(friction, width=0.5, height=1.0, edge_elements=True)
    assert (m.contacts.partner[:m.contacts.n] >= 0).all()       # the base is one edge element
    tilt(m, theta)
    return m


def test_a_rocking_block_that_cannot_topple_gains_no_energy():
    m = tall_block(75.0, 20.0)
    rocking, lifted, balance, external = 0.0, 0, [], []
    for _ in range(60):                         # 20 s, about 60,000 steps
        m.cycle(1000)
        rocking = max(rocking, abs(m.state.theta[1]))
        c = m.contacts
        lifted += int((c.sn[:c.n] == 0.0).any())
        e = m.energy()
        balance.append(e["balance"])
        external.append(e["external"])
    assert lifted > 10                          # it does rock on its toe (the heel lifts)
    assert rocking < 5e-3                       # bounded, far from toppling (0.5 rad)
    assert abs(m.state.pos[1, 0] - m.state.pos0[1, 0]) < 2e-3    # and it does not walk
    # no energy made: the account's balance (external work minus what is stored or spent)
    # never falls below zero by more than 2 % of the largest external work
    assert min(balance) > -0.02 * max(np.abs(external))


@pytest.mark.parametrize("edge_elements", [True, False])
def test_a_block_sliding_with_its_heel_lifted_keeps_coulomb_acceleration(edge_elements):
    m = block_on_plane(20.0, width=0.5, height=1.0, edge_elements=edge_elements)
    tilt(m, 30.0)
    m.cycle(1000)
    t1, v1 = m.time, m.state.vel[1, 0]
    m.cycle(6000)
    t2, v2 = m.time, m.state.vel[1, 0]
    a = (v2 - v1) / (t2 - t1)
    th, ph = math.radians(30.0), math.radians(20.0)
    expected = G * (math.sin(th) - math.cos(th) * math.tan(ph))
    c = m.contacts
    assert (c.sn[:c.n] == 0.0).any()            # one end of the base is open
    assert a == pytest.approx(expected, rel=0.02 if not edge_elements else 0.005)
    assert m.energy()["closure"] < 1e-3
