"""Resumable case runs: inside ``store.case_output`` every finished sweep member is
kept as soon as it finishes; a run that dies part-way is resumed with ``resume=True``: the kept
members are loaded, not run again, the others run, and the results equal an uninterrupted
run's. The command line does the same for a whole case (``--resume``) and writes the DEM
models for ParaView (``--vtk``)."""
import functools
import json
import os
import uuid
from pathlib import Path

import meshio
import numpy as np
import pytest

from comparisons import cli, longtan, store
from comparisons.sweep import run_sweep

XS = [1.0, 2.0, 3.0]


def member(p: dict) -> dict:
    """A sweep member that records each call in ``p["calls"]`` and fails while the file
    ``p["fail"]`` exists; its result holds what a kept result must bring back intact."""
    Path(p["calls"], f"{p['x']:g}-{uuid.uuid4().hex}").touch()
    if os.path.exists(p["fail"]):
        raise RuntimeError(f"member {p['x']:g} interrupted")
    x = p["x"]
    return {"x": x, "curve": np.column_stack([np.arange(4.0), x * np.arange(4.0)]),
            "empty": np.zeros((0, 3)), "ids": np.arange(3, dtype=np.int32),
            "n": np.int64(7), "nan": float("nan"), "runtime_s": 0.1 * x}


def calls(folder) -> list:
    """The x of each call so far, sorted."""
    return sorted(float(f.name.split("-")[0]) for f in Path(folder).iterdir())


def same(a, b) -> bool:
    """Deep equality of member results (arrays by dtype, shape and value, numbers by value;
    NaN equals NaN)."""
    if isinstance(a, dict):
        return isinstance(b, dict) and a.keys() == b.keys() and all(same(a[k], b[k]) for k in a)
    if isinstance(a, list):
        return isinstance(b, list) and len(a) == len(b) and all(map(same, a, b))
    if isinstance(a, np.ndarray):
        return (isinstance(b, np.ndarray) and a.dtype == b.dtype and a.shape == b.shape
                and np.array_equal(a, b, equal_nan=True))
    if isinstance(a, float) and np.isnan(a):
        return isinstance(b, float) and np.isnan(b)
    return a == b


@pytest.mark.parametrize("workers", [1, 2])
def test_an_interrupted_sweep_resumes_with_the_uninterrupted_results(tmp_path, workers,
                                                                     monkeypatch):
    monkeypatch.setenv("COMPARISONS_WORKERS", "2")     # a pool even in a pytest-xdist worker
    (tmp_path / "calls").mkdir()
    flag = tmp_path / "fail-2"
    params = [{"x": x, "calls": str(tmp_path / "calls"),
               "fail": str(flag if x == 2.0 else tmp_path / "never")} for x in XS]
    flag.touch()
    with store.case_output(tmp_path / "run"):
        with pytest.raises(RuntimeError, match="member 2 interrupted"):
            run_sweep(member, params, workers=workers)
    assert calls(tmp_path / "calls") == XS                  # the others finished ...
    assert len(list((tmp_path / "run" / "members").glob("member-*.json"))) == 2   # ... kept

    flag.unlink()
    with store.case_output(tmp_path / "run", resume=True):
        resumed = run_sweep(member, params, workers=workers)
    assert calls(tmp_path / "calls") == [1.0, 2.0, 2.0, 3.0]     # only member 2 ran again

    with store.case_output(tmp_path / "uninterrupted"):
        straight = run_sweep(member, params, workers=workers)
    assert same(resumed, straight)
    assert same(straight, [member({**p, "calls": str(tmp_path / "calls")}) for p in params])
    assert resumed[0]["curve"].dtype == np.float64 and resumed[0]["ids"].dtype == np.int32


