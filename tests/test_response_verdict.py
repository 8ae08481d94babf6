"""The physics verdict of a solve (``judge="response"``, dem_core/workflow/response.py): a
block on a plane at 0.98 and 1.02 of its limit friction, a block sliding steadily at its limit,
an undecided level, and a stage list that stops where the model failed.

The verdict must not move with the cap: the same verdict at the same step with 1x, 2x and 4x
the default number of windows.
"""
import math
import sys
from pathlib import Path

import numpy as np
import pytest

from dem_core.contact.materials import Material
from dem_core.geometry.simple_blocks import from_polygons
from dem_core.model import Model
from dem_core.settings import SolveSettings
from dem_core.workflow.limit import search_failure
from dem_core.workflow.stages import ChangeMaterial, Excavate, Solve, StrengthSchedule, run_stages

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
from scenes import block_on_plane, tilt  # noqa: E402  (benchmarks/scenes.py)

THETA = 30.0                       # deg, the plane's dip (gravity tilted, base horizontal)
WINDOWS = SolveSettings().windows  # the default cap, in windows of N_r


def friction_at(factor):
    """The friction angle (deg) at which the block's limit is ``factor`` of the plane's:
    tan(phi) = tan(theta) / factor (factor < 1 stands, > 1 slides)."""
    return math.degrees(math.atan(math.tan(math.radians(THETA)) / factor))


def plane(factor, damping=0.8):
    m = block_on_plane(friction_at(factor))
    m.set_options(damping=damping)
    tilt(m, THETA)
    return m


@pytest.mark.parametrize("factor, expected", [(0.98, "equilibrium"), (1.02, "failing")])
def test_block_on_a_plane_gets_the_same_verdict_with_1x_2x_4x_the_cap(factor, expected):
    results = [plane(factor).solve(judge="response", windows=WINDOWS * x) for x in (1, 2, 4)]
    assert [r.verdict for r in results] == [expected] * 3
    assert len({r.steps for r in results}) == 1          # decided at the same step
    assert len({r.response_steps for r in results}) == 1
    if expected == "failing":
        # the block really slides: g (sin - cos tan phi) times (1 - damping) drives it
        assert results[0].max_displacement > 0.0 and "mechanism" in results[0].reason


@pytest.mark.parametrize("factor, expected", [(0.98, "equilibrium"), (1.02, "failing")])
def test_a_watched_point_gets_the_blocks_verdict(factor, expected):
    """A watched point at rest drifts by round-off only; it must not read as a mechanism
    (a creep of 0 did), and a sliding one must."""
    m = plane(factor)
    m.add_history_point("top", (2.5, 1.4))
    assert m.solve(judge="response", watch=("top",)).verdict == expected


@pytest.mark.parametrize("factor, expected", [(0.98, "equilibrium"), (1.02, "failing")])
def test_the_verdict_does_not_change_with_density_scaling(factor, expected):
    """Mass scaling (every block's inertia scaled to one critical step) changes the path to
    the answer, not the verdict."""
    m = block_on_plane(friction_at(factor), mass_scaling=True)
    m.set_options(damping=0.8)
    tilt(m, THETA)
    scaled = m.solve(judge="response")
    assert scaled.verdict == plane(factor).solve(judge="response").verdict == expected


@pytest.mark.parametrize("speed, expected", [(0.1, "failing"), (2e-4, "equilibrium")])
def test_steady_slide_at_the_limit_same_verdict_at_1x_and_2x(speed, expected):
    """At exactly its limit friction a block given a speed slides on at that speed: no
    unbalanced force (the ratio test alone calls it equilibrium), but a mechanism when it
    moves more than ``creep`` per response time; below that, creep that is not movement."""
    out = []
    for x in (1, 2):
        m = plane(1.0)
        m.state.vel[1] = (speed, 0.0)
        out.append(m.solve(judge="response", windows=WINDOWS * x, creep=2e-3))
    assert [r.verdict for r in out] == [expected] * 2
    assert out[0].steps == out[1].steps


def test_response_time_is_measured_without_changing_the_model():
    m = plane(0.98)
    m.cycle(100)
    before = m.snapshot()
    n_r = m.measure_response()
    assert n_r > 0 and m.response_steps == n_r
    for key in ("step", "time"):
        assert m.snapshot()[key] == before[key]
    assert np.array_equal(m.state.pos, before["state"].pos)
    assert np.array_equal(m.state.vel, before["state"].vel)
    assert np.array_equal(m.gravity, before["gravity"])


