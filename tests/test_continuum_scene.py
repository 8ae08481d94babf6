"""The continuum runs a scene file's stage list (``continuum_ref.scene_run``): a cut in two
lifts with a water table and a factor of safety, from the file alone, equals the same model
built by hand through ``ContinuumModel`` calls; a stage the continuum cannot run is refused
before anything is meshed; ``run-scene --method both`` writes one report with both columns."""
import json
import math

import numpy as np
import pytest

from dem_core.contact.materials import Material
from dem_core.geometry import GeometrySpec
from dem_core.geometry.regions import rectangle
from dem_core.workflow.scene import Boundary, Scene
from dem_core.workflow.stages import (Cycle, Excavate, FactorOfSafety, Gravity, Solve,
                                      WaterTable)

LENGTH, HEIGHT, CREST = 40.0, 20.0, 15.0       # m
ROCK = {"kind": "mohr_coulomb", "E": 1e9, "nu": 0.3, "cohesion": 25e3, "friction": 35.0}
TABLE = ((0.0, 15.0), (LENGTH, 8.0))            # water table, m


def _lift(y0, y1):
    """The part of the box right of a 60 deg face from the crest, between y0 and y1 (m)."""
    def x_face(y):
        return CREST + (HEIGHT - y) / math.tan(math.radians(60.0))
    return [(x_face(y0), y0), (LENGTH, y0), (LENGTH, y1), (x_face(y1), y1)]


def cut_scene(stages=None, continuum=True):
    """A 10 m cut (60 deg face) in two 5 m lifts, a water table, a factor of safety."""
    geo = GeometrySpec([rectangle("rock", 0, 0, LENGTH, HEIGHT)],
                       groups={"lift1": _lift(15.0, 20.0), "lift2": _lift(10.0, 15.0)})
    stages = stages if stages is not None else [
        Gravity(1.0), Solve(), Excavate("lift1"), Excavate("lift2"), WaterTable(TABLE),
        FactorOfSafety(("*",), f_levels=(1.0, 1.5, 2.0, 3.0), refine_to=0.02)]
    return Scene(geo, {"*": Material(kn=1e9, ks=1e9, friction=35.0)}, density=2000.0,
                 groups={"base": {"touching": "bottom"}, "left": {"touching": "left"},
                         "right": {"touching": "right"},
                         "sides": {"union": ["left", "right"]}},
                 boundaries=[Boundary("base"), Boundary("sides", y=False, rotation=False)],
                 points={"crest": (CREST - 0.5, HEIGHT - 0.5)}, stages=stages, name="cut",
                 continuum={"h": 2.5, "materials": {"rock": ROCK}} if continuum else None)


def test_a_staged_cut_from_the_file_equals_the_model_built_by_hand(tmp_path):
    from continuum_ref.from_scene import apply_boundaries, apply_water, mesh_from_scene, \
        scene_bounds
    from continuum_ref.materials import MohrCoulomb
    from continuum_ref.model import ContinuumModel
    from continuum_ref.scene_run import max_displacement, run_scene
    from continuum_ref.ssr import factor_of_safety

    path = tmp_path / "cut.json"
    cut_scene().save(path)
    scene = Scene.load(path)
    records = run_scene(scene)
    assert [r.kind for r in records] == ["gravity", "solve", "excavate", "excavate", "water",
                                         "factor_of_safety"]
    assert all(r.verdict == "equilibrium" for r in records[:5])
    fos = records[-1]
    assert fos.verdict == "limit" and 1.0 < fos.value < 3.0

    rock = MohrCoulomb(**{k: v for k, v in ROCK.items() if k != "kind"})
    model = ContinuumModel(mesh_from_scene(scene, 2.5), {"rock": rock}, 2000.0)
    apply_boundaries(model, scene, scene_bounds(scene))
    assert model.solve_gravity(1.0).converged and model.equilibrate().converged
    for lift in ("lift1", "lift2"):
        assert model.excavate(lift).converged
    assert apply_water(model, WaterTable(TABLE), solve=True).converged
    limit = factor_of_safety(model, [rock], f_max=3.0, f_start=1.0, tol=0.02)
    assert limit.found
    assert fos.value == pytest.approx(limit.value, abs=1e-6)
    assert fos.max_displacement == pytest.approx(max_displacement(model), rel=1e-6, abs=1e-12)


