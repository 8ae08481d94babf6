"""``python -m comparisons run-scene FILE``: a scene file run from the command line writes what
a case writes (summary, stage table, a picture of the blocks, the model for ParaView), and its
numbers are those of ``run_stages`` on the same scene. ``--resume`` goes on after the stages an
earlier run of the same scene and ``--set`` kept, and refuses those of a changed scene
(``--restart`` starts over)."""
import csv
import json
import math
import re

import meshio
import pytest

from comparisons import cli
from dem_core.geometry import GeometrySpec
from dem_core.geometry.regions import rectangle
from dem_core.contact.materials import Material
from dem_core.workflow.scene import Boundary, Scene, build_model
from dem_core.workflow.stages import (ChangeMaterial, Cycle, Excavate, FactorOfSafety, Gravity,
                                      PrescribeVelocity, Solve, StageRecord, WaterTable,
                                      run_stages, stage_table)
from comparisons.run_scene import verdict_line, verdict_lines

TILT, PHI = 20.0, 30.0


def tilted_block(stages=None, groups=None):
    """A block on a base with gravity tilted TILT degrees, friction PHI: F = tan(PHI)/tan(TILT)
    = 1.586 by limit equilibrium."""
    th = math.radians(TILT)
    geo = GeometrySpec([rectangle("base", 0, 0, 4, 1), rectangle("block", 1, 1, 2, 1.5)])
    stages = stages or [Gravity(1.0, direction=(math.sin(th), -math.cos(th))),
                        Solve(ratio=1e-6, max_steps=20_000),
                        FactorOfSafety(("*",), f_levels=(1.0, 1.25, 1.5, 2.0), refine_to=0.05,
                                       failure_displacement=0.01)]
    return Scene(geo, {"*": Material(kn=1e9, ks=1e9, friction=PHI)}, density=2500.0,
                 groups=groups or {}, boundaries=[Boundary("base")],
                 points={"top": (1.5, 1.4)}, stages=stages, name="tilted block",
                 description="a block on a tilted plane")


def test_a_scene_file_runs_from_the_command_line_with_the_runners_numbers(tmp_path, capsys):
    sc = tilted_block()
    path = tmp_path / "tilted.json"
    sc.save(path)
    assert cli.main(["run-scene", str(path), "--out", str(tmp_path / "out"), "--vtk"]) == 0
    out, err = capsys.readouterr()                  # a line per stage and per search level
    assert "stage 1 solve: equilibrium" in err
    assert re.search(r"stage 2 F = 1.25 \(level 2/4\): equilibrium, \d+ steps, elapsed "
                     r"[\d.]+ s, left ~[\d.]+ s", err)
    folder = tmp_path / "out" / "tilted_block"
    summary = json.loads((folder / "summary.json").read_text())

    m = build_model(Scene.load(path))
    records = run_stages(m, sc.stages)
    assert summary["scene"] == "tilted block" and summary["error"] is None
    assert summary["blocks"] == m.n_blocks == 2
    assert len(summary["stages"]) == len(records) == 3
    for s, r in zip(summary["stages"], records):
        assert (s["kind"], s["verdict"], s["steps"], s["cracks"]) == (r.kind, r.verdict,
                                                                      r.steps, r.cracks)
        assert s["time"] == r.time
        assert {k: tuple(v) for k, v in s["points"].items()} == r.points
    fos = records[2].detail["factor_of_safety"]
    # the stage's own progress line gives its F, not a bare "failed"
    assert re.search(rf"stage 2 factor_of_safety: factor of safety {fos:.2f} \(\d\.\d\d fails\); "
                     rf"\d+ steps, [\d.]+ s", err)
    assert summary["stages"][2]["factor_of_safety"] == summary["results"]["factor_of_safety"] \
        == fos
    assert summary["results"]["first_failed"] == records[2].detail["first_failed"]
    assert summary["stages"][2]["search"]["level"] == records[2].detail["F"]
    # the search brackets limit equilibrium's F
    assert fos <= math.tan(math.radians(PHI)) / math.tan(math.radians(TILT)) \
        <= records[2].detail["first_failed"]

    with open(folder / "stages.csv") as fh:
        rows = list(csv.DictReader(fh))
    assert [int(r["steps"]) for r in rows] == [r.steps for r in records]
    assert float(rows[-1]["top_ux_m"]) == pytest.approx(records[-1].points["top"][0], rel=1e-7)
    assert stage_table(records) in (folder / "report.md").read_text()
    assert (folder / "blocks.png").stat().st_size > 10_000
    vtu = meshio.read(folder / "tilted_block.vtu")
    assert sum(len(c.data) for c in vtu.cells) >= 2

    # the console's last lines and the top of report.md: each stage's verdict with its number
    verdicts = ["stage 0 gravity: set",
                f"stage 1 solve: equilibrium, {records[1].steps} steps",
                f"stage 2 factor_of_safety: factor of safety {fos:.2f} "
                f"({records[2].detail['first_failed']:.2f} fails); {records[2].steps} steps"]
    assert out.strip().splitlines()[-4:] == ["Verdicts:"] + [f"  {v}" for v in verdicts]
    report = (folder / "report.md").read_text().splitlines()
    assert report[2:4] == ["## Verdicts", ""] and report[4:7] == [f"- {v}" for v in verdicts]


