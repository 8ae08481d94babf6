"""Loading paths as stages (dem_core.workflow.loading): a servo-held force and a displacement-controlled
load, on one rigid block on a fixed base (two blocks, one face-to-face contact of length 1 m):

- ``ServoLoad`` settles the block at the target stress, where the contact closes by
  stress / kn (the elastic closure of the contact);
- ``Load`` pressing the block records reaction = kn x displacement (the contact's elastic
  line) and stops at its maximum displacement;
- ``Load`` pulling a bonded block records the bond's tensile strength as its peak and stops
  once the bond has broken;
- the stages survive a scene file and bad ones are refused naming the item.
"""
import json

import numpy as np
import pytest

from dem_core.geometry import GeometrySpec, rectangle
from dem_core.workflow.loading import Load, ServoLoad
from dem_core.contact.materials import Material
from dem_core.workflow.scene import Boundary, Scene, build_model
from dem_core.workflow.stages import run_stages

KN, T = 1e10, 0.5e6


def block_on_base(stages, tensile=0.0):
    geo = GeometrySpec([rectangle("base", 0.0, -0.2, 1.0, 0.0),
                        rectangle("top", 0.0, 0.0, 1.0, 0.5)])
    mat = Material(kn=KN, ks=KN, tensile_strength=tensile, cohesion=1e6 if tensile else 0.0,
                   friction=30.0)
    return Scene(geo, {"*": mat}, density=2500.0, boundaries=[Boundary("base")],
                 stages=stages, solver={"mass_scaling": True, "damping": 0.8})


def test_a_servo_settles_the_block_at_the_target_stress():
    stress = 2e6
    sc = block_on_base([ServoLoad("top", stress, 1.0, (0.0, -1.0), v_max=1e-6)])
    m = build_model(sc)
    rec = run_stages(m, sc.stages)[0]
    assert rec.verdict == "settled"
    assert rec.detail["force"] == pytest.approx(stress, rel=0.02)
    # the contact closes by stress / kn
    assert rec.points == {} and m.displacement()[1, 1] == pytest.approx(-stress / KN, rel=0.03)


def test_pressing_a_block_follows_the_contacts_elastic_line():
    sc = block_on_base([Load("top", 2e-8, (0.0, -1.0), read_on=("top", "base"),
                             max_displacement=1e-5, chunk=50)])
    m = build_model(sc)
    rec = run_stages(m, sc.stages)[0]
    assert rec.verdict == "max displacement"
    d, r = rec.detail["displacement"], rec.detail["reaction"]
    assert d[-1] > 1e-5
    late = d > 0.2e-5             # past the start-up of the motion
    assert np.allclose(r[late], KN * d[late], rtol=0.02)


def test_pulling_a_bonded_block_peaks_at_the_bonds_tensile_strength():
    sc = block_on_base([Load("top", 2e-8, (0.0, 1.0), read_on=("top", "base"),
                             max_displacement=1e-3, post_peak=0.5, chunk=20)], tensile=T)
    m = build_model(sc)
    rec = run_stages(m, sc.stages)[0]
    assert rec.verdict == "peak passed"
    assert rec.detail["peak"] == pytest.approx(T, rel=0.02)
    assert m.crack_counts()["tension"] > 0


def test_loading_stages_survive_a_scene_file_and_bad_ones_are_refused(tmp_path):
    sc = block_on_base([ServoLoad("top", 1e6, 1.0), Load("top", 1e-8, gauge=("top", "base"))])
    sc.save(tmp_path / "s.json")
    assert Scene.load(tmp_path / "s.json").stages == sc.stages
    for bad, words in ((dict(kind="load", group="top", rate=-1.0), "rate"),
                       (dict(kind="load", group="top", rate=1e-8, read_on=["lid"]), "lid"),
                       (dict(kind="servo", group="top", stress=1e6, length=0.0), "length"),
                       (dict(kind="servo", group="top", stress=1e6, length=1.0,
                             direction=[0.0, 0.0]), "direction")):
        d = sc.to_dict()
        d["stages"] = [bad]
        (tmp_path / "bad.json").write_text(json.dumps(d))
        with pytest.raises(ValueError, match=words):
            Scene.load(tmp_path / "bad.json")