def test_a_stage_the_continuum_cannot_run_is_refused_before_any_mesh(monkeypatch):
    from continuum_ref import scene_run

    def no_mesh(*a, **k):
        raise AssertionError("meshed before the stages were checked")
    monkeypatch.setattr(scene_run, "build_continuum", no_mesh)
    scene = cut_scene(stages=[Gravity(1.0), Solve(), Cycle(100), Excavate("lift1")])
    with pytest.raises(ValueError, match=r"cannot run stage 2 \(cycle\)"):
        scene_run.run_scene(scene)
    scene = cut_scene(stages=[Gravity(1.0), Excavate("base")])
    with pytest.raises(ValueError, match=r"stage 1 \(excavate\).*'base'"):
        scene_run.run_scene(scene)


def test_a_bad_continuum_section_names_the_key():
    scene = cut_scene()
    with pytest.raises(ValueError, match="did you mean 'materials'"):
        Scene(**{**scene.__dict__, "continuum": {"h": 1.0, "material": {}}})
    with pytest.raises(ValueError, match=r"materials\['rok'\] matches no region"):
        Scene(**{**scene.__dict__, "continuum": {"h": 1.0, "materials": {"rok": ROCK}}})
    with pytest.raises(ValueError, match="flow must be one of"):
        Scene(**{**scene.__dict__, "continuum": {"h": 1.0, "materials": {"*": ROCK},
                                                 "flow": "plastic"}})
    with pytest.raises(ValueError, match="search_step F must be finite and > 0, got -0.5"):
        Scene(**{**scene.__dict__, "continuum": {"h": 1.0, "materials": {"*": ROCK},
                                                 "search_step": {"F": -0.5}}})
    with pytest.raises(ValueError, match="did you mean 'g'"):
        Scene(**{**scene.__dict__, "continuum": {"h": 1.0, "materials": {"*": ROCK},
                                                 "search_step": {"gg": 1.0}}})


def tiny_scene():
    """A box resting on a fixed base: gravity, then a solve (fast in both methods)."""
    geo = GeometrySpec([rectangle("base", 0, 0, 4, 1), rectangle("block", 1, 1, 3, 2)])
    return Scene(geo, {"*": Material(kn=1e9, ks=1e9, friction=30.0)}, density=2500.0,
                 groups={"bottom": {"touching": "bottom"}},
                 boundaries=[Boundary("bottom")], points={"top": (2.0, 1.9)},
                 stages=[Gravity(1.0), Solve(ratio=1e-4, max_steps=3000)], name="tiny",
                 continuum={"h": 0.5, "materials": {"*": {"kind": "elastic", "E": 1e9,
                                                          "nu": 0.25}}})


def test_method_both_writes_one_report_with_both_columns(tmp_path, capsys):
    from comparisons import cli

    path = tmp_path / "tiny.json"
    tiny_scene().save(path)
    assert cli.main(["run-scene", str(path), "--out", str(tmp_path), "--method", "both",
                     "--quiet"]) == 0
    folder = tmp_path / "tiny"
    report = (folder / "report.md").read_text()
    assert "| stage | kind | DEM" in report and "continuum" in report
    summary = json.loads((folder / "continuum.json").read_text())
    assert [s["verdict"] for s in summary["stages"]] == ["equilibrium", "equilibrium"]
    assert summary["runtime_s"] > 0 and np.isfinite(summary["stages"][1]["max_displacement"])
    out = capsys.readouterr().out
    assert "Verdicts:" in out and "Continuum:\n  stage 0 gravity: equilibrium" in out