def test_a_scene_stops_after_a_failing_solve_and_says_which_stage(tmp_path, capsys):
    """Friction lowered below the tilt: the solve judged over the response time fails, and
    the factor-of-safety stage after it does not run (the scene's after_failure "stop")."""
    th = math.radians(TILT)
    sc = tilted_block([Gravity(1.0, direction=(math.sin(th), -math.cos(th))),
                       Solve(ratio=1e-6, max_steps=20_000),
                       ChangeMaterial("*", {"friction": 0.5 * TILT}),
                       Solve(judge="response", failure_displacement=0.05),
                       FactorOfSafety(("*",), f_levels=(1.0, 1.25))])
    path = tmp_path / "sliding.json"
    sc.save(path)
    assert cli.main(["run-scene", str(path), "--out", str(tmp_path / "out")]) == 0
    out, _ = capsys.readouterr()
    summary = json.loads((tmp_path / "out" / "tilted_block" / "summary.json").read_text())
    assert [s["verdict"] for s in summary["stages"]] == ["set", "equilibrium", "changed",
                                                         "failing"]
    last = out.strip().splitlines()[-1]
    assert last.startswith("  stage 3 (solve) ended failing; moved most in it: blocks 1 (")
    assert last.endswith("stage 4 not run (after_failure: \"continue\" runs them)")


def test_a_stage_that_raises_keeps_the_stages_before_it(tmp_path, capsys):
    """A stage that raises while it runs (here the block driven at 1e6 m/s blows the model
    up) stops the run after the stages before it are written. (What the checks before the
    first step can see, e.g. an excavation of an empty group, is refused before any
    compute: tests/test_bad_input.py.)"""
    sc = tilted_block(stages=[Gravity(1.0), Solve(ratio=1e-6, max_steps=20_000),
                              PrescribeVelocity("block", vx=1e6, vy=0.0), Cycle(50)])
    path = tmp_path / "bad.json"
    sc.save(path)
    assert cli.main(["run-scene", str(path), "--out", str(tmp_path), "--quiet"]) == 1
    out, err = capsys.readouterr()
    assert "stage 3 stopped the run" in err
    last = out.strip().splitlines()[-1]
    assert last.startswith("  stage 3 cycle: FAILED, it stopped the run: ModelUnstable")
    assert f"- {last.strip()}" in (tmp_path / "tilted_block" / "report.md").read_text()
    summary = json.loads((tmp_path / "tilted_block" / "summary.json").read_text())
    assert [s["kind"] for s in summary["stages"]] == ["gravity", "solve", "prescribe_velocity"]
    assert "unstable" in summary["error"]


@pytest.mark.parametrize("text, words", [(None, "No such file"), ("{not json", "not valid JSON"),
                                         ('{"name": "x"}', "missing 'geometry'")])