def test_without_resume_every_member_runs_and_a_half_written_file_is_run_again(tmp_path):
    (tmp_path / "calls").mkdir()
    params = [{"x": x, "calls": str(tmp_path / "calls"), "fail": str(tmp_path / "never")}
              for x in XS]
    with store.case_output(tmp_path / "run") as out:
        run_sweep(member, params)
    with store.case_output(tmp_path / "run"):                 # no resume: all run again
        run_sweep(member, params)
    assert calls(tmp_path / "calls") == sorted(XS * 2)
    out.member_path(member, params[0]).write_text('{"x": 1.0, "cur')      # killed mid-write
    with store.case_output(tmp_path / "run", resume=True):
        again = run_sweep(member, params)
    assert calls(tmp_path / "calls") == sorted(XS * 2 + [1.0])
    assert again[0]["x"] == 1.0
    assert run_sweep(member, params[:1])[0]["n"] == 7           # no store: nothing kept
    left = out.members / "checkpoint-0123.npz"                  # a killed ramp's progress
    left.touch()
    with store.case_output(tmp_path / "run", resume=True):
        assert store.checkpoint({"x": 1}).startswith(str(out.members / "checkpoint-"))
    assert left.exists()                                        # kept for the resume ...
    with store.case_output(tmp_path / "run"):
        pass
    assert not left.exists()                                    # ... a fresh run starts over
    assert store.checkpoint({"x": 1}) is None                   # outside a case run


def test_keys_follow_the_parameters_and_the_function():
    a = {"x": 1.0, "g": [40, 80]}
    assert store.member_key(member, a) == store.member_key(member, {"g": [40, 80], "x": 1.0})
    assert store.member_key(member, a) != store.member_key(member, {**a, "x": 1.0 + 1e-15})
    assert store.member_key(member, a) != store.member_key(same, a)


# a case from the command line: longtan shrunk to two short members (seconds)
TINY = dict(edge_length=0.012, relax_iterations=2, g_levels=[200, 300], max_steps=3000,
            refine_to=None, tensile=[4.81e6], conventional=True, continuum=False,
            continuum_h=0.05, workers=1, threads=1)


def summary(folder):
    """The case's summary without its clock: run times, when written, software versions."""
    def drop(v):
        if isinstance(v, dict):
            return {k: drop(x) for k, x in v.items() if "runtime" not in k and k != "written"}
        return [drop(x) for x in v] if isinstance(v, list) else v
    s = drop(json.loads((folder / "summary.json").read_text()))
    s.pop("versions")
    return s


def test_a_case_resumes_from_the_command_line_and_writes_vtk(tmp_path, monkeypatch):
    monkeypatch.setitem(longtan.VARIANTS, "quick", TINY)
    original, ran, kill = longtan.run_member, [], ["T=4.81"]

    @functools.wraps(original)           # same name and module: the same member keys
    def run_member(m):
        ran.append(m["label"])
        if m["label"] in kill:
            raise KeyboardInterrupt      # Ctrl-C during the second member
        return original(m)

    monkeypatch.setattr(longtan, "run_member", run_member)
    args = ["run", "longtan", "--quick", "--quiet", "--vtk", "--out"]
    with pytest.raises(KeyboardInterrupt):
        cli.main(args + [str(tmp_path / "a")])
    assert ran == ["conventional", "T=4.81"]
    kill.clear()
    assert cli.main(args + [str(tmp_path / "a"), "--resume"]) == 0
    assert ran == ["conventional", "T=4.81", "T=4.81"]     # the kept member did not run again
    assert cli.main(args + [str(tmp_path / "b")]) == 0     # uninterrupted
    folder = tmp_path / "a" / "longtan"
    assert summary(folder) == summary(tmp_path / "b" / "longtan")

    kept = {r["label"]: r for r in (store.loads(f.read_text())["result"]
                                    for f in (folder / "members").glob("run_member-*.json"))}
    assert sorted(kept) == ["T=4.81", "conventional"]
    for label, name in (("T=4.81", "T4.81"), ("conventional", "conventional")):
        mesh = meshio.read(folder / "vtk" / f"{name}.vtu")
        kind = np.concatenate(mesh.cell_data["kind"])
        block = np.concatenate(mesh.cell_data["block"])[kind == 0]
        disp = np.concatenate(mesh.cell_data["displacement"])[kind == 0, :2]
        pic = kept[label]["picture"]                # the same final state, as drawn
        assert np.count_nonzero(kind == 0) == kept[label]["blocks"]
        assert np.array_equal(disp, (pic["pos"] - pic["pos0"])[block])
    assert (folder / "cracks_at_failure.png").exists()


