"""The MPI path of the sweeps: a tiny sweep launched under ``mpirun -n 3 python -m
mpi4py.futures`` (one manager, two workers) returns the serial results, in order, to the bit."""
import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from comparisons.sweep import run_sweep

HERE = Path(__file__).resolve().parent
FRICTIONS = [10.0, 20.0, 25.0, 35.0]


@pytest.mark.skipif(shutil.which("mpirun") is None, reason="no MPI launcher")
def test_a_sweep_under_mpi_gives_the_serial_results():
    pytest.importorskip("mpi4py")
    sys.path.insert(0, str(HERE))
    from sweep_members import slide

    serial = run_sweep(slide, FRICTIONS, workers=1)
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
               PYTHONPATH=os.pathsep.join([str(HERE), str(HERE.parent)]))
    run = subprocess.run(["mpirun", "--oversubscribe", "-n", "3", sys.executable, "-m",
                          "mpi4py.futures", str(HERE / "sweep_members.py")],
                         capture_output=True, text=True, env=env, timeout=300, cwd=HERE.parent)
    assert run.returncode == 0, run.stderr[-2000:]
    out = json.loads(run.stdout.strip().splitlines()[-1])
    assert out["mpi"] is True
    assert out["results"] == serial                 # same numbers, same order
    # less friction, further down; at 35 degrees (> 30) the block holds
    assert serial[0] > serial[1] > serial[2] > 0.01 > 1e-4 > abs(serial[3])