def test_a_bad_scene_file_is_one_line_naming_the_file(tmp_path, capsys, text, words):
    path = tmp_path / "scene.json"
    if text is not None:
        path.write_text(text)
    assert cli.main(["run-scene", str(path), "--out", str(tmp_path)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and str(path) in err and words in err


def test_an_unwritable_out_is_refused_before_the_model_is_built(tmp_path, capsys):
    path = tmp_path / "tilted.json"
    tilted_block().save(path)
    (tmp_path / "out").write_text("a file")
    assert cli.main(["run-scene", str(path), "--out", str(tmp_path / "out")]) == 2
    assert "cannot write results" in capsys.readouterr().err


def quick_block():
    """The tilted block with two short stages: a resumable run in a second."""
    th = math.radians(TILT)
    return tilted_block(stages=[Gravity(1.0, direction=(math.sin(th), -math.cos(th))),
                                Solve(ratio=1e-4, max_steps=3000)])


def test_a_resume_is_refused_after_the_scene_changed_and_restart_starts_over(tmp_path, capsys,
                                                                            monkeypatch):
    import dem_core.workflow.stages as stages_module

    path, out = tmp_path / "tilted.json", str(tmp_path / "out")
    quick_block().save(path)
    assert cli.main(["run-scene", str(path), "--out", out, "--quiet"]) == 0
    kept = tmp_path / "out" / "tilted_block" / "members" / "checkpoint-stages.json"
    assert kept.exists()
    first = json.loads((kept.parent.parent / "summary.json").read_text())

    # the unchanged scene resumes from its kept stages: no stage runs again
    ran, real = [], stages_module.run_stages
    monkeypatch.setattr(stages_module, "run_stages",
                        lambda *a, **k: ran.append(1) or real(*a, **k))
    capsys.readouterr()
    assert cli.main(["run-scene", str(path), "--out", out, "--resume"]) == 0
    assert ran == [] and "2 kept from an earlier run" in capsys.readouterr().err
    again = json.loads((kept.parent.parent / "summary.json").read_text())
    assert [(s["steps"], s["points"]) for s in again["stages"]] == \
        [(s["steps"], s["points"]) for s in first["stages"]]

    # the scene file changed: refused before any compute, naming the kept file
    sc = quick_block()
    sc.density = 2600.0                             # the same scene, another density
    sc.save(path)
    assert cli.main(["run-scene", str(path), "--out", out, "--resume"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and str(kept) in err
    assert "scene or settings changed since it was written" in err and "--restart" in err
    assert ran == []
    # so are other --set items than those of the kept run
    quick_block().save(path)
    assert cli.main(["run-scene", str(path), "--out", out, "--resume",
                     "--set", 'solver={"damping": 0.5}']) == 2
    assert "changed since it was written" in capsys.readouterr().err
    # --restart deletes the kept stages and runs the scene with its --set
    assert cli.main(["run-scene", str(path), "--out", out, "--resume", "--restart", "--quiet",
                     "--set", 'solver={"damping": 0.5}']) == 0
    assert len(ran) == 2
    assert cli.main(["run-scene", str(path), "--out", out, "--resume", "--quiet",
                     "--set", 'solver={"damping": 0.5}']) == 0
    assert len(ran) == 2                       # the same --set resumes


def test_an_interrupted_scene_run_goes_on_after_its_last_kept_stage(tmp_path, monkeypatch):
    import dem_core.workflow.stages as stages_module

    path, out = tmp_path / "tilted.json", str(tmp_path / "out")
    quick_block().save(path)
    assert cli.main(["run-scene", str(path), "--out", str(tmp_path / "straight"),
                     "--quiet"]) == 0
    real, ran = stages_module.run_stages, []

    def run_stages(model, stages, **kw):
        ran.append(type(stages[0]).__name__)
        if len(ran) == 2 and kill:
            raise KeyboardInterrupt                 # Ctrl-C in the second stage
        return real(model, stages, **kw)

    kill = [1]
    monkeypatch.setattr(stages_module, "run_stages", run_stages)
    with pytest.raises(KeyboardInterrupt):
        cli.main(["run-scene", str(path), "--out", out, "--quiet"])
    kill.clear()
    assert cli.main(["run-scene", str(path), "--out", out, "--quiet", "--resume"]) == 0
    assert ran == ["Gravity", "Solve", "Solve"]     # the kept stage did not run again
    a, b = (json.loads((tmp_path / d / "tilted_block" / "summary.json").read_text())
            for d in ("out", "straight"))
    assert [(s["kind"], s["verdict"], s["steps"], s["time"], s["points"], s["cracks"])
            for s in a["stages"]] == [(s["kind"], s["verdict"], s["steps"], s["time"],
                                       s["points"], s["cracks"]) for s in b["stages"]]


def test_a_cut_checkpoint_is_one_line_naming_it(tmp_path, capsys):
    path, out = tmp_path / "tilted.json", str(tmp_path / "out")
    quick_block().save(path)
    assert cli.main(["run-scene", str(path), "--out", out, "--quiet"]) == 0
    kept = tmp_path / "out" / "tilted_block" / "members" / "checkpoint-stages.json"
    kept.write_text(kept.read_text()[:40])
    capsys.readouterr()
    assert cli.main(["run-scene", str(path), "--out", out, "--resume"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and str(kept) in err and "not valid JSON" in err
    assert "Traceback" not in err


@pytest.mark.parametrize("item, words", [("density", "--set takes KEY=VALUE"),
                                         ("solver=3", "--set solver: expected a JSON object"),
                                         ("densty=2", "did you mean 'density'"),
                                         ("density=-1", "density")])
def test_a_bad_set_is_one_line_before_any_compute(tmp_path, capsys, item, words):
    path = tmp_path / "tilted.json"
    quick_block().save(path)
    assert cli.main(["run-scene", str(path), "--out", str(tmp_path), "--set", item]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and words in err
    assert not (tmp_path / "tilted_block").exists()


def test_check_draws_the_model_as_built_and_runs_no_step(tmp_path, capsys, monkeypatch):
    from dem_core.model import Model

    def no_step(*a, **k):
        raise AssertionError("--check ran a step")

    monkeypatch.setattr(Model, "cycle", no_step)
    monkeypatch.setattr(Model, "solve", no_step)
    th = math.radians(TILT)
    sc = tilted_block(stages=[Gravity(1.0, direction=(math.sin(th), -math.cos(th))),
                              WaterTable(1.2), Solve(ratio=1e-6, max_steps=20_000),
                              FactorOfSafety(("*",), f_levels=(1.0, 1.5))])
    path = tmp_path / "tilted.json"
    sc.save(path)
    assert cli.main(["run-scene", str(path), "--out", str(tmp_path), "--check"]) == 0
    out = capsys.readouterr().out.strip().splitlines()
    folder = tmp_path / "tilted_block"
    n_contacts = int(build_model(sc).contacts.n)
    assert len(out) == 1
    assert out[0].startswith(f"tilted block: 2 blocks, {n_contacts} contacts; 4 stages: "
                             f"0 gravity, 1 water, 2 solve, 3 factor_of_safety;")
    assert str(folder / "check.png") in out[0]
    assert (folder / "check.png").stat().st_size > 10_000
    assert sorted(p.name for p in folder.iterdir()) == ["check.png"]   # no run's outputs


def test_check_refuses_a_bad_scene_in_one_line(tmp_path, capsys):
    path = tmp_path / "tilted.json"
    tilted_block().save(path)
    d = json.loads(path.read_text())
    d["stages"][2]["materials"] = ["no such"]
    path.write_text(json.dumps(d))
    assert cli.main(["run-scene", str(path), "--out", str(tmp_path), "--check"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "no such" in err


def record(kind, verdict, steps=100, index=2, **detail):
    return StageRecord(index, kind, steps, verdict, 0.0, {}, {}, 0.0, detail)


@pytest.mark.parametrize("detail, verdict, text", [
    ({"factor_of_safety": 1.3, "first_failed": 1.35, "F": [1.0, 1.5, 1.3, 1.35]}, "failed",
     "factor of safety 1.30 (1.35 fails)"),
    ({"factor_of_safety": None, "first_failed": 1.0, "F": [1.0]}, "failed",
     "factor of safety below 1.00 (the first level, F = 1.00, fails)"),
    ({"factor_of_safety": 2.5, "first_failed": None, "F": [1.0, 2.5]}, "stood",
     "factor of safety above 2.50 (the last level stands)")])
def test_a_factor_of_safety_verdict_gives_the_bracket(detail, verdict, text):
    assert verdict_line(record("factor_of_safety", verdict, **detail)) == \
        f"stage 2 factor_of_safety: {text}; 100 steps"


def test_the_other_verdicts_give_their_numbers():
    from dem_core.workflow.limit import LimitRecord

    ramp = record("raise_gravity", "failed", failure_g=45.0, last_stable_g=40.0, g=[40, 45])
    assert verdict_line(ramp) == "stage 2 raise_gravity: fails at 45 g (last stable 40 g); " \
        "100 steps"
    sched = record("strength_schedule", "failed", last_stable_value=25.0, failure_value=20.0,
                   values=[30, 25, 20], search=LimitRecord("friction"))
    assert verdict_line(sched) == "stage 2 strength_schedule: friction 25 stands, 20 fails; " \
        "100 steps"
    solve = record("solve", "equilibrium", steps=1234, index=1)
    assert verdict_line(solve) == "stage 1 solve: equilibrium, 1234 steps"
    lines = verdict_lines([solve], ValueError("boom"), [Gravity(), Solve(), Excavate("a"),
                                                        Solve()])
    assert lines[1:] == ["stage 2 excavate: FAILED, it stopped the run: ValueError: boom",
                         "stage 3: not run"]
