"""Run every benchmark: JSON and PNG figures into results/benchmarks/ (ignored by git).

    .venv/bin/python benchmarks/run_all.py --quick     # about 55 min on 2 cores, most of it
                                                       # the Adhikary 4 mm run (2,591 s)
    .venv/bin/python benchmarks/run_all.py --full      # the full grids (longer still)
    .venv/bin/python benchmarks/run_all.py --list      # the jobs, run nothing
    .venv/bin/python benchmarks/run_all.py --reference # the files the docs cite, rewritten in
                                                       # benchmarks/results/ (then commit them)

The one-off trials and case investigations of benchmarks/trials/ are not run (trials/README.md).

Runs one after the other (never in parallel: the machine is shared), each in its own process
so a crash in one does not stop the rest:

- first_compile.py   numba's first compile of a serial model's step from an empty cache, rigid
                     and deformable blocks (about 2 and 4 min; docs/performance.md)
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
- gravity_box.py     contact tension of bonded Voronoi rock under its own weight, rigid and
                     deformable blocks (about 3 min; docs/cases/checkerboard.md)
- regression_numbers.py   prints the regression-guard numbers (does not rewrite the reference)
- full only: continuum_scaling.py (slope and footing refinement), throughput.py --scaling,
  column_bending.py (flexural strength of a Voronoi column against beam theory by block size),
  verdict_budgets.py (every quick case member under both judges at 1x and 2x the cap)

Moved to trials/ on 2026-11-29 (one-offs, their committed results the record):
contact_pass_trials.py, million.py, numba_pipelines.py, deformable_ucs.py (quick);
conventional_deformable.py, fewer_steps.py, case_steps.py (full).
"""
from __future__ import annotations

import argparse
import json
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import outdir  # noqa: E402

# the jobs that take --reference (they write a file the docs cite)
TAKES_REFERENCE = {"error_vs_time.py", "stability_map.py", "critical_step_cost.py",
                   "leave_out.py", "support_cost.py", "deformable_cost.py", "performance.py",
                   "two_threads.py", "lab_resolution.py", "centrifuge_resolution.py",
                   "gravity_box.py", "continuum_scaling.py", "verdict_budgets.py"}


def jobs(full: bool) -> list:
    """The rerunnable benchmarks, in order: [script, args...] each."""
    mode = "--full" if full else "--quick"
    out = [["first_compile.py"], ["first_compile.py", "--deformable"],
           ["error_vs_time.py", mode], ["stability_map.py", mode],
           ["critical_step_cost.py", mode], ["leave_out.py", mode],
           ["support_cost.py"], ["deformable_cost.py"],
           ["performance.py", mode], ["performance.py", "--streams"], ["two_threads.py"],
           ["lab_resolution.py", mode],
           ["centrifuge_resolution.py", "--edges", "0.008", "0.006", "0.004"]
           + (["0.003"] if full else []), ["bedding_demand.py"], ["gravity_box.py"],
           ["regression_numbers.py"]]
    if full:
        out += [["continuum_scaling.py"], ["throughput.py", "--scaling"],
                ["column_bending.py", "--edges", "0.006", "0.004", "0.003"],
                ["verdict_budgets.py"]]
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    g = ap.add_mutually_exclusive_group()
    g.add_argument("--quick", action="store_true", help="(default)")
    g.add_argument("--full", action="store_true")
    ap.add_argument("--list", action="store_true", help="print the jobs and run nothing")
    ap.add_argument("--reference", action="store_true",
                    help="pass --reference to the jobs that take it: they rewrite the "
                         "committed files the docs cite in benchmarks/results/")
    a = ap.parse_args()
    mode = "--full" if a.full else "--quick"
    todo = [j + (["--reference"] if a.reference and j[0] in TAKES_REFERENCE else [])
            for j in jobs(a.full)]
    if a.list:
        for job in todo:
            print(" ".join(job))
        return
    summary = []
    for job in todo:
        t0 = time.perf_counter()
        print(f"== {' '.join(job)}", flush=True)
        r = subprocess.run([sys.executable, str(HERE / job[0]), *job[1:]], cwd=HERE)
        summary.append({"job": " ".join(job), "returncode": r.returncode,
                        "seconds": round(time.perf_counter() - t0, 1)})
        print(f"== {' '.join(job)}: rc {r.returncode}, {summary[-1]['seconds']} s", flush=True)
    (outdir.results_dir() / "run_all.json").write_text(json.dumps(
        {"mode": mode, "date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()),
         "jobs": summary}, indent=1))
    sys.exit(max(s["returncode"] for s in summary))


if __name__ == "__main__":
    main()