def test_response_steps_is_saved_and_cleared_by_an_excavation(tmp_path):
    m = toe_held_block()
    n_r = m.measure_response()
    m.save(tmp_path / "m.npz")
    assert Model.load(tmp_path / "m.npz").response_steps == n_r
    m.remove("toe")
    assert m.response_steps is None


@pytest.mark.parametrize("bad", [dict(judge="physics"), dict(windows=1),
                                 dict(response_steps=0), dict(response_steps=2.5)])
def test_bad_judge_settings_are_refused_by_name(bad):
    with pytest.raises(ValueError, match=next(iter(bad))):
        plane(0.98).solve(**bad)


def test_an_undecided_level_is_reported_undecided_and_ends_the_search():
    """Two windows cannot show a mechanism (it needs three), so a block that slides is
    undecided at windows=2: the search stops there with no failure level, and never counts
    the level as standing."""
    m = plane(0.9)
    values = [friction_at(f) for f in (0.95, 1.05, 1.2)]
    rec = search_failure(m, values, lambda mm, a, b: mm.set_material("joint:*", friction=b),
                         judge="response", windows=2, start=friction_at(0.9))
    assert rec.verdict[0] == "equilibrium"
    assert rec.verdict[1:] == ["undecided"]
    assert rec.undecided_level == values[1] and rec.failure_level is None
    assert rec.last_stable_level == values[0]
    assert not rec.resumable()
    st = StrengthSchedule("joint:*", "friction", tuple(values), judge="response", windows=2)
    records = run_stages(plane(0.9), [st, ChangeMaterial("joint:*", {"friction": 40.0})])
    assert [r.verdict for r in records] == ["undecided"]
    assert "undecided" in records[0].detail["stopped"]
    assert "stage 1 not run" in records[0].detail["stopped"]


def toe_held_block():
    """A block on a plane below its limit friction, held by a toe block downslope."""
    bs = from_polygons([[(0, 0), (20, 0), (20, 1), (0, 1)],
                        [(2, 1), (3, 1), (3, 1.5), (2, 1.5)],
                        [(3, 1), (3.5, 1), (3.5, 1.5), (3, 1.5)]],
                       edge_material="joint:base", groups={"base": [0], "block": [1],
                                                           "toe": [2]})
    m = Model(bs, {"joint:*": Material(kn=1e9, ks=1e9, friction=friction_at(1.05))},
              density=2000, damping=0.8)
    m.fix("base")
    m.fix("toe")
    tilt(m, THETA)
    return m


def test_a_stage_list_whose_excavation_fails_stops_there_and_says_so():
    stages = [Solve(judge="response"), Excavate("toe"), Solve(judge="response"),
              ChangeMaterial("joint:*", {"friction": 45.0}), Solve(judge="response")]
    records = run_stages(toe_held_block(), stages)
    assert [r.verdict for r in records] == ["equilibrium", "removed", "failing"]
    note = records[-1].detail["stopped"]
    assert "stage 2 (solve) ended failing" in note and "stages 3..4 not run" in note
    assert "blocks 1 (" in note                      # the block that slid moved most
    ran_on = run_stages(toe_held_block(), stages, after_failure="continue")
    assert [r.verdict for r in ran_on] == ["equilibrium", "removed", "failing", "changed",
                                           "equilibrium"]


def test_an_excavation_keeps_the_response_time_of_a_model_in_motion(tmp_path):
    """A mechanism under way has no response time to measure (on the Lornex slope the
    measurement stops at its cap), so an excavation after a solve that did not end at rest
    keeps N_r; after one that came to rest it clears it (a new structure)."""
    m = toe_held_block()
    assert m.solve(judge="response").verdict == "equilibrium" and not m.in_motion
    m.remove("toe")
    assert m.response_steps is None
    assert m.solve(judge="response").verdict == "failing" and m.in_motion
    n_r = m.response_steps
    m.save(tmp_path / "moving.npz")
    again = Model.load(tmp_path / "moving.npz")
    assert again.in_motion and again.response_steps == n_r
    m.remove("block")
    assert m.response_steps == n_r


def test_a_liner_over_an_opening_is_judged_by_its_own_nodes():
    """The blocks are all held, so only the liner's nodes move: judged on the blocks alone the
    solve read "at rest" in its second window with the liner barely sagged."""
    from test_support import G, liner_over_opening
    m = liner_over_opening()
    res = m.solve(ratio=1e-6, judge="response")
    assert res.verdict == "equilibrium"
    ln = m.liners
    q, ei, span = 2500.0 * G * 0.1, 30e9 * 0.1 ** 3 / 12, 4.0
    mid = np.argmin(np.abs(ln.node_pos[:, 0] - 4.0))
    assert 1.0 - ln.node_pos[mid, 1] == pytest.approx(q * span ** 4 / (384 * ei), rel=0.05)


