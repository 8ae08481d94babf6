"""Support under kinetic damping alone (``damping=0``, ``kinetic_damping=n``): the cable and
liner nodes are advanced by the step's one integration (``step.integration.advance_nodes``),
so the kinetic-damping stop and the half kick after it act on them as on the blocks.

- A grouted cable across a joint, pulled by its block, reaches the equilibrium local damping
  finds: its axial force against the elastic-grout solution (sinh) within 1 % of the pull.
- A liner spanning an opening under its weight sags as a clamped beam, q L^4 / (384 E I),
  within 1 %.
- At every kinetic-damping stop the kinetic energy of blocks and nodes is zero, and at every
  check the energy compared is that of blocks and nodes together.
- The threaded step gives the serial numbers, bit for bit, with support nodes.

The scenes and closed forms are those of tests/test_support.py.
"""
import math

import numba
import numpy as np
import pytest

from dem_core.components.support import decay_length
from dem_core.step.relaxation import free_kinetic_energy
from test_support import G, liner_over_opening, pulled_cable, two_blocks

PULL = 1e5                    # N/m on the cable's block
KINETIC = dict(damping=0.0, kinetic_damping=10)


def pulled(**options):
    m = pulled_cable(two_blocks())
    m.set_options(**options)
    m.apply_load("block", fx=PULL)
    return m


def sinh_force(cb):
    """The elastic-grout axial force at each segment's middle (tests/test_support.py)."""
    lam = decay_length(5e-4, 200e9, 1e8)                   # 1 m
    x = 0.5 * (cb.node_pos[cb.seg_a, 0] + cb.node_pos[cb.seg_b, 0])
    d = np.abs(x - 5.0)                                    # from the joint
    bond = 3.95                                            # grouted length on each side, m
    return PULL * np.sinh((bond - d) / lam) / np.sinh(bond / lam)


def test_a_grouted_cable_reaches_the_elastic_grout_solution_under_kinetic_damping_alone():
    m = pulled(**KINETIC)
    assert m.solve(ratio=1e-6, max_steps=100_000).verdict == "equilibrium"
    assert np.abs(m.cables.seg_force - sinh_force(m.cables)).max() < 0.01 * PULL


def clamped_sag():
    q, ei, span = 2500.0 * G * 0.1, 30e9 * 0.1 ** 3 / 12, 4.0
    return q * span ** 4 / (384 * ei)


def test_a_liner_over_an_opening_sags_as_a_clamped_beam_under_kinetic_damping_alone():
    """Checks every 200 steps, well under the quarter period of the liner's sag (about
    12,000 steps): it settles within 30,000 steps at 1.0098 of the clamped beam, where local
    damping settles (1.0099, in 105,000 steps to a ratio of 1e-6). The stiff liner's fast
    modes keep the unbalanced ratio near 3e-4 (no convergence measure with damping=0), so
    the sag is judged; checks every 10 or 50 steps stop the sag early, again and again, and
    leave it 0.4 % short or 0.2 % long."""
    m = liner_over_opening()
    m.set_options(damping=0.0, kinetic_damping=200)
    sags = []
    for _ in range(6):
        m.cycle(5000)
        ln = m.liners
        mid = np.argmin(np.abs(ln.node_pos[:, 0] - 4.0))
        sags.append(1.0 - ln.node_pos[mid, 1])
    assert abs(sags[-1] - sags[-2]) < 1e-3 * sags[-1]          # settled
    assert sags[-1] == pytest.approx(clamped_sag(), rel=0.01)


def kinetic_energy(m):
    """J/m: blocks (free components) and support nodes, inertial masses, as the
    kinetic-damping test counts them."""
    cb, ln = m.cables, m.liners
    ke = free_kinetic_energy(m.state, m.props)
    ke += 0.5 * float(((cb.node_vel ** 2).sum(axis=1) / cb.node_inv_mass).sum())
    ke += 0.5 * float(((ln.node_vel ** 2).sum(axis=1) / ln.node_inv_mass).sum())
    return ke + 0.5 * float((ln.node_omega ** 2 / ln.node_inv_inertia).sum())


def node_speed(m):
    return max([np.abs(a).max(initial=0.0) for a in
                (m.cables.node_vel, m.liners.node_vel, m.liners.node_omega)])


@pytest.mark.parametrize("scene, interval", [("cable", 10), ("liner", 200)])
def test_every_kinetic_damping_stop_stops_the_support_nodes_too(scene, interval):
    """Check by check (``Model.kinetic``: [energy at the last check, steps since, 1 just after
    a stop]): the energy compared includes the nodes' (the liner's blocks are fixed: all of
    it is the nodes'), and a stop leaves no kinetic energy anywhere."""
    m = pulled() if scene == "cable" else liner_over_opening()
    # checks every ``interval`` steps exactly (the fixed rule), so that each chunk ends at one
    m.set_options(damping=0.0, kinetic_damping=interval, kinetic_adaptive=False)
    stops, node_energy = 0, 0.0
    for _ in range(100):
        m.cycle(interval)
        assert m.kinetic[1] == 0.0                       # a check ended the chunk
        if m.kinetic[2] == 1.0:                          # stopped at this check
            stops += 1
            assert m.kinetic[0] == 0.0
            assert kinetic_energy(m) == 0.0 and node_speed(m) == 0.0
        else:
            assert m.kinetic[0] == pytest.approx(kinetic_energy(m), rel=1e-12, abs=0.0)
            node_energy = max(node_energy, m.kinetic[0] - free_kinetic_energy(m.state, m.props))
    assert stops >= 3 and node_energy > 0.0


@pytest.mark.skipif(numba.config.NUMBA_NUM_THREADS < 2, reason="needs 2 threads")
def test_the_threaded_step_moves_the_support_nodes_as_the_serial_one(monkeypatch):
    monkeypatch.setattr("dem_core.step.threads.parallel.MIN_CONTACTS", 0)   # threaded anyway
    runs = []
    for threads in (1, 2):
        m = pulled(threads=threads, **KINETIC)
        m.cycle(2000)
        runs.append(m)
    one, two = runs
    assert one.kinetic[0] == two.kinetic[0]
    for name in ("node_pos", "node_vel", "seg_force"):
        assert np.array_equal(getattr(one.cables, name), getattr(two.cables, name)), name
    assert np.array_equal(one.state.pos, two.state.pos)
    assert math.isfinite(one.kinetic[0])
