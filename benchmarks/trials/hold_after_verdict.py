"""Is a verdict of the response judge right? Hold the model long after it and watch it.

Two questions of 2026-11-30 (issue 57; docs/history.md, "rest needs a decaying ratio; a
mechanism must be seen twice"):

- ``levels``: the cross-jointed field slope (examples/field_slope.py, second joint set at 70
  deg, interfaces divided) brought to each strength-reduction factor F of ``--path`` in turn
  (20,000 steps each), the last held for ``--hold`` steps, printing the crest's horizontal
  displacement and the unbalanced ratio every 10,000 steps. Found: from a settled F = 1.05,
  F = 1.0625 slides 1.6 cm and 1.0875 slides 6.8 cm (over 30,000 steps) and both stop dead
  (ratio 5e-12); F = 1.1 slides 6.7 m off the slope.
- ``member``: a quick case member run on the response judge; the solve that ends after
  ``--steps`` steps (as its judge reports them) is held for ``--hold`` more, printing the
  watched points' further movement, the ratio and the cracks. Found: underdip's 300 kPa
  cohesion level, at rest at 213,800 steps, moves 7 mm more and settles to a ratio of 7e-10.

    .venv/bin/python benchmarks/trials/hold_after_verdict.py levels --path 1.0 1.05 1.0875
    .venv/bin/python benchmarks/trials/hold_after_verdict.py member underdip "uniform beds" \\
        --steps 213800

Printed, no file.
"""
from __future__ import annotations

import argparse
import dataclasses
import os
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path[:0] = [str(ROOT / "benchmarks"), str(ROOT / "examples"), str(ROOT)]


def levels(path, hold, every=10_000):
    import field_slope as fs
    from dem_core.workflow.scene import build_model
    from dem_core.workflow.stages import run_stages
    from dem_core.workflow.strength import reduced_strength
    from dem_core.workflow.water import WaterTable

    sc = fs.scene(spacing=5.0, f_step=0.02, cross=70.0)
    sc = dataclasses.replace(sc, solver={**sc.solver, "divide_interfaces": True})
    stages = [st for st in sc.stages if not isinstance(st, WaterTable)][:-1]  # up to F
    model = build_model(sc)
    run_stages(model, stages)
    base = dict(model.materials)
    for i, f in enumerate(path):
        for name, mat in base.items():
            model.set_material(name, **reduced_strength(mat, f))
        x0 = model.point_motion("crest")[0]
        steps = hold if i == len(path) - 1 else 20_000
        for k in range(steps // every):
            model.cycle(every)
            print(f"F = {f}: {(k + 1) * every} steps, crest ux "
                  f"{model.point_motion('crest')[0] - x0:.4e} m, ratio "
                  f"{model.unbalanced_ratio():.2e}", flush=True)


def member(case_name, label, at, hold, every=20_000):
    from dem_core.workflow import response
    from verdict_budgets import members, quick_variant

    judge = response.judge

    def held(model, st, n_r, check, moved, trace):
        res = judge(model, st, n_r, check, moved, trace)
        print(f"solve: {res.verdict} at {res.steps} steps (N_r = {n_r})", flush=True)
        if res.steps == at:
            names = list(model.points)
            p0 = {n: model.point_motion(n)[:2] for n in names}
            for k in range(hold // every):
                model.cycle(every)
                du = {n: [round(float(a - b), 5) for a, b in
                          zip(model.point_motion(n)[:2], p0[n])] for n in names}
                print(f"  held {(k + 1) * every} steps: {du} m, ratio "
                      f"{model.unbalanced_ratio():.2e}, cracks {int(model.cracks.count[0])}",
                      flush=True)
            os._exit(0)
        return res

    response.judge = held
    case, v = quick_variant(case_name)
    m = next(m for m in members(case, v, "response", 1) if m["label"] == label)
    case.run_member(m)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    sub = ap.add_subparsers(dest="what", required=True)
    a = sub.add_parser("levels")
    a.add_argument("--path", type=float, nargs="+", default=[1.0, 1.05, 1.0875])
    a.add_argument("--hold", type=int, default=200_000)
    b = sub.add_parser("member")
    b.add_argument("case")
    b.add_argument("label")
    b.add_argument("--steps", type=int, required=True)
    b.add_argument("--hold", type=int, default=200_000)
    args = ap.parse_args(argv)
    if args.what == "levels":
        levels(args.path, args.hold)
    else:
        member(args.case, args.label, args.steps, args.hold)


if __name__ == "__main__":
    main()