def test_a_bolted_block_below_its_limit_is_at_rest():
    from test_support import bolted_block, limit_pull
    m = bolted_block(0.98 * limit_pull())
    res = m.solve(ratio=1e-6, failure_displacement=0.005, judge="response")
    assert res.verdict == "equilibrium"


def test_a_block_pulled_past_its_bolted_limit_is_failing_under_the_response_judge():
    """The yielding bolt lets the block slide at a near-constant 6e-5 m per N_r, below the
    creep of 2 mm per N_r, with the ratio steady at 3e-3: slowing movement without a decaying
    ratio is not rest (``RATIO_FALL``); it slides on past its 5 mm failure displacement."""
    from test_support import bolted_block, limit_pull
    m = bolted_block(1.02 * limit_pull())
    res = m.solve(ratio=1e-6, failure_displacement=0.005, judge="response")
    assert res.verdict == "failing"


@pytest.mark.parametrize("factor", [1, 2])
def test_a_slow_mechanism_without_a_failure_displacement_is_failing_at_the_same_step(factor):
    """Past its yielding bolt the block slides at 2-4 % of creep with the ratio at 2-3e-3,
    slowing by about a tenth a window: neither rest nor a mechanism above creep; without a
    failure displacement it was "undecided" at 20 windows and "standing still" (a ratio of
    9e-4) at 40. The slow-mechanism test on three windows of ``LONGEST`` N_r calls it
    failing, at the same step whatever the cap."""
    from dem_core.workflow.response import LONGEST
    from test_support import bolted_block, limit_pull
    m = bolted_block(1.02 * limit_pull())
    res = m.solve(ratio=1e-6, judge="response", windows=factor * WINDOWS)
    assert res.verdict == "failing" and res.reason.startswith("a slow mechanism"), res.reason
    assert res.steps == 73 * res.response_steps            # window 13: 3 + 2 + 4 + 8 x 8 N_r
    assert f"({LONGEST:g}, {LONGEST:g} and {LONGEST:g} N_r" in res.reason


def test_a_slow_motion_is_judged_on_the_longest_windows_only():
    """The same three windows below creep keep their speed and ratio: on windows of N_r a
    slow motion is not yet judged; on three windows of ``LONGEST`` N_r it is a mechanism;
    one at most ``STILL`` of creep is standing still, not a mechanism."""
    from dem_core.workflow.response import LONGEST, STILL, _window_verdict
    creep, n_r = 1e-3, 100
    before = [(0.5 * creep, 0.5 * creep, 1e-3)] * 2
    now = (0.5 * creep, 0.5 * creep, 1e-3)
    assert _window_verdict(6, now, 1, before, creep, n_r, "a block", [n_r] * 6, False) is None
    longest = [n_r] * 3 + [LONGEST * n_r] * 3
    verdict, reason = _window_verdict(6, now, 1, before, creep, n_r, "a block", longest, False)
    assert verdict == "failing" and reason.startswith("a slow mechanism")
    still = [(0.5 * STILL * creep, 0.5 * STILL * creep, 1e-3)] * 3
    assert _window_verdict(6, still[0], 0, still[:2], creep, n_r, "a block", longest,
                           False)[0] == "equilibrium"


def test_a_block_pulled_past_a_cables_capacity_is_failing_under_the_response_judge():
    """Read as at rest at window 2 before the ratio had to decay (docs/history.md)."""
    from test_support import pulled_cable, two_blocks
    m = pulled_cable(two_blocks(), yield_tension=5e4, rupture_strain=0.02)
    m.apply_load("block", fx=6e4)                 # more than the cable can hold
    res = m.solve(ratio=1e-6, failure_displacement=0.05, judge="response")
    assert res.verdict == "failing"


def test_rest_by_movement_needs_a_decaying_ratio():
    """The ratio's second half of checks against its first: a halving is decay, a steady or
    rising ratio is not (the slow slide past a yielding bolt: 3e-3 throughout)."""
    from dem_core.workflow.response import RATIO_FALL, _ratio_falls
    decaying = [1e-2 * math.exp(-0.3 * i) for i in range(9)]      # falls e^-1.35 per half
    assert _ratio_falls(decaying)
    assert not _ratio_falls([3e-3, 2.9e-3, 3.1e-3, 3e-3, 3.05e-3, 2.95e-3, 3e-3, 3e-3])
    assert not _ratio_falls([1e-4] * 4 + [RATIO_FALL * 1e-4 * 1.01] * 4)
    assert _ratio_falls([1e-4] * 4 + [RATIO_FALL * 1e-4] * 4)


