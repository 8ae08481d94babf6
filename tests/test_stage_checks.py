"""What a stage list needs of the built model is checked before its first step
(``stages.check_on_model``): a run does not compute its early stages and then stop on a
watched point that does not exist, an excavation of a group with no blocks, or a cable whose
collar is not in rock."""
import math

import pytest

from dem_core.components.support import Cable
from dem_core.contact.materials import Material
from dem_core.geometry import GeometrySpec
from dem_core.geometry.regions import rectangle
from dem_core.workflow.scene import Boundary, Scene, build_model
from dem_core.workflow.stages import Cycle, Excavate, Gravity, Solve, run_stages


def block_on_base(stages, groups=None):
    geo = GeometrySpec([rectangle("base", 0, 0, 4, 1), rectangle("block", 1, 1, 2, 1.5)])
    return Scene(geo, {"*": Material(kn=1e9, ks=1e9, friction=35.0)}, density=2500.0,
                 groups=groups or {}, boundaries=[Boundary("base")],
                 points={"top": (1.5, 1.4)}, stages=stages)


CABLE = dict(area=1e-4, E=2e11, yield_tension=1e5, grout_stiffness=1e9, grout_strength=1e6)


@pytest.mark.parametrize("late, groups, words", [
    (Solve(watch=("nowhere",)), None, r"stage 2 \(solve\): watch names no monitoring point "
                                     r"\['nowhere'\]; points are \['top'\]"),
    (Excavate("air"), {"air": {"inside": [[5, 5], [6, 5], [6, 6], [5, 6]]}},
     r"stage 2 \(excavate\): group 'air' has no blocks"),
    (Cable((8.0, 8.0), (9.0, 8.0), **CABLE), None,
     r"stage 2 \(cable\): the collar \(8.0, 8.0\) is not inside any active block"),
])
def test_a_stage_the_model_cannot_take_is_refused_before_the_first_step(late, groups, words):
    sc = block_on_base([Gravity(1.0), Cycle(500), late], groups)
    m = build_model(sc)
    with pytest.raises(ValueError, match=words):
        run_stages(m, sc.stages)
    assert m.step == 0                          # the stages before it did not run


def test_a_cable_in_rock_and_a_watched_point_pass_the_check():
    sc = block_on_base([Gravity(1.0), Cable((1.5, 1.4), (1.5, 0.5), **CABLE),
                        Solve(watch=("top",), max_steps=200)])
    records = run_stages(build_model(sc), sc.stages)
    assert [r.kind for r in records] == ["gravity", "cable", "solve"]
    assert math.isfinite(records[-1].points["top"][0])
