"""Early settling of a quasi-static level (``settle``; dem_core.output.monitor.settled): a level that
has stopped moving and cracking ends as "settled" instead of running to its step limit, and the
search's answer does not move."""
import dataclasses
import math

import pytest

from comparisons.staged import settled_stages, stage_run
from dem_core.output.monitor import settled
from dem_core.workflow.scene import build_model
from dem_core.workflow.stages import Solve, run_stages
from dem_core.workflow.strength import FactorOfSafety
from test_strength import THETA, block_on_plane

STEPS = [0, 100, 200, 300, 400, 500]
QUIET = [0.0, 1e-4, 1.5e-4, 1.6e-4, 1.61e-4, 1.612e-4]     # m: moved, then (nearly) still


def test_a_still_uncracking_run_is_settled_after_two_windows():
    assert settled(STEPS, QUIET, [0] * 6, window=200, creep=2e-4)


def test_a_new_crack_in_the_last_two_windows_holds_it_back():
    assert not settled(STEPS, QUIET, [0, 0, 1, 1, 1, 1], window=200, creep=2e-4)


def test_movement_above_half_the_creep_over_the_last_window_holds_it_back():
    moving = [0.0, 1e-4, 2e-4, 3e-4, 4e-4, 5e-4]              # 2e-4 m per 200 steps
    assert not settled(STEPS, moving, [0] * 6, window=200, creep=2e-4)


def test_a_steady_creep_below_the_rates_is_not_settled():
    """0.8e-4 m per window, under half the creep over the last window and under the creep over
    the one before, but not slowing down: it may creep on without end (a level of the Longtan
    8 mm ramp settled so and the ramp ended 6 g above the answer of twice the step budget)."""
    steady = [0.0, 0.4e-4, 0.8e-4, 1.2e-4, 1.6e-4, 2.0e-4]
    assert not settled(STEPS, steady, [0] * 6, window=200, creep=2e-4)
    halving = [0.0, 0.4e-4, 0.8e-4, 1.1e-4, 1.15e-4, 1.24e-4]   # 0.7e-4, then 0.14e-4
    assert settled(STEPS, halving, [0] * 6, window=200, creep=2e-4)


def test_a_run_shorter_than_two_windows_is_not_judged():
    assert not settled(STEPS[:4], QUIET[:4], [0] * 4, window=200, creep=2e-4)


def _factor_of_safety(settle, **solver):
    """The block on a 30 degree plane (c = 0, phi = 40: F = tan 40 / tan 30 = 1.453) with a
    force ratio no level reaches (1e-13), so every stable level runs to its step limit unless
    it settles."""
    sc = block_on_plane(0.0, 40.0)
    m = build_model(sc, **solver)
    fos = FactorOfSafety(("*",), f_levels=(1.0, 1.2, 1.4, 1.6), refine_to=0.02, ratio=1e-13,
                         max_steps=10_000, failure_displacement=0.01, creep=1e-5,
                         settle=settle)
    return run_stages(m, [*sc.stages, fos])[-1]


def test_settling_gives_the_same_factor_of_safety_in_fewer_steps():
    today, early = _factor_of_safety(False), _factor_of_safety(True)
    closed = math.tan(math.radians(40.0)) / math.tan(math.radians(THETA))
    for rec in (today, early):
        assert rec.detail["factor_of_safety"] == pytest.approx(closed, abs=0.03)
    assert "settled" in early.detail["verdicts"] and "settled" not in today.detail["verdicts"]
    # a stable level settles after two windows of a tenth of its 10,000 steps at the soonest
    assert early.steps <= 0.5 * today.steps, (early.steps, today.steps)


def test_settling_on_the_eigen_step_gives_the_same_factor_of_safety():
    """The step from the largest eigenvalue (``step_estimate="eigen"``) is larger than the
    bounded one; the search's answer is the closed form's all the same."""
    assert build_model(block_on_plane(0.0, 40.0), step_estimate="eigen").dt > build_model(
        block_on_plane(0.0, 40.0)).dt
    rec = _factor_of_safety(True, step_estimate="eigen")
    closed = math.tan(math.radians(40.0)) / math.tan(math.radians(THETA))
    assert rec.detail["factor_of_safety"] == pytest.approx(closed, abs=0.03)


def test_a_solve_stage_that_settles_stops_before_its_step_limit():
    """The block at rest on the plane (F = 1.45) with a force ratio it never reaches: the solve
    runs all its 10,000 steps, and with ``settle`` stops once its displacement stops growing."""
    sc = block_on_plane(0.0, 40.0)
    today, early = (run_stages(build_model(sc), [sc.stages[0], Solve(
        ratio=1e-13, max_steps=10_000, settle=s)])[-1] for s in (False, True))
    assert today.steps == 10_000 and today.verdict != "settled"
    assert early.verdict == "settled" and early.steps <= 5_000
    assert early.points["block"][0] == pytest.approx(today.points["block"][0], abs=1e-4)


def test_a_member_that_settles_sets_settle_on_every_stage_that_has_it():
    sc = block_on_plane(0.0, 40.0)
    fos = FactorOfSafety(("*",), f_levels=(1.0, 1.2))
    out = settled_stages([*sc.stages, fos])
    assert out[0] == sc.stages[0]                                  # gravity: no such option
    assert out[1].settle and out[2].settle and not sc.stages[1].settle
    run = stage_run(dataclasses.replace(sc, stages=[sc.stages[0], Solve(
        ratio=1e-13, max_steps=10_000)]), {"label": "b", "params": {}, "settle": True})
    assert run["stages"][1]["verdict"] == "settled" and run["stages"][1]["steps"] <= 5_000
