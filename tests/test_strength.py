"""Strength searches (factor of safety, strength schedule), the displacement stage and staged
excavation, against closed forms; bad input refused before compute."""
import json
import math

import numpy as np
import pytest

from dem_core.geometry import GeometrySpec, rectangle
from dem_core.contact.materials import Material
from dem_core.model import Model
from dem_core.workflow.scene import Boundary, Scene, build_model
from dem_core.geometry.simple_blocks import brick_grid
from dem_core.workflow.stages import (Cycle, Displace, Excavate, FactorOfSafety, Gravity, Solve,
                             StrengthSchedule, run_stages, stage_table)
from dem_core.workflow.strength import reduced_strength

G = 9.81
THETA = 30.0


def block_on_plane(cohesion, phi):
    """A 1 x 0.5 m block (2,000 kg/m^3) on a fixed base, gravity tilted by THETA so the block
    is pushed along x. The interface keeps its cohesion when it slips (residual = peak): the
    rigid-plastic joint the limit-equilibrium formula assumes (with the thesis's residual c = 0
    the less loaded end of the base fails first and the block goes early)."""
    geo = GeometrySpec([rectangle("base", 0, 0, 20, 1), rectangle("block", 2, 1, 3, 1.5)])
    mat = Material(kn=1e9, ks=1e9, cohesion=cohesion, residual_cohesion=cohesion, friction=phi)
    th = math.radians(THETA)
    return Scene(geo, {"*": mat}, density=2000.0, boundaries=[Boundary("base")],
                 points={"block": (2.5, 1.25)},
                 stages=[Gravity(1.0, direction=(math.sin(th), -math.cos(th))),
                         Solve(ratio=1e-6, max_steps=50_000)],
                 solver={"damping": 0.8})


@pytest.mark.parametrize("cohesion, phi", [(0.0, 40.0), (3000.0, 20.0)])
def test_factor_of_safety_of_a_block_on_a_plane_matches_the_closed_form(cohesion, phi):
    sc = block_on_plane(cohesion, phi)
    m = build_model(sc)
    weight = 2000.0 * G * 0.5                                 # N/m
    th = math.radians(THETA)
    closed = (cohesion * 1.0 + weight * math.cos(th) * math.tan(math.radians(phi))) / (
        weight * math.sin(th))
    fos = FactorOfSafety(("*",), f_levels=(1.0, 1.2, 1.4, 1.6, 2.0), refine_to=0.01,
                         failure_displacement=0.01)
    rec = run_stages(m, [*sc.stages, fos])[-1]
    f, first = rec.detail["factor_of_safety"], rec.detail["first_failed"]
    assert rec.verdict == "failed" and first - f <= 0.01 + 1e-9
    assert f == pytest.approx(closed, rel=0.02), (f, first, closed)


def test_reduced_strength_divides_c_and_tan_phi():
    mat = Material(kn=1e9, ks=1e9, tensile_strength=2e5, cohesion=1e5, friction=35.0,
                   residual_friction=25.0)
    r = reduced_strength(mat, 2.0)
    assert r["cohesion"] == 5e4 and "tensile_strength" not in r
    assert math.tan(math.radians(r["friction"])) == pytest.approx(math.tan(math.radians(35)) / 2)
    assert math.tan(math.radians(r["residual_friction"])) == pytest.approx(
        math.tan(math.radians(25)) / 2)
    assert reduced_strength(mat, 4.0, tension=True)["tensile_strength"] == 5e4


def hanging_block():
    """A 0.1 m block hangs from a fixed one by a bonded edge: the bond carries rho h g."""
    bs = brick_grid(1, 2, 0.1, 0.1)
    mat = Material(kn=1e10, ks=1e10, tensile_strength=2e4, cohesion=1e6, friction=30)
    m = Model(bs, {"flaw:*": mat}, density=2500.0, damping=0.8)
    m.fix("top")
    run_stages(m, [Gravity(1.0), Solve(ratio=1e-6, max_steps=100_000)])
    return m


def test_a_strength_schedule_finds_the_tensile_strength_at_which_a_bond_lets_go():
    m = hanging_block()
    stress = 2500.0 * 0.1 * G                                 # 2,452 Pa on the bond
    sched = StrengthSchedule("flaw:*", "tensile_strength", (8000.0, 5000.0, 3000.0, 2000.0),
                             refine_to=25.0, failure_displacement=0.005)
    rec = run_stages(m, [sched])[-1]
    d = rec.detail
    assert rec.verdict == "failed" and d["values"][:4] == [8000.0, 5000.0, 3000.0, 2000.0]
    assert d["failure_value"] < stress < d["last_stable_value"]
    assert d["last_stable_value"] - d["failure_value"] <= 25.0 + 1e-9
    assert m.crack_counts()["tension"] > 0


