"""Progress of long runs: each sweep member reports its level, steps, elapsed time
and an estimate of the time left; in a log (not a terminal) each report is a plain line, on a
terminal one line per running member is rewritten in place. The reports reach the parent from
the same process and from a local process pool alike."""
import io
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path
from types import SimpleNamespace

import pytest

from comparisons import centrifuge
from comparisons.progress import Progress, Status, duration, ramp_status
from comparisons.sweep import run_sweep
from dem_core.geometry import GeometrySpec
from dem_core.geometry.regions import rectangle
from dem_core.workflow.limit import LimitRecord
from dem_core.contact.materials import Material
from dem_core.workflow.scene import Boundary, Scene

HERE = Path(__file__).resolve().parent
G_LEVELS = (1.0, 2.0, 3.0)
LINE = re.compile(r"^\[tiny +[\d.]+ s\] member (\d+)/(\d+) (\S+): g = ([\d.]+) "
                  r"\(level (\d+)/(\d+)\), (\d+) steps, elapsed ([\d.]+) s, left ~([\d.]+) s$")


def block_scene(params, stages):
    """A block resting on a fixed base: stands at every g-level (points A and B on it)."""
    geo = GeometrySpec([rectangle("base", 0, 0, 4, 1), rectangle("block", 1, 1, 2, 1.5)])
    return Scene(geo, {"*": Material(kn=1e9, ks=1e9, friction=params["friction"])},
                 density=2500.0, boundaries=[Boundary("base")],
                 points={"A": (1.5, 1.4), "B": (1.2, 1.1)}, stages=stages)


def tiny_ramp(member: dict) -> dict:
    """A sweep member: the centrifuge g-ramp (``centrifuge.ramp_run``) of the block."""
    run = centrifuge.ramp_run(SimpleNamespace(scene=block_scene), member["params"], member,
                              failure_displacement=0.01, creep=1e-5)
    return {"label": run["label"], "steps": run["steps"], "g": run["g"]}


def members():
    return [dict(label=f"phi={phi:g}", params={"friction": phi}, g_levels=G_LEVELS,
                 max_steps=3000) for phi in (30.0, 40.0)]


@pytest.mark.parametrize("workers", [1, 2])
def test_a_sweep_in_a_log_reports_level_steps_elapsed_and_estimate(workers, monkeypatch):
    monkeypatch.setenv("COMPARISONS_WORKERS", "2")     # a pool even in a pytest-xdist worker
    out = io.StringIO()
    progress = Progress("tiny", stream=out, live=False)
    runs = run_sweep(tiny_ramp, members(), workers=workers, progress=progress)
    lines = out.getvalue().splitlines()
    assert "\x1b" not in out.getvalue()                     # plain lines only
    for i, run in enumerate(runs):
        who = f"member {i + 1}/2 {run['label']}"
        assert any(line.endswith(f"] {who}: started, 0 steps, elapsed 0.0 s, left unknown")
                   for line in lines)
        found = [LINE.match(line) for line in lines if f"] {who}: g =" in line]
        assert all(found) and len(found) == len(G_LEVELS) == len(run["g"])
        levels = [(float(m[4]), int(m[5]), int(m[6])) for m in found]
        assert levels == [(g, k + 1, 3) for k, g in enumerate(G_LEVELS)]
        steps = [int(m[7]) for m in found]
        assert steps == sorted(steps) and steps[-1] == run["steps"] > 0
        elapsed = [float(m[8]) for m in found]
        left = [float(m[9]) for m in found]
        assert elapsed == sorted(elapsed)
        assert left[-1] == 0.0                                  # the last planned level
        # the time per level so far times the levels left (to the 0.1 s of the line)
        assert left[0] == pytest.approx(2 * elapsed[0], abs=0.15)
        how = "serial" if workers == 1 else "2 processes"
        assert any(line.endswith(f"sweep member {i + 1}/2 done ({how})") for line in lines)


def test_each_sweep_of_a_run_reports_its_members():
    """A case runs several sweeps with one Progress: the second's members report too."""
    out = io.StringIO()
    progress = Progress("tiny", stream=out, live=False)
    for _ in range(2):
        run_sweep(tiny_ramp, members()[:1], workers=1, progress=progress)
    assert sum(bool(LINE.match(line)) for line in out.getvalue().splitlines()) == 6