def test_a_ramp_stopped_after_a_level_goes_on_to_the_same_result(tmp_path, monkeypatch):
    """A g-ramp killed after its first level resumes from its checkpoint (the model saved by
    ``limit.save_resumable``) and ends where the ramp that was not stopped ends, to the bit:
    levels (a bisection and closing steps after the resumed level), displacements, cracks,
    the final blocks. The level series for ParaView holds every level once."""
    from comparisons import centrifuge

    v = dict(edge_length=0.012, relax_iterations=2, g_levels=[60, 120, 240, 360],
             max_steps=2000, refine_to=30.0, tensile=[4.81e6], conventional=False)
    base = centrifuge.ramp_members(v, seed=1)[0]
    straight = longtan.run_member(base)
    assert straight["refined_levels"] > 0 and straight["failure_g"] is not None   # bisected

    ck = str(tmp_path / "checkpoint-x")
    member = {**base, "checkpoint": ck, "vtk": str(tmp_path / "vtk" / "T4.81.vtu")}
    real = centrifuge.save_resumable

    def save_then_die(path, model, rec):
        real(path, model, rec)
        if len(rec.level) == 1:
            raise KeyboardInterrupt                         # killed after the first level

    monkeypatch.setattr(centrifuge, "save_resumable", save_then_die)
    with pytest.raises(KeyboardInterrupt):
        longtan.run_member(member)
    assert Path(ck + ".npz").exists() and Path(ck + ".json").exists()
    monkeypatch.setattr(centrifuge, "save_resumable", real)
    resumed = longtan.run_member(member)
    assert not Path(ck + ".npz").exists()                   # finished: checkpoint removed

    differ = [k for k in straight if k != "runtime_s" and not same(resumed[k], straight[k])]
    assert differ == [], [(k, resumed[k], straight[k]) for k in differ if k != "picture"]
    pvd = (tmp_path / "vtk" / "T4.81" / "T4.81.pvd").read_text()
    assert pvd.count("<DataSet") == len(straight["g"])      # one file per level run


def test_the_lab_case_keeps_every_dem_run_and_resumes_to_the_same_report(tmp_path,
                                                                        monkeypatch):
    """lajtai shrunk to 14 mm blocks and one normal stress: its calibration runs are members
    too, so a resumed run runs no DEM model and reports the same numbers, with the specimen
    pictures."""
    import matplotlib

    matplotlib.use("Agg")
    from comparisons import lajtai
    from comparisons.results import write_results

    tiny = dict(lajtai.VARIANTS["quick"], ucs_edge=0.014, shear_edge=0.014, ucs_rate=6e-7,
                shear_rate=1.2e-6, normal_stresses=[1.2e6], lajtai_normal_stresses=[1.2e6],
                persistence=[0.0], tensile=[], continuum=False, workers=1)
    ran = []
    for name in ("ucs_member", "shear_member"):
        real = getattr(lajtai, name)
        monkeypatch.setattr(lajtai, name, functools.wraps(real)(
            lambda q, real=real: ran.append(q) or real(q)))
    summaries = []
    for resume in (False, True):
        with store.case_output(tmp_path / "lajtai", resume=resume, vtk=True):
            result = lajtai.run(tiny, seed=1)
        summaries.append(summary(write_results(result, tmp_path)))
        if not resume:
            assert len(ran) >= 7         # 3 shear tests, calibration, rate check, tension
            ran.clear()
    assert ran == [] and summaries[0] == summaries[1]
    folder = tmp_path / "lajtai"
    assert (folder / "shear_specimens.png").exists() and (folder / "ucs.png").exists()
    assert (folder / "vtk" / "lajtai_open_sn1.2.vtu").exists()


