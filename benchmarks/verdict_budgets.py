"""Does a case's answer move with its step budget? Each quick case member run with both
judges (``dem_core.settings.SolveSettings.judge``) at 1x and 2x the cap: "budget" (the cases'
judge, the verdict at ``max_steps``; every budget of the variant, its settings ending in
"steps", times the factor) and "response" (the verdict over windows of the measured response
time, ``dem_core/workflow/response.py``; the default ``windows``, ``SolveSettings().windows``,
times the factor).

    .venv/bin/python benchmarks/verdict_budgets.py [--cases adhikary underdip ...]
        [--judges budget response] [--solver JSON] [--out NAME] [--reference]

Per member: steps (all stages), seconds, each stage's verdict, the stages that did not stand,
the search's failure and last stable levels (its ``answer``); per judge: how many members give
the same answer at 2x as at 1x, and the steps over the budget judge's at 1x. The answers do
not depend on the machine; the seconds do (the machine is stamped). Writes
results/benchmarks/verdict_budgets.json (``--reference``: benchmarks/results/, the file
docs/performance.md quotes).
"""
from __future__ import annotations

import argparse
import importlib
import json
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from scenes import machine, write_json  # noqa: E402
from dem_core.settings import SolveSettings  # noqa: E402
from dem_core.workflow.stages import STOPS  # noqa: E402

CASES = ["adhikary", "longtan", "underdip", "coal_buckling", "highwood", "lornex",
         "checkerboard", "common_toppling"]


def answer(run: dict) -> dict:
    """What a member's run concluded: the stages that did not stand, its search's failure and
    last stable levels (a centrifuge ramp: its failure g and last stable g)."""
    if "stages" not in run:                               # a centrifuge ramp
        return {"failed_stages": [], "failure": run.get("failure_g"),
                "last_stable": run.get("last_stable_g")}
    search = run.get("search") or {}
    return {"failed_stages": [i for i, s in enumerate(run["stages"])
                              if s["verdict"] in STOPS],
            "failure": search.get("failure"), "last_stable": search.get("last_stable")}


def steps_and_verdicts(run: dict) -> tuple:
    """(steps of all stages or levels plus those of the response-time measurements, the
    verdicts)."""
    extra = int(run.get("measure_steps", 0))
    if "stages" not in run:
        return int(sum(run["level_steps"])) + extra, list(run["verdict"])
    return sum(s["steps"] for s in run["stages"]) + extra, [s["verdict"] for s in run["stages"]]


def members(case, v, judge, factor):
    """The quick members with the judge and the cap times ``factor``."""
    if judge == "budget":
        v = dict(v, **{k: int(round(x * factor)) for k, x in v.items()
                       if k.endswith("steps") and isinstance(x, int)})
    from comparisons import centrifuge
    out = (case.members(v, 1) if hasattr(case, "members") else
           case._members(v, 1) if hasattr(case, "_members") else centrifuge.ramp_members(v, 1))
    for m in out:
        m["judge"] = judge
        if judge == "response":
            m["windows"] = int(round(SolveSettings().windows * factor))
    return out


def quick_variant(name: str, solver=None) -> tuple:
    """(the case module, its quick variant without the continuum); ``solver``: Model options
    over the variant's (e.g. ``{"step_estimate": "auto"}``)."""
    from comparisons.cli import custom_variant
    case = importlib.import_module(f"comparisons.{name}")
    v = custom_variant(case, "quick", [])
    v["continuum"] = False if "continuum" in v else v.get("continuum")
    if solver:
        v["solver"] = {**v.get("solver", {}), **solver}
    return case, v


def measure(name: str, workers: int, judges=("budget", "response"), solver=None) -> dict:
    from comparisons.sweep import run_sweep
    case, v = quick_variant(name, solver)
    out = {"case": name, "members": []}
    runs = {}
    for judge in judges:
        for factor in (1, 2):
            key = f"{judge}_x{factor}"
            t0 = time.perf_counter()
            runs[key] = run_sweep(case.run_member, members(case, v, judge, factor),
                                  workers=workers)
            out[f"wall_s_{key}"] = round(time.perf_counter() - t0, 1)
    for i, b in enumerate(runs[f"{judges[0]}_x1"]):
        row = {"label": b["label"]}
        for key, rs in runs.items():
            steps, verdicts = steps_and_verdicts(rs[i])
            row[key] = {"steps": steps, "seconds": round(rs[i]["runtime_s"], 1),
                        "verdicts": verdicts, **answer(rs[i])}
        for judge in judges:
            row[f"same_{judge}"] = answer(runs[f"{judge}_x1"][i]) == answer(
                runs[f"{judge}_x2"][i])
        out["members"].append(row)
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cases", nargs="+", default=CASES, choices=CASES)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--judges", nargs="+", default=["budget", "response"],
                    choices=["budget", "response"], help="run only these judges")
    ap.add_argument("--solver", type=json.loads, default=None,
                    help='Model options over each variant\'s, e.g. \'{"step_estimate": "auto"}\'')
    ap.add_argument("--out", default="verdict_budgets", help="the result file's name")
    ap.add_argument("--reference", action="store_true")
    args = ap.parse_args(argv)
    result = {"machine": machine(), "solver": args.solver, "cases": []}
    for name in args.cases:
        r = measure(name, args.workers, tuple(args.judges), args.solver)
        result["cases"].append(r)
        print(json.dumps({k: r[k] for k in r if k != "members"}), flush=True)
        for m in r["members"]:
            print("  ", m["label"], {k: (m[k]["failure"], m[k]["last_stable"], m[k]["steps"])
                                     for k in m if k.endswith(("x1", "x2"))},
                  [m[f"same_{j}"] for j in args.judges], flush=True)
    total = {}
    rows = [m for c in result["cases"] for m in c["members"]]
    for judge in args.judges:
        total[judge] = {"members": len(rows), "same_at_2x": sum(m[f"same_{judge}"] for m in rows),
                        "steps_x1": sum(m[f"{judge}_x1"]["steps"] for m in rows)}
    if len(total) == 2:
        total["response_steps_over_budget"] = round(total["response"]["steps_x1"]
                                                    / max(1, total["budget"]["steps_x1"]), 3)
    result["total"] = total
    print(json.dumps(total))
    write_json(args.out, result, reference=args.reference)


if __name__ == "__main__":
    main()
