"""Same input, same bits: a run that compiles the kernels and a run that loads them from numba's
cache end in the same final state, bit for bit (issue 56, docs/output.md "Same input, same
bits").

The case: the Adhikary centrifuge slope at 20 mm blocks (about 570 Voronoi blocks with flaws
and bedding joints), built and stepped 4,000 steps at 100 g on the step from the largest
eigenvalue, with kinetic damping: contacts searched anew, flaws breaking, the crack log
growing. It runs in two fresh processes that share one empty numba cache folder
(``NUMBA_CACHE_DIR``): the first compiles every kernel and writes the cache, the second loads
them. Each prints ``dem_core.output.fingerprint.state_hash`` of its final state; only the
first prints the first-run notice (``dem_core.jit_cache.first_run_notice``).

Run this file as a script to print one run's line: ``python tests/test_same_bits.py``.
"""
import json
import os
import subprocess
import sys
import time
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]

EDGE = 0.02             # m: about 570 blocks
G_LEVEL = 100.0
STEPS = 4000


def final_state() -> dict:
    """Build and run the case in this process: its state hash, sizes and numba's cache
    statistics for the step kernel (hits: loaded from the cache; misses: compiled)."""
    from comparisons.scenes import adhikary as scene
    from dem_core.output.fingerprint import state_hash
    from dem_core.step import run as stepper
    from dem_core.workflow.scene import build_model

    p = scene.AdhikaryParams(edge_length=EDGE, relax_iterations=2, seed=1)
    model = build_model(scene.scene(p), damping=0.0, kinetic_damping=100,
                        step_estimate="eigen")
    model.set_gravity(G_LEVEL)
    model.cycle(STEPS)
    stats = stepper.run_steps.stats
    return {"hash": state_hash(model), "blocks": model.n_blocks, "contacts": model.contacts.n,
            "cracks": int(model.cracks.count[0]), "step": model.step,
            "cache_hits": sum(stats.cache_hits.values()),
            "cache_misses": sum(stats.cache_misses.values())}


def _fresh_run(cache: Path) -> dict:
    path = os.pathsep.join(filter(None, [str(ROOT), os.environ.get("PYTHONPATH")]))
    env = dict(os.environ, NUMBA_CACHE_DIR=str(cache), OMP_NUM_THREADS="1",
               MPLBACKEND="Agg", PYTHONPATH=path, DEM_CORE_COMPILE_NOTICE="1")
    t0 = time.perf_counter()
    run = subprocess.run([sys.executable, str(Path(__file__).resolve())], cwd=ROOT, env=env,
                         capture_output=True, text=True, timeout=900)
    assert run.returncode == 0, run.stderr[-3000:]
    out = json.loads(run.stdout.strip().splitlines()[-1])
    out["seconds"] = time.perf_counter() - t0
    out["notices"] = run.stderr.count("dem_core: compiling the numba kernels")
    return out


def _small_model():
    from comparisons.scenes import adhikary as scene
    from dem_core.workflow.scene import build_model

    p = scene.AdhikaryParams(edge_length=EDGE, relax_iterations=2, seed=1)
    return build_model(scene.scene(p), damping=0.0, kinetic_damping=100, step_estimate="eigen")


def test_the_state_hash_sees_one_bit_and_nothing_else():
    import numpy as np

    from dem_core.output.fingerprint import HEX_DIGITS, state_hash

    model = _small_model()
    model.set_gravity(G_LEVEL)
    model.cycle(50)
    digest = state_hash(model)
    assert len(digest) == HEX_DIGITS and state_hash(model) == digest
    saved = model.snapshot()
    x = model.state.pos[7, 0]
    model.state.pos[7, 0] = np.nextafter(x, np.inf)          # one bit of one position
    assert state_hash(model) != digest
    model.restore(saved)
    assert state_hash(model) == digest
    n = model.contacts.n
    model.contacts.sn[n] = 123.0                 # a row past the live contacts: not read
    assert state_hash(model) == digest
    model.contacts.ts[n - 1] += 1.0              # the last live contact's shear stress
    assert state_hash(model) != digest


def test_a_case_report_carries_a_results_hash_of_its_numbers(tmp_path):
    import numpy as np

    from comparisons.results import CaseResult, Curve, write_results

    def case(g, runtime):
        r = CaseResult("probe", "quick", 1)
        r.methods["dem"] = {"failure_g": g, "runtime_s": runtime, "ux": np.array([0.1, 0.2])}
        r.add_error("failure g", g, [80.0, 85.0])
        r.curves["ux"] = Curve(["g_level", "ux_m", "runtime_s"],
                               np.array([[40.0, 1e-3, runtime], [60.0, 2e-3, runtime]]))
        return r

    digests = []
    for i, (g, runtime) in enumerate([(80.0, 1.0), (80.0, 99.0), (np.nextafter(80.0, 0), 1.0)]):
        folder = write_results(case(g, runtime), tmp_path / str(i))
        digest = json.loads((folder / "summary.json").read_text())["results_hash"]
        assert f"Results hash: `{digest}`" in (folder / "report.md").read_text()
        digests.append(digest)
    assert digests[0] == digests[1]              # run times are not results
    assert digests[0] != digests[2]              # one bit of the failure g is


@pytest.mark.slow
def test_a_compiling_run_and_a_cached_run_end_in_the_same_bits(tmp_path):
    cache = tmp_path / "numba-cache"
    cache.mkdir()
    compiling = _fresh_run(cache)
    loading = _fresh_run(cache)
    # the first compiled the step, the second loaded it from the folder the first wrote
    assert compiling["cache_misses"] >= 1 and compiling["cache_hits"] == 0, compiling
    assert loading["cache_hits"] >= 1 and loading["cache_misses"] == 0, loading
    assert loading["seconds"] < compiling["seconds"] / 2, (compiling, loading)
    assert compiling["cracks"] > 0 and compiling["step"] == STEPS
    assert loading["hash"] == compiling["hash"], (compiling, loading)
    # the first run on a "machine" (an empty cache) says it is compiling, once; the next not
    assert (compiling["notices"], loading["notices"]) == (1, 0)


if __name__ == "__main__":
    print(json.dumps(final_state()))