def test_a_kept_result_of_other_settings_is_refused_and_restart_starts_over(tmp_path):
    """Each kept member records the run's source; resuming with another source is refused,
    naming the file, before anything runs; ``restart`` (and a run without resume) deletes
    the kept results."""
    (tmp_path / "calls").mkdir()
    params = [{"x": x, "calls": str(tmp_path / "calls"), "fail": str(tmp_path / "never")}
              for x in XS]
    with store.case_output(tmp_path / "run", source="a") as out:
        run_sweep(member, params)
    kept = store.loads(out.member_path(member, params[0]).read_text())
    assert kept["source"] == {"member": store.member_key(member, params[0]), "run": "a"}
    with pytest.raises(store.StaleResult, match="settings changed since it was written") as e:
        with store.case_output(tmp_path / "run", resume=True, source="b"):
            pytest.fail("entered")
    assert str(out.members) in str(e.value) and len(str(e.value).splitlines()) == 1
    with store.case_output(tmp_path / "run", resume=True, source="a"):
        run_sweep(member, params)
    assert calls(tmp_path / "calls") == XS                      # resumed: none ran again
    with store.case_output(tmp_path / "run", resume=True, source="b", restart=True):
        run_sweep(member, params)
    assert calls(tmp_path / "calls") == sorted(XS * 2)          # restarted: all ran
    assert store.source_hash({"a": 1, "b": [2]}) == store.source_hash({"b": [2], "a": 1})


def test_a_checkpoint_of_other_settings_or_cut_short_is_refused_by_name(tmp_path):
    with store.case_output(tmp_path / "run", source="a"):
        stem = Path(store.checkpoint({"x": 1}))
    assert json.loads(Path(str(stem) + ".source.json").read_text())["run"] == "a"
    Path(str(stem) + ".json").write_text('{"record": {"level": [1.0]}, "step": 10}')
    with store.case_output(tmp_path / "run", resume=True, source="a"):
        pass                                                    # the same source: kept
    with pytest.raises(store.StaleResult, match="changed since it was written") as e:
        with store.case_output(tmp_path / "run", resume=True, source="b"):
            pass
    assert str(stem) + ".json" in str(e.value)
    Path(str(stem) + ".json").write_text('{"record": {"lev')    # cut short
    with pytest.raises(ValueError, match="not valid JSON") as e:
        with store.case_output(tmp_path / "run", resume=True, source="a"):
            pass
    assert str(stem) + ".json" in str(e.value) and len(str(e.value).splitlines()) == 1


def test_the_command_line_refuses_a_resume_with_other_settings_before_the_case_runs(
        tmp_path, monkeypatch, capsys):
    import types

    from comparisons import registry

    class Ran(Exception):
        pass

    def run(variant, seed, progress):
        raise Ran(variant)

    fake = types.SimpleNamespace(__name__="comparisons.fake", VARIANTS={"quick": {"x": 1}},
                                 run=run)
    monkeypatch.setattr(registry, "case_module", lambda name: fake)
    (tmp_path / "calls").mkdir()
    params = [{"x": 1.0, "calls": str(tmp_path / "calls"), "fail": str(tmp_path / "never")}]
    with store.case_output(tmp_path / "fake", source=cli.case_source(fake, "fake", "quick",
                                                                     "quick", 1)) as out:
        run_sweep(member, params)
    args = ["run", "fake", "--quick", "--out", str(tmp_path), "--resume"]
    assert cli.main(args + ["--set", "x=2"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and str(out.member_path(member, params[0])) in err
    assert "--restart" in err
    with pytest.raises(Ran):                    # the same settings get to the case's run
        cli.main(args)
    with pytest.raises(Ran):                    # so does --restart, which deletes them
        cli.main(args + ["--set", "x=2", "--restart"])
    assert not list(out.members.glob("*.json"))
