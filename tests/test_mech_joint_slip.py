"""Layered columns: a frictionless joint lets the layers bend on their own (a leaf spring).

Two Voronoi columns side by side, clamped at the base and loaded across by gravity, separated
by a joint. With a frictionless joint each column bends as if alone, so the pair's tip
deflection equals one column's; with a glued joint they bend as one beam twice as wide, whose
deflection is a quarter of that (Euler-Bernoulli: deflection ~ 1 / width^3 per unit weight ~
1 / width^2). Where Voronoi flaw lines meet the joint from both sides (an X-crossing), a contact
between diagonal neighbours would lock the joint; this test fails if it does.
"""
import numpy as np
import pytest

from dem_core.geometry import GeometrySpec, JointSet, Region, Voronoi, build_block_system, rectangle
from dem_core.contact.materials import Material
from dem_core.model import Model

LENGTH, WIDTH, EDGE = 0.1, 0.01, 0.0035


def _tip_deflection(n_columns, joint):
    col = Region("rock", [(0, 0), (n_columns * WIDTH, 0), (n_columns * WIDTH, LENGTH),
                          (0, LENGTH)])
    base = rectangle("base", -0.01, -0.01, n_columns * WIDTH + 0.01, 0.0)
    joints = [JointSet("bed", 90.0, WIDTH, regions=["rock"])] if n_columns > 1 else []
    joint = joint or Material(kn=1e11, ks=1e11)
    bs = build_block_system(GeometrySpec([col, base], joint_sets=joints,
                                         voronoi={"rock": Voronoi(edge_length=EDGE, seed=3)}))
    rock = Material(kn=1e11, ks=1e11, tensile_strength=1e9, cohesion=1e9, friction=40)
    model = Model(bs, {"flaw:*": rock, "boundary:*": rock, "joint:*": joint}, density=2500.0,
                  mass_scaling=True)
    model.fix("base")
    model.add_history_point("tip", (0.5 * WIDTH, LENGTH - 0.001))
    model.set_gravity(200.0, direction=(1.0, 0.0))          # sideways: pure bending load
    result = model.solve(ratio=1e-6, max_steps=300_000)
    assert result.verdict == "equilibrium", result.reason
    return model.point_motion("tip")[0]


@pytest.mark.slow
def test_frictionless_joint_lets_layers_bend_alone_and_a_glued_one_makes_one_beam():
    single = _tip_deflection(1, None)
    free = _tip_deflection(2, Material(kn=1e11, ks=1e11, friction=0.0))
    glued = _tip_deflection(2, Material(kn=1e11, ks=1e11, breakable=False))
    assert single > 0
    assert free / single == pytest.approx(1.0, abs=0.2)
    assert glued / single == pytest.approx(0.25, abs=0.1)