def test_displace_moves_a_group_the_distance_then_lets_it_go():
    bs = brick_grid(3, 1, 0.1, 0.1)
    mat = Material(kn=1e10, ks=1e10, tensile_strength=1e9, cohesion=1e9, friction=30)
    m = Model(bs, {"flaw:*": mat}, density=2500.0, damping=0.8)
    m.fix("left")
    rec = run_stages(m, [Displace("right", 2e-5, direction=(1.0, 0.0), rate=1e-8)])[-1]
    assert rec.verdict == "displaced"
    assert rec.detail["displacement"] == pytest.approx(2e-5, rel=0.01)
    right = m.group("right")
    assert np.all(m.props.fixity[right] == 0)                 # released
    m.cycle(20_000)                                            # the elastic bar springs back
    assert np.abs(m.displacement()[right, 0]).max() < 1e-6


def test_staged_excavation_records_each_stage_and_refuses_a_group_twice():
    # a row of three blocks on a base; remove the outer ones: the middle one stays put
    geo = GeometrySpec([rectangle("base", 0, 0, 3, 1), rectangle("a", 0, 1, 1, 2),
                        rectangle("b", 1, 1, 2, 2), rectangle("c", 2, 1, 3, 2)])
    mat = Material(kn=1e9, ks=1e9, friction=35.0)
    sc = Scene(geo, {"*": mat}, density=2500.0, boundaries=[Boundary("base")],
               points={"b": (1.5, 1.5)},
               stages=[Gravity(1.0), Solve(ratio=1e-6, max_steps=100_000), Excavate("a"),
                       Solve(ratio=1e-6, max_steps=100_000), Excavate("c"),
                       Solve(ratio=1e-6, max_steps=100_000)])
    m = build_model(sc)
    recs = run_stages(m, sc.stages)
    assert [r.verdict for r in recs[1::2]] == ["equilibrium"] * 3
    assert recs[2].detail["blocks"] == 1
    table = stage_table(recs)
    assert table.count("\n") == len(recs) + 1 and "| 4 | excavate | removed |" in table
    assert abs(recs[-1].points["b"][0]) < 1e-6                # nothing pushes b sideways
    with pytest.raises(ValueError, match="has no blocks left"):
        run_stages(m, [Excavate("a")])
    with pytest.raises(ValueError, match="already excavated by stage 0"):
        run_stages(build_model(sc), [Excavate("a"), Cycle(10), Excavate("a")])


@pytest.mark.parametrize("stage, words", [
    (dict(kind="strength_schedule", material="*", property="cohesion",
          values=[5e3, 1e4]), "must lower cohesion"),
    (dict(kind="strength_schedule", material="*", property="cohesion", values=[1e5]),
     "must lower cohesion"),
    (dict(kind="strength_schedule", material="*", property="kn", values=[1e5]), "property"),
    (dict(kind="strength_schedule", material="rock", property="cohesion", values=[1e3]),
     "unknown material 'rock'"),
    (dict(kind="factor_of_safety", materials=["*"], f_levels=[1.5, 1.2]), "f_levels"),
    (dict(kind="factor_of_safety", materials=["joint"]), "unknown material 'joint'"),
    (dict(kind="excavate", group="nowhere"), "unknown group 'nowhere'"),
    (dict(kind="displace", group="block", displacement=-1.0), "displacement"),
])
def test_bad_searches_are_refused_naming_the_item(tmp_path, stage, words):
    d = block_on_plane(3000.0, 20.0).to_dict()
    d["stages"] = [stage]
    (tmp_path / "bad.json").write_text(json.dumps(d))
    with pytest.raises(ValueError, match=words):
        Scene.load(tmp_path / "bad.json")


def test_a_search_stage_survives_the_file():
    sc = block_on_plane(3000.0, 20.0)
    sc2 = Scene.from_dict(json.loads(json.dumps(
        {**sc.to_dict(), "stages": [{"kind": "factor_of_safety", "materials": ["*"],
                                     "f_levels": [1.0, 1.5], "tension": True}]})))
    assert sc2.stages[0] == FactorOfSafety(("*",), f_levels=(1.0, 1.5), tension=True)
