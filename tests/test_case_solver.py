"""Every DEM case takes a ``solver`` setting: Model options over its scenes' for every run
(e.g. ``{"step_estimate": "eigen"}``), carried by each sweep member to the model it builds."""
import importlib

import pytest

from comparisons import staged
from comparisons.cli import custom_variant

STAGED = ["checkerboard", "coal_buckling", "common_toppling", "highwood", "lornex", "underdip"]
EIGEN = {"step_estimate": "eigen"}


@pytest.mark.parametrize("name", STAGED + ["adhikary", "longtan"])
def test_every_variant_has_a_solver_setting(name):
    """(the quick variants of adhikary, longtan, coal_buckling, highwood, lornex and underdip
    run on the eigen step, where it gives the same answers on the response judge,
    docs/comparisons.md; the full variants and the other quick ones on the scenes' own
    solver)"""
    case = importlib.import_module(f"comparisons.{name}")
    for key, v in case.VARIANTS.items():
        assert isinstance(v["solver"], dict)
        eigen = name not in ("checkerboard", "common_toppling") and key == "quick"
        assert v["solver"] == {} or (eigen and v["solver"].get("step_estimate") in
                                     ("eigen", "auto")), (key, v["solver"])


@pytest.mark.parametrize("name", STAGED)
def test_each_member_carries_the_variants_solver(name):
    case = importlib.import_module(f"comparisons.{name}")
    v = custom_variant(case, "quick", ['solver={"step_estimate": "eigen"}'])
    members = case.members(v, 1)
    assert members and all(m["solver"] == EIGEN for m in members)


class _Built(Exception):
    pass


def test_stage_run_builds_the_model_with_the_members_solver(monkeypatch):
    seen = {}

    def build(sc, **options):
        seen.update(options)
        raise _Built
    monkeypatch.setattr(staged, "build_model", build)
    with pytest.raises(_Built):
        staged.stage_run(None, {"label": "x", "params": {}, "solver": EIGEN})
    assert seen == {"threads": 1, **EIGEN}
    seen.clear()
    with pytest.raises(_Built):                      # the caller's own options win
        staged.stage_run(None, {"label": "x", "params": {}, "solver": EIGEN},
                         step_estimate="bound")
    assert seen["step_estimate"] == "bound"


@pytest.mark.parametrize("name", STAGED)
def test_each_member_carries_the_variants_settle(name):
    """(``settle``: every solve and search level that can stop early once settled does,
    ``staged.settled_stages``; off in every named variant)"""
    case = importlib.import_module(f"comparisons.{name}")
    assert all(v["settle"] is False for v in case.VARIANTS.values())
    members = case.members(custom_variant(case, "quick", ["settle=true"]), 1)
    assert members and all(m["settle"] is True for m in members)


@pytest.mark.parametrize("name", STAGED + ["adhikary", "longtan"])
def test_each_member_carries_the_variants_judge(name):
    """(``judge``: how every solve and search level is judged, ``SolveSettings.judge``;
    "response" in every named variant since 2026-11-30, ``--set judge=budget`` for the verdict
    at the step budget)"""
    case = importlib.import_module(f"comparisons.{name}")
    assert all(v["judge"] == "response" for v in case.VARIANTS.values())
    from comparisons import centrifuge
    build = getattr(case, "members", None) or getattr(case, "_members", None) or (
        centrifuge.ramp_members)
    assert all(m["judge"] == "response" for m in build(case.VARIANTS["quick"], 1))
    members = build(custom_variant(case, "quick", ["judge=budget"]), 1)
    assert members and all(m["judge"] == "budget" for m in members)


def test_a_bad_judge_is_named_before_any_run():
    from comparisons import underdip
    v = custom_variant(underdip, "quick", ["judge=respons"])
    with pytest.raises(ValueError, match="judge must be one of .*'respons'"):
        underdip.run(v)


def test_a_member_with_the_budget_judge_judges_every_stage_so():
    from comparisons import underdip
    member = underdip.members(custom_variant(underdip, "quick", ["judge=budget"]), 1)[0]
    sc = underdip.scene.scene(underdip.scene.UnderdipParams(**member["params"]),
                              underdip.stages(underdip.scene.UnderdipParams(**member["params"]),
                                              member["v"]))
    judged = staged.judged_stages(sc.stages, member["judge"])
    has = [st for st in judged if hasattr(st, "judge")]
    assert has and all(st.judge == "budget" for st in has)


def test_the_failure_note_says_what_the_judge_calls_failure():
    """The response judge's note names its verdicts and no step budget; the budget judge's
    keeps the case's own sentence; a failure displacement is named in both."""
    from comparisons.staged import judge_note
    response = judge_note("response", "no equilibrium within 40000 steps", 1.0)
    assert "'failing'" in response and "'undecided'" in response
    assert "40000" not in response and "more than 1.0 m" in response
    budget = judge_note("budget", "no equilibrium within 40000 steps", None)
    assert "40000 steps" in budget and "failing" not in budget