def test_a_window_grows_only_after_one_that_slowed():
    """N_r for the first three windows; then twice the window before (up to LONGEST N_r)
    after a window slower than the one before it, else as long as that one."""
    from dem_core.workflow.response import LONGEST, next_span
    slowing, speeding = [(0, 2.0, 0), (0, 1.0, 0)], [(0, 1.0, 0), (0, 2.0, 0)]
    assert next_span(3, 100, 100, slowing) == 100               # the even windows
    assert next_span(4, 100, 100, slowing) == 200
    assert next_span(4, 100, 400, speeding) == 400              # never shorter
    assert next_span(9, 100, 800, slowing) == LONGEST * 100
    # a mechanism waiting to be seen again: growing whatever the speeds
    assert next_span(4, 100, 100, speeding, confirming=True) == 200


def test_joint_slip_that_settles_over_many_response_times_is_not_a_mechanism():
    """Common toppling's quick slope (3 m flaws, 6 m layers, friction 50) after its 12 lifts
    are removed together settles by joint slip over about 36 N_r: run on the budget judge
    with 320,000 steps it reaches a ratio of 1e-5 at 68,600 steps, the crest 0.18 m out
    (benchmarks/trials/long_budget_check.py). Over equal windows of N_r the response judge
    called it "failing" at window 10 (1 cm a window, not slowing by a fifth); the growing
    windows see it come to rest, at the same step with 1x and 2x the cap. (Measured on end
    springs; the scene's edge elements since 2026-12-01 come to rest too.)"""
    from comparisons import common_toppling as case
    from comparisons.cli import custom_variant
    from comparisons.scenes import common_toppling as scene
    from dem_core.workflow.scene import build_model
    v = custom_variant(case, "quick", [])
    member = next(m for m in case.members(v, 1) if m["label"] == "6 m, friction 50")
    p = scene.ToppleParams(**member["params"])
    lifts = case.strength_stages(p, member["v"])[:14]     # gravity, solve, the 12 lifts
    out = []
    for x in (1, 2):
        model = build_model(scene.scene(p, lifts), threads=1)
        run_stages(model, lifts)
        out.append(model.solve(judge="response", windows=WINDOWS * x))
    assert [r.verdict for r in out] == ["equilibrium"] * 2, [r.reason for r in out]
    assert out[0].steps == out[1].steps > 3 * out[0].response_steps


def _still_and_sliding():
    """Block A on a flat fixed slab, block B on a fixed 45-degree face with friction 30
    degrees: A stands, B slides away at a = g (sin 45 - cos 45 tan 30) for good, keeping the
    unbalanced ratio up."""
    d, n = np.array([1.0, 1.0]) / math.sqrt(2), np.array([-1.0, 1.0]) / math.sqrt(2)
    p = np.array([12.0, 0.0]) + 8.0 * d
    bs = from_polygons([[(0, 0), (10, 0), (10, 1), (0, 1)], [(12, 0), (22, 0), (22, 10)],
                        [(2, 1), (3, 1), (3, 2), (2, 2)], [p, p + d, p + d + n, p + n]],
                       edge_material="joint:base",
                       groups={"base": [0, 1], "A": [2], "B": [3]})
    m = Model(bs, {"joint:*": Material(kn=1e9, ks=1e9, friction=30.0)}, density=2000,
              damping=0.8)
    m.fix("base")
    m.set_gravity(1.0)
    m.add_history_point("A", (2.5, 1.5))
    return m


@pytest.mark.parametrize("factor", [1, 2])
def test_a_watched_point_standing_still_is_at_rest_while_an_unwatched_block_slides(factor):
    """The ratio never falls (block B accelerates down its face), so neither rest by the ratio
    nor by a decaying movement can be granted; the watched point on A moves by round-off
    only: two windows at most ``STILL`` of creep are at rest (``response.STILL``), at the
    same window whatever the cap. Judging every block instead, B's slide is a mechanism."""
    m = _still_and_sliding()
    res = m.solve(judge="response", watch=("A",), windows=factor * WINDOWS)
    assert res.verdict == "equilibrium" and res.reason.startswith("standing still")
    assert res.steps == 2 * res.response_steps           # at the end of window 2
    m = _still_and_sliding()
    assert m.solve(judge="response", windows=factor * WINDOWS).verdict == "failing"
