"""Kinetic damping (dynamic relaxation, ``Model(kinetic_damping=n)``) against closed forms.

- A block hanging on one bonded edge settles by m g / (kn L) (rigid blocks): kinetic damping
  must reach that static answer, not a damped approximation of it.
- The slender Voronoi cantilever of tests/test_mech_specimens.py: kinetic damping must give the
  same static tip deflection as local damping solved to equilibrium, in fewer steps (local
  damping turns a slender structure's lowest mode into a slow creep: the reason the option
  exists, docs/mechanics.md).
"""
import sys
from pathlib import Path

import numpy as np
import pytest

from dem_core.contact.materials import Material
from dem_core.model import Model
from dem_core.geometry.simple_blocks import brick_grid

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
from scenes import materials, voronoi_bar  # noqa: E402


def test_hanging_block_settles_to_the_static_spring_extension():
    kn, h, w, rho, g_level = 1e10, 0.1, 0.1, 2500.0, 10.0
    bs = brick_grid(1, 2, w, h)
    m = Model(bs, {"flaw:*": Material(kn=kn, ks=kn, breakable=False)}, density=rho,
              damping=0.0, kinetic_damping=5)
    m.fix("top")
    m.add_history_point("tip", (0.05, 0.0))
    m.set_gravity(g_level)
    m.cycle(2000)
    static = rho * w * h * 9.81 * g_level / (kn * w)
    assert -m.point_motion("tip")[1] == pytest.approx(static, rel=1e-3)
    assert abs(m.point_motion("tip")[3]) * m.dt < 1e-4 * static    # at rest


def _hanging_block(n, adaptive):
    kn, h, w, rho, g_level = 1e10, 0.1, 0.1, 2500.0, 10.0
    m = Model(brick_grid(1, 2, w, h), {"flaw:*": Material(kn=kn, ks=kn, breakable=False)},
              density=rho, damping=0.0, kinetic_damping=n, kinetic_adaptive=adaptive)
    m.fix("top")
    m.add_history_point("tip", (0.05, 0.0))
    m.set_gravity(g_level)
    m.cycle(2000)
    static = rho * w * h * 9.81 * g_level / (kn * w)
    period = 2.0 * np.pi * np.sqrt(rho * w * h / (kn * w)) / m.dt      # steps
    return m, -m.point_motion("tip")[1] / static - 1.0, period


def test_checks_too_sparse_for_the_motion_are_made_denser():
    """Checked every 20 steps, the hanging block's bounce (a period of 25 steps: the kinetic
    energy peaks every 12.5) is stopped after its peak every time; the stops take little out
    and it still rings after 2,000 steps. A late stop halves the interval, and the block
    comes to rest at the spring's static extension to round-off."""
    fixed, err_fixed, period = _hanging_block(20, adaptive=False)
    assert 20 > period / 4
    stops = fixed.kinetic_stops()
    assert stops["stops"] > 10 and stops["late"] == stops["stops"] and stops["every"] == 20
    assert abs(err_fixed) > 1e-5
    adaptive, err, _ = _hanging_block(20, adaptive=True)
    assert abs(err) < 1e-9 and adaptive.unbalanced_ratio() < 1e-10
    assert adaptive.kinetic_stops()["every"] < period / 4
    adaptive.restart_kinetic_interval()        # what every solve does first: sparse again
    assert adaptive.kinetic_stops()["every"] == 20


def _tip_history(model, chunk, n_chunks):
    out = []
    for _ in range(n_chunks):
        model.cycle(chunk)
        out.append(-model.point_motion("tip")[1])
    return np.array(out)


def _steps_to_settle(history, chunk, final, rel=0.01):
    """Steps after which the history stays within ``rel`` of ``final``."""
    off = np.abs(history / final - 1) > rel
    return chunk * (int(np.flatnonzero(off)[-1]) + 2 if off.any() else 1)


def _cantilever(**options):
    length, height = 0.3, 0.03
    m = Model(voronoi_bar(length, height, edge=0.005, seed=3), materials(1.0), density=2500.0,
              **options)
    m.remove("right")
    m.fix("left")
    m.set_gravity(1.0)
    m.add_history_point("tip", (length, 0.5 * height))
    return m


def test_kinetic_damping_finds_the_cantilever_static_deflection_sooner():
    local = _cantilever(damping=0.8)
    result = local.solve(ratio=1e-5, max_steps=80_000)
    assert result.verdict == "equilibrium"
    static = -local.point_motion("tip")[1]
    chunk = 500
    kinetic = _tip_history(_cantilever(damping=0.0, kinetic_damping=20), chunk, 40)
    assert kinetic[-1] == pytest.approx(static, rel=0.01)
    damped = _tip_history(_cantilever(damping=0.8), chunk, 40)
    assert _steps_to_settle(kinetic, chunk, static) < _steps_to_settle(damped, chunk, static)


def test_kinetic_damping_survives_save_and_load(tmp_path):
    m = _cantilever(damping=0.0, kinetic_damping=20)
    m.cycle(300)
    m.save(tmp_path / "m.npz")
    again = Model.load(tmp_path / "m.npz")
    assert again.kinetic_damping == 20
    m.cycle(300)
    again.cycle(300)
    assert np.array_equal(m.state.pos, again.state.pos)


@pytest.mark.parametrize("bad", [-1, 2.5, "yes"])
def test_bad_kinetic_damping_is_refused(bad):
    with pytest.raises(ValueError, match="kinetic_damping"):
        _cantilever(kinetic_damping=bad)


def test_a_kinetic_damping_stop_is_a_turning_point_of_the_restarted_motion():
    """After a stop the block restarts from rest where it stands, as leapfrog starts from rest
    (half a velocity update first): the stopped offset from equilibrium is the amplitude of
    the motion that follows. A plain v = 0 restart puts the turning point half a step earlier
    and the amplitude becomes offset / cos(omega dt / 2): a gain that compounded, stop after
    stop, into a growing rattle of glued blocks (the Longtan conventional run)."""
    kn, h, w, rho = 1e10, 0.1, 0.1, 2500.0
    bs = brick_grid(1, 2, w, h)
    m = Model(bs, {"flaw:*": Material(kn=kn, ks=kn, breakable=False)}, density=rho,
              damping=0.0, kinetic_damping=7)
    m.fix("top")
    m.add_history_point("tip", (0.05, 0.0))
    m.set_gravity(10.0)
    static = rho * w * h * 9.81 * 10.0 / (kn * w)
    for _ in range(200):                 # step until the first stop: the block is at rest
        m.cycle(1)
        if m.step > 7 and m.point_motion("tip")[3] == 0.0:
            break
    else:
        pytest.fail("kinetic damping never stopped the motion")
    offset = abs(-m.point_motion("tip")[1] - static)
    assert offset > 1e-3 * static        # stopped off equilibrium: the test has a swing to see
    m.set_options(kinetic_damping=0)               # watch the free motion after the stop
    omega = np.sqrt(kn * w / (rho * w * h))
    swing = []
    for _ in range(int(2 * np.pi / omega / m.dt) + 2):
        m.cycle(1)
        swing.append(abs(-m.point_motion("tip")[1] - static))
    assert max(swing) <= offset * (1 + 1e-9)
    assert max(swing) > 0.99 * offset    # it does swing back to the other side
