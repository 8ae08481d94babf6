"""Run every benchmark: JSON and PNG figures into benchmarks/results/.

    .venv/bin/python benchmarks/run_all.py --quick     # about 65 min on 2 cores, most of it
                                                       # the Adhikary 4 mm run (2,591 s)
    .venv/bin/python benchmarks/run_all.py --full      # the full grids (longer still)

Runs one after the other (never in parallel: the machine is shared), each in its own process
so a crash in one does not stop the rest:

- error_vs_time.py   error against run time of the closed-form checks (docs/verification.md)
- stability_map.py   DEM time-step margin map, continuum Newton map (docs/verification.md)
- critical_step_cost.py  the step from the largest eigenvalue against the bounded one: gain
                     and the cost of a solve against a step (1e3, 1e4 blocks; full: 1e5;
                     docs/performance.md)
- leave_out.py       cost of unused parts, flaws only where needed (docs/performance.md)
- support_cost.py    cost per step of 200 cables and a liner on a pit wall (issue 23; the same
                     measurement in both modes, about 3 min; docs/performance.md)
- deformable_cost.py cost per step and per simulated second of deformable blocks against
                     rigid ones, 218 Voronoi blocks (about 1 min; docs/mechanics.md)
- performance.py     throughput (1 and 2 threads), scaling, step profile, machine limit,
                     continuum s/iteration
- performance.py --streams  the contact pass's bytes through a loop of its shape against
                     their size (about 1 min; the cache between 1e5 and 1e6 blocks, issue 29
                     item 3)
- two_threads.py     two threads against one, both shapes of the threaded step, its parts,
                     and the machine's ceiling beside it (two serial copies in two processes,
                     machine_threads.py; 1e3 to 1e5 blocks, about 5 min; docs/performance.md)
- lab_resolution.py  error against run time of the lab case (UCS, shear peak: block size,
                     time-step safety)
- centrifuge_resolution.py  Adhikary failure g against block size and run time (quick: 8, 6
                     and 4 mm; full: 8, 6, 4, 3 mm; the case's 1 g-step ramp, two processes)
- bedding_demand.py  Adhikary beds' elastic shear demand against bedding cohesion, DEM and
                     continuum (docs/comparisons.md)
- contact_pass_trials.py  three other shapes of the serial contact pass (one loop without
                     the model's other paths, a vectorised law pass and a scatter pass, one
                     row per block's pose) against the model's, 1e4 and 1e5 blocks (about
                     2 min; issue 29 item 2, docs/performance.md)
- million.py         a million blocks: tessellation time, memory and the per-contact rate
                     against 1e5 blocks, with the stream loop's rate at both sizes (about
                     6 min, 4 GB; issue 29 item 3, docs/performance.md)
- numba_pipelines.py the contact kernel through numba's plain and parallel pipelines (ns per
                     contact, reference counts in the IR; docs/performance.md)
- gravity_box.py     contact tension of bonded Voronoi rock under its own weight, rigid and
                     deformable blocks (about 3 min; docs/cases/checkerboard.md)
- deformable_ucs.py  the lab UCS floor with deformable blocks against rigid ones (about 2 min;
                     docs/comparisons.md, lajtai)
- regression_numbers.py   prints the regression-guard numbers (does not rewrite the reference)
- full only: continuum_scaling.py (slope and footing refinement), throughput.py --scaling,
  column_bending.py (flexural strength of a Voronoi column against beam theory by block size),
  conventional_deformable.py (the thesis's conventional model of longtan and adhikary with
  Mohr-Coulomb zones, raised in g to failure, bisected to 5 g: about 5 and 12 min;
  docs/comparisons.md), fewer_steps.py (early settling against today's search in the
  Adhikary ramp at 6 and 4 mm, each at 0.9, 1 and 1.1 times the steps a level: about 25 min;
  then settling with the step from the largest eigenvalue against those runs: about 15 min;
  docs/performance.md, issue 29 item 4), case_steps.py (the six staged cases' quick DEM runs
  on the bounded step, on the eigen step and settling, against today's spread and a run with
  twice the budgets: steps, seconds and answers per case, about 25 min; issue 29 item 4)
"""
from __future__ import annotations

import argparse
import json
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    g = ap.add_mutually_exclusive_group()
    g.add_argument("--quick", action="store_true", help="(default)")
    g.add_argument("--full", action="store_true")
    a = ap.parse_args()
    mode = "--full" if a.full else "--quick"
    jobs = [["error_vs_time.py", mode], ["stability_map.py", mode],
            ["critical_step_cost.py", mode], ["leave_out.py", mode],
            ["support_cost.py"], ["deformable_cost.py"],
            ["performance.py", mode], ["performance.py", "--streams"], ["two_threads.py"],
            ["contact_pass_trials.py"], ["million.py"], ["numba_pipelines.py"],
            ["lab_resolution.py", mode],
            ["centrifuge_resolution.py", "--edges", "0.008", "0.006", "0.004"]
            + (["0.003"] if a.full else []), ["bedding_demand.py"], ["gravity_box.py"],
            ["deformable_ucs.py", "--zones", "0", "0.0035", "--cohesion", "0.05e6", "0.5e6",
             "1.2e6"], ["regression_numbers.py"]]
    if a.full:
        jobs += [["continuum_scaling.py"], ["throughput.py", "--scaling"],
                 ["column_bending.py", "--edges", "0.006", "0.004", "0.003"],
                 ["conventional_deformable.py", "--case", "longtan", "--zone", "0.01",
                  "--plastic", "--levels", "100", "200", "20", "--refine-to", "5", "--out",
                  str(HERE / "results" / "conventional_longtan_plastic_10mm_refined.json")],
                 ["conventional_deformable.py", "--case", "adhikary", "--zone", "0.005",
                  "--plastic", "--levels", "40", "200", "20", "--refine-to", "5", "--out",
                  str(HERE / "results" / "conventional_adhikary_plastic_5mm_refined.json")],
                 ["fewer_steps.py", "--edges", "0.006", "0.004", "--budgets", "0.9", "1", "1.1"],
                 ["fewer_steps.py", "--edges", "0.006", "0.004", "--budgets", "0.9", "1", "1.1",
                  "--solver", '{"step_estimate": "eigen"}', "--today", "fewer_steps_budgets"],
                 ["case_steps.py"]]
    summary = []
    for job in jobs:
        t0 = time.perf_counter()
        print(f"== {' '.join(job)}", flush=True)
        r = subprocess.run([sys.executable, str(HERE / job[0]), *job[1:]], cwd=HERE)
        summary.append({"job": " ".join(job), "returncode": r.returncode,
                        "seconds": round(time.perf_counter() - t0, 1)})
        print(f"== {' '.join(job)}: rc {r.returncode}, {summary[-1]['seconds']} s", flush=True)
    (HERE / "results" / "run_all.json").write_text(json.dumps(
        {"mode": mode, "date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()),
         "jobs": summary}, indent=1))
    sys.exit(max(s["returncode"] for s in summary))


if __name__ == "__main__":
    main()
