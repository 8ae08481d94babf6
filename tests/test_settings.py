"""The two settings records (``dem_core.settings``): one set of solve defaults carried by every
stage and search, options validated once and shared with the scene's solver keys, and the
time step as a function of the bundles (the driver's ``update_timestep`` is that function)."""
import dataclasses
import inspect

import pytest

from dem_core.contact.materials import Material
from dem_core.geometry.simple_blocks import brick_grid
from dem_core.model import Model
from dem_core.settings import SCENE_SOLVER_KEYS, SolverOptions, SolveSettings
from dem_core.step.timestep import choose_timestep
from dem_core.workflow import scene, stages, strength
from dem_core.workflow.gravity_ramp import raise_gravity
from dem_core.workflow.limit import search_failure

DEFAULTS = {f.name: f.default for f in dataclasses.fields(SolveSettings)}


@pytest.mark.parametrize("record", [stages.Solve, stages.RaiseGravity, strength.FactorOfSafety,
                                    strength.StrengthSchedule])
def test_every_stage_takes_the_one_set_of_solve_defaults(record):
    fields = {f.name: f.default for f in dataclasses.fields(record)}
    shared = {k: v for k, v in fields.items() if k in DEFAULTS}
    assert shared and shared == {k: DEFAULTS[k] for k in shared}


def test_the_searches_and_the_solve_default_to_the_same_settings():
    for fn in (search_failure, raise_gravity, Model.solve):
        assert inspect.signature(fn).parameters["settings"].default is None
    for name in DEFAULTS:           # no search or solve keeps a default of its own
        for fn in (search_failure, raise_gravity, Model.solve):
            assert name not in inspect.signature(fn).parameters


def test_the_judge_is_the_response_judge_unless_a_step_budget_is_given():
    """A solve with no judge and no budget is judged from the response time; one that names a
    budget keeps the budget judge (so calls and scene files written before the switch keep
    their verdicts); the budget judge alone gets the 20,000 steps it always had."""
    from dem_core.settings import BUDGET_STEPS
    assert SolveSettings().validated().judge == "response"
    assert SolveSettings().validated().max_steps is None
    st = SolveSettings(max_steps=5_000).validated()
    assert (st.judge, st.max_steps) == ("budget", 5_000)
    st = SolveSettings(judge="budget").validated()
    assert (st.judge, st.max_steps) == ("budget", BUDGET_STEPS) and BUDGET_STEPS == 20_000
    st = SolveSettings(judge="response", max_steps=5_000).validated()
    assert (st.judge, st.max_steps) == ("response", 5_000)      # not used by this judge
    assert stages.Solve().judge is None and SolveSettings.of(stages.Solve(max_steps=10)
                                                             ).validated().judge == "budget"


@pytest.mark.parametrize("bad, words", [
    (dict(ratio=0.0), "ratio must be > 0"),
    (dict(max_steps=0), "max_steps must be a whole number > 0"),
    (dict(max_steps=True), "max_steps must be a whole number > 0"),
    (dict(failure_displacement=-1.0), "failure_displacement must be > 0 m"),
    (dict(creep=-1e-3), "creep must be >= 0 m"),
    (dict(settle="no"), "settle must be true or false"),
])
def test_bad_solve_settings_are_refused_naming_the_value(bad, words):
    with pytest.raises(ValueError, match=words):
        SolveSettings(**bad).validated("stage 3 (solve)")
    with pytest.raises(ValueError, match=r"stage 0 \(solve\)"):
        stages.Solve(**bad).check(0, set(), {})


def test_an_unknown_setting_or_option_is_named():
    with pytest.raises(ValueError, match="unknown solve setting.*'ratoi'"):
        SolveSettings().replace(ratoi=1e-5)
    with pytest.raises(ValueError, match="unknown solver option.*'dampng'"):
        SolverOptions().replace(dampng=0.8)


def test_the_scene_takes_the_options_but_the_block_moduli():
    assert scene.SOLVER_KEYS == set(SCENE_SOLVER_KEYS)
    assert SCENE_SOLVER_KEYS == {f.name for f in dataclasses.fields(SolverOptions)} - {
        "block_E", "block_nu"}


def two_blocks(**options):
    bs = brick_grid(1, 2, 0.1, 0.1)
    m = Model(bs, {"flaw:*": Material(kn=1e9, ks=1e9, friction=30)}, density=2500.0, **options)
    m.fix("bottom")
    return m


def test_options_read_back_and_changed_through_set_options():
    m = two_blocks(damping=0.6, kinetic_damping=20)
    assert (m.damping, m.kinetic_damping, m.fixed_dt) == (0.6, 20, None)
    dt = m.dt
    m.set_options(damping=0.0)
    assert m.damping == 0.0 and m.dt == dt
    m.set_options(safety=0.25)
    assert m.dt == pytest.approx(0.5 * dt, rel=1e-12)
    with pytest.raises(ValueError, match="fixed when the model is built"):
        m.set_options(rounding=0.001)
    with pytest.raises(ValueError, match="damping must be in"):
        m.set_options(damping=1.0)
    with pytest.raises(AttributeError):
        m.damping = 0.5                         # read-only: set_options is the one way


def test_the_time_step_is_a_function_of_the_bundles():
    m = two_blocks()
    step = choose_timestep(m.world(), m.cables, m.liners, m.options, m.table, m.dt)
    assert (step.dt, step.critical_dt) == (m.dt, m.critical_dt)
    assert step.dt == pytest.approx(m.safety * step.critical_dt, rel=1e-15)
    fixed = choose_timestep(m.world(), m.cables, m.liners, m.options.replace(dt=1e-6),
                            m.table, m.dt)
    assert fixed.dt == 1e-6 and fixed.critical_dt == step.critical_dt