def test_on_a_terminal_each_running_member_has_one_line_rewritten_in_place():
    out = io.StringIO()
    progress = Progress("tiny", stream=out, live=True)
    progress.member(Status(0, 2, "a", "g = 10 (level 1/3)", 100, 1.0, 2.0))
    progress.member(Status(1, 2, "b", "g = 10 (level 1/3)", 120, 1.0, 2.0))
    progress("a message")                   # printed above the status lines
    progress.member(Status(0, 2, "a", "g = 20 (level 2/3)", 200, 2.0, 1.0))
    progress.finish(0)
    progress.member(Status(0, 2, "a", "g = 30 (level 3/3)", 300, 3.0, 0.0))   # late: ignored
    progress.finish(1)
    text = out.getvalue()
    assert "g = 30" not in text
    # every redraw first moves up over the lines shown and clears them
    assert text.count("\x1b[2F\x1b[J") == 3 and text.count("\x1b[1F\x1b[J") == 2
    screen = _replay(text)
    assert screen[-1].endswith("a message") and len(screen) == 1      # the board is gone


def _replay(text):
    """The lines left on a terminal after ``text`` (cursor-up-and-clear sequences applied)."""
    screen = []
    for part in re.split(r"(\x1b\[\d+F\x1b\[J)", text):
        m = re.fullmatch(r"\x1b\[(\d+)F\x1b\[J", part)
        if m:
            del screen[len(screen) - int(m[1]):]
        else:
            screen += part.splitlines()
    return screen


def test_the_status_line_and_durations():
    s = Status(1, 5, "T=1.1", "g = 70 (level 7/30)", 140000, 41.23, 130.0)
    assert s.line() == ("member 2/5 T=1.1: g = 70 (level 7/30), 140000 steps, "
                        "elapsed 41.2 s, left ~2 min 10 s")
    assert Status(0, 1, "", "started", 0, 0.0).line() == \
        "member 1/1: started, 0 steps, elapsed 0.0 s, left unknown"
    assert duration(7384) == "2 h 03 min"


def record(levels, verdicts, refined=0, failure=None, stable=None):
    return LimitRecord("g", level=list(levels), verdict=list(verdicts), refined=refined,
                       failure_level=failure, last_stable_level=stable)


def test_the_estimate_counts_the_levels_and_bisections_still_to_run():
    plan = [10.0, 20.0, 30.0, 40.0, 50.0]
    # first pass, 2 levels in 20 s: 10 s a level, 3 levels left
    assert ramp_status(record([10, 20], ["equilibrium"] * 2), plan, 20.0, 1.0) == \
        ("g = 20 (level 2/5)", 30.0)
    # 30 g failed: bisecting [20, 30] to 1 g takes ceil(log2(10)) = 4 more levels
    assert ramp_status(record([10, 20, 30], ["equilibrium"] * 2 + ["failed"], stable=20.0),
                       plan, 30.0, 1.0) == ("g = 30 (level 3/5)", 40.0)
    # bisecting: 25 stood, [25, 30] needs 3 more
    rec = record([10, 20, 30, 25], ["equilibrium"] * 2 + ["failed", "equilibrium"], 1,
                 failure=30.0, stable=20.0)
    assert ramp_status(rec, plan, 40.0, 1.0) == ("g = 25 (refining, level 4)", 30.0)
    # closing in from the last stable level in 1 g steps: the end is not known
    rec = record([10, 20, 30, 21], ["equilibrium"] * 2 + ["failed", "equilibrium"], 1)
    assert ramp_status(rec, plan, 40.0, 1.0)[1] is None
    # without refine_to a failure ends the search
    assert ramp_status(record([10], ["failed"]), plan, 5.0)[1] == 0.0


MPI_SCRIPT = """
from comparisons.progress import Progress
from comparisons.sweep import run_sweep
from test_progress import members, tiny_ramp

if __name__ == "__main__":          # mpi4py.futures runs this file on the workers too
    run_sweep(tiny_ramp, members(), progress=Progress("tiny", live=False))
"""


@pytest.mark.skipif(shutil.which("mpirun") is None, reason="no MPI launcher")
def test_under_mpi_the_members_report_as_plain_lines_on_stderr(tmp_path):
    pytest.importorskip("mpi4py")
    script = tmp_path / "sweep.py"
    script.write_text(MPI_SCRIPT)
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
               PYTHONPATH=os.pathsep.join([str(HERE), str(HERE.parent)]))
    run = subprocess.run(["mpirun", "--oversubscribe", "-n", "3", sys.executable, "-m",
                          "mpi4py.futures", str(script)], capture_output=True, text=True,
                         env=env, timeout=300, cwd=HERE.parent)
    assert run.returncode == 0, run.stderr[-2000:]
    worker = re.compile(r"^\[tiny\] member (\d)/2 (\S+): g = ([\d.]+) \(level (\d)/3\), "
                        r"(\d+) steps, elapsed [\d.]+ s, left ~[\d.]+ s$")
    found = [worker.match(line) for line in run.stderr.splitlines()]
    assert sorted((m[1], m[4]) for m in found if m) == [(i, k) for i in "12" for k in "123"]
    assert run.stderr.count("done (MPI)") == 2