def test_method_continuum_without_a_continuum_section_is_one_line(tmp_path, capsys):
    from comparisons import cli

    path = tmp_path / "tiny.json"
    sc = tiny_scene()
    sc.continuum = None
    sc.save(path)
    assert cli.main(["run-scene", str(path), "--out", str(tmp_path), "--method",
                     "continuum"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "no \"continuum\" section" in err[0]


def test_an_insitu_field_set_at_zero_g_is_balanced_by_gravity_and_a_g_search_runs():
    from continuum_ref.scene_run import run_scene
    from dem_core.workflow.insitu import InSitu
    from dem_core.workflow.stages import RaiseGravity

    scene = tiny_scene()
    scene.stages = [InSitu.geostatic(2500.0, 0.5), Gravity(1.0), RaiseGravity((2.0, 3.0))]
    records = run_scene(scene)
    assert [r.verdict for r in records] == ["set", "equilibrium", "stable"]
    assert records[1].max_displacement < 1e-6          # the field balances the weight, m
    assert records[2].value == pytest.approx(3.0)      # elastic: stands to the range's end
    assert records[2].detail["steps"] == 10            # default step: a tenth of 1 -> 3 g


def test_the_search_step_of_the_section_is_the_searchs_first_and_largest_step():
    from continuum_ref.scene_run import run_scene
    from dem_core.workflow.stages import RaiseGravity

    scene = tiny_scene()
    scene.continuum = {**scene.continuum, "search_step": {"g": 0.5, "F": 0.5}}
    scene.stages = [Gravity(1.0), RaiseGravity((2.0, 3.0))]
    ramp = run_scene(scene)[-1]
    assert ramp.verdict == "stable" and ramp.value == pytest.approx(3.0)
    assert ramp.detail["steps"] == 4                   # 1.5, 2.0, 2.5, 3.0 g


def test_method_continuum_builds_no_dem_model(tmp_path, capsys, monkeypatch):
    from comparisons import cli, run_scene

    def no_dem(*a, **k):
        raise AssertionError("the DEM model was built")
    monkeypatch.setattr(run_scene, "build_checked", no_dem)
    path = tmp_path / "tiny.json"
    tiny_scene().save(path)
    assert cli.main(["run-scene", str(path), "--out", str(tmp_path), "--method",
                     "continuum", "--quiet"]) == 0
    report = (tmp_path / "tiny" / "report.md").read_text()
    assert report.startswith("# tiny (scene file, continuum)") and "| stage | kind | DEM" \
        not in report and "| 1 | solve | equilibrium |" in report
    assert not (tmp_path / "tiny" / "summary.json").exists()


def test_method_both_refuses_a_stage_the_continuum_cannot_run_before_the_dem_runs(tmp_path,
                                                                                    capsys):
    from comparisons import cli

    path = tmp_path / "tiny.json"
    sc = tiny_scene()
    sc.stages = [Gravity(1.0), Cycle(10)]
    sc.save(path)
    assert cli.main(["run-scene", str(path), "--out", str(tmp_path), "--method", "both"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "stage 1 (cycle)" in err[0]
    assert not (tmp_path / "tiny" / "summary.json").exists()


def test_each_stage_can_be_drawn_at_its_end_without_the_excavated_cells():
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from continuum_ref.plot import live_cells, stage_figure
    from continuum_ref.scene_run import run_scene

    scene = cut_scene([Gravity(1.0), Excavate("lift1"), Excavate("lift2")])
    seen = []

    def draw(model, rec):
        live = live_cells(model)
        fig = stage_figure(model, f"stage {rec.index} ({rec.kind}): {rec.verdict}")
        yield_cells = fig.axes[1].collections[0].get_array().size   # one colour per cell drawn
        seen.append((rec.kind, int(live.sum()), len(live), yield_cells, fig._suptitle.get_text()))
        plt.close(fig)

    run_scene(scene, on_stage=draw)
    (k0, live0, n0, drawn0, t0), (_, live1, _, drawn1, t1), (_, live2, _, drawn2, t2) = seen
    assert live0 == n0 == drawn0 and "excavated" not in t0 and t0.startswith("stage 0 (gravity)")
    assert n0 > live1 == drawn1 > live2 == drawn2 > 0
    assert f"{n0 - live2} excavated cells not drawn" in t2 and "stage 2 (excavate)" in t2


def _tresca_scene(stages):
    """The cut with a joint set whose (frictionless) strength the continuum's rock mass takes
    (``dem_rock_mass``, bound "joints"): a Tresca rock mass of c = 60 kPa."""
    from dem_core.geometry import JointSet

    base = cut_scene([])
    geo = GeometrySpec(base.geometry.regions, joint_sets=[JointSet("bed", 20.0, 4.0)],
                       groups=base.geometry.groups)
    mats = {"joint:bed": Material(kn=1e9, ks=1e9, cohesion=60e3, friction=0.0),
            "*": Material(kn=1e9, ks=1e9, friction=35.0)}
    return Scene(geo, mats, density=2000.0, groups=base.groups, boundaries=base.boundaries,
                 points=base.points, stages=stages, name="tresca-cut",
                 continuum={"h": 2.5, "materials": {"rock": {"kind": "dem_rock_mass",
                                                             "bound": "joints"}}})


def test_a_strength_schedule_finds_the_cohesion_whose_ratio_is_the_factor_of_safety():
    """Tresca: strength reduction divides c alone, so F = c / c_critical, where c_critical
    is the cohesion a schedule lowering c finds the limit at."""
    from continuum_ref.scene_run import run_scene
    from dem_core.workflow.strength import StrengthSchedule

    cut = [Gravity(1.0), Excavate("lift1"), Excavate("lift2")]
    schedule = run_scene(_tresca_scene(cut + [StrengthSchedule(
        "joint:bed", "cohesion", (50e3, 40e3, 30e3, 20e3, 10e3), refine_to=100.0)]))[-1]
    fos = run_scene(_tresca_scene(cut + [FactorOfSafety(("*",), f_levels=(1.0, 2.0, 4.0),
                                                        refine_to=0.0025)]))[-1]
    assert schedule.verdict == fos.verdict == "limit"
    assert 10e3 < schedule.first_failed < schedule.value < 50e3        # lowered: failed below
    assert "limit at joint:bed cohesion" in schedule.note
    assert fos.value == pytest.approx(60e3 / schedule.value, rel=0.02)


def test_a_material_change_derives_the_rock_mass_again_and_one_that_reaches_none_is_refused():
    from continuum_ref import scene_run
    from continuum_ref.rock_mass import dem_rock_mass
    from dem_core.workflow.stages import ChangeMaterial

    scene = _tresca_scene([Gravity(1.0), ChangeMaterial("joint:bed", {"cohesion": 80e3})])
    seen = []
    records = scene_run.run_scene(scene, on_stage=lambda m, r: seen.append(m.materials[0]))
    assert [r.verdict for r in records] == ["equilibrium", "equilibrium"]
    stronger = dict(scene.materials, **{"joint:bed": Material(kn=1e9, ks=1e9, cohesion=80e3,
                                                              friction=0.0)})
    assert seen == [dem_rock_mass(scene, "rock", "joints"),
                    dem_rock_mass(scene, "rock", "joints", materials=stronger)]
    assert seen[1].cohesion == 80e3
    for stage in (ChangeMaterial("*", {"friction": 30.0}),        # not what the rock is from
                  ChangeMaterial("joint:bed", {"kn": 1e9})):        # no change at all
        with pytest.raises(ValueError, match=r"stage 1 \(change_material\).*reaches no "
                                             r"continuum region"):
            scene_run.run_scene(_tresca_scene([Gravity(1.0), stage]))
    plain = cut_scene([Gravity(1.0), ChangeMaterial("*", {"friction": 30.0})])
    with pytest.raises(ValueError, match="dem_rock_mass"):
        scene_run.run_scene(plain)


def test_a_graded_mesh_is_finer_near_its_points_and_a_bad_one_is_named():
    from continuum_ref.scene_run import build_continuum, region_materials

    refine = {"points": [[CREST, HEIGHT]], "h_far": 5.0, "d_near": 3.0, "d_far": 20.0}
    graded = cut_scene([Gravity(1.0)])
    graded = Scene.from_dict(dict(graded.to_dict(), continuum={**graded.continuum,
                                                              "h": 1.0, "refine": refine}))
    plain = cut_scene([Gravity(1.0)])
    cells = []
    for sc, h in ((graded, 1.0), (plain, 1.0), (plain, 5.0)):
        mats, _ = region_materials(sc, sc.continuum["materials"])
        cells.append(len(build_continuum(sc, h, mats).triangles()[1]))
    assert cells[2] < cells[0] < cells[1] / 3       # between the uniform 5 m and 1 m meshes
    for bad, words in ((dict(refine, h_far=0.5), "h_far 0.5 must be at least h"),
                       (dict(refine, d_near=30.0), "needs 0 <= d_near < d_far"),
                       (dict(refine, points=[[1.0]]), "points must be a list of"),
                       ({"h_far": 5.0}, "refine")):
        with pytest.raises(ValueError, match=words):
            Scene.from_dict(dict(plain.to_dict(), continuum={**plain.continuum, "h": 1.0,
                                                             "refine": bad}))
