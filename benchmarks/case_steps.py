"""Steps and seconds per case, before and after: each staged case's quick DEM runs on the
bounded time step (today's default) and on the step from the largest eigenvalue (issue 29
item 4, "report steps and seconds per case before and after").

    .venv/bin/python benchmarks/case_steps.py [--cases underdip lornex ...] [--solver JSON]

For each case (default: the six staged cases; adhikary and longtan, the centrifuge ramps, are
measured by ``fewer_steps.py``), the quick variant's sweep members (``members``; the continuum
is not run) are run twice through the case's own ``run_member``, two members side by side: with
``solver={}`` and with ``--solver`` (default ``{"step_estimate": "eigen"}``), the step budgets
unchanged; then a third time with ``--solver`` and every budget of the variant (its settings
ending in "steps") divided by the step's gain on the case (the smallest over the members of
the eigen critical step over the bounded one of the built model), so each solve covers the
simulated time it did before, as the adhikary and longtan quick variants do. With
``--spread`` (default 0.9 1.1) the bounded step runs again with every budget times each
factor: a member's answer on the eigen step counts as "in today's spread" when it equals one
of the bounded step's answers over these budgets (how the thirteenth session judged "the same
answer" for a chaotic search, docs/performance.md). Per member: steps (all stages), seconds, each stage's verdict, the stages that
failed and its search stage's failure and last stable levels; its answer is the same when the
last three match (``answer``). One JSON line a case
to stdout; all in benchmarks/results/case_steps.json and a figure, case_steps.png (steps and
seconds over before in both runs on the eigen step, per case, with how many members kept
their answer).
"""
from __future__ import annotations

import argparse
import importlib
import json
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
sys.path.insert(0, str(HERE.parent))

CASES = ["underdip", "coal_buckling", "highwood", "lornex", "checkerboard", "common_toppling"]


FAILED = ("failed", "unstable")


def answer(run: dict) -> dict:
    """What a member's run concluded: the stages that failed (their indices), and its search's
    failure and last stable levels. (Each stage's verdict is kept beside it: a solve that ends
    "moving" on one step and "equilibrium" on the other has the same answer.)"""
    search = run.get("search") or {}
    return {"failed_stages": [i for i, s in enumerate(run["stages"]) if s["verdict"] in FAILED],
            "failure": search.get("failure"), "last_stable": search.get("last_stable")}


def measure(name: str, solver: dict, workers: int, spread=(0.9, 1.1)) -> dict:
    """Both runs of case ``name``'s quick members (module docstring)."""
    from comparisons.cli import custom_variant
    from comparisons.sweep import run_sweep
    case = importlib.import_module(f"comparisons.{name}")
    v = custom_variant(case, "quick", [])
    if "continuum" in v:
        v["continuum"] = False
    out = {"case": name, "solver": solver, "members": []}
    runs = {}

    def sweep(key, settings):
        t0 = time.perf_counter()
        runs[key] = run_sweep(case.run_member, case.members(settings, 1), workers=workers)
        out[f"wall_s_{key}"] = round(time.perf_counter() - t0, 1)
    sweep("before", dict(v, solver={}))
    sweep("after", dict(v, solver=solver))
    # the step's gain on this case: the smallest over the members of the two built models'
    # critical steps; the budgets over it cover at least the old simulated time for each
    out["gain"] = round(min(a["critical_dt_start"] / b["critical_dt_start"]
                            for a, b in zip(runs["after"], runs["before"])), 3)
    out["budgets"] = {k: x for k, x in v.items() if k.endswith("steps") and isinstance(x, int)}
    sweep("same_time", dict(v, solver=solver, **{k: int(round(x / out["gain"]))
                                                  for k, x in out["budgets"].items()}))
    for f in spread:                  # today's own answers under another budget
        sweep(f"before_x{f:g}", dict(v, solver={}, **{k: int(round(x * f))
                                                      for k, x in out["budgets"].items()}))
    for i, b in enumerate(runs["before"]):
        row = {"label": b["label"]}
        for key in runs:
            r = runs[key][i]
            row[key] = {"steps": sum(s["steps"] for s in r["stages"]),
                        "seconds": round(r["runtime_s"], 1), **answer(r),
                        "verdicts": [s["verdict"] for s in r["stages"]]}
            row[f"same_answer_{key}"] = answer(b) == answer(r)
        todays = [answer(runs[k][i]) for k in runs if k.startswith("before")]
        for key in ("after", "same_time"):
            row[f"in_todays_spread_{key}"] = answer(runs[key][i]) in todays
        out["members"].append(row)
    for key in ("after", "same_time"):
        for what in ("steps", "seconds"):
            before = sum(m["before"][what] for m in out["members"])
            now = sum(m[key][what] for m in out["members"])
            out[f"{what}_ratio_{key}"] = round(now / before, 3) if before else None
        out[f"same_answers_{key}"] = sum(m[f"same_answer_{key}"] for m in out["members"])
        out[f"in_todays_spread_{key}"] = sum(m[f"in_todays_spread_{key}"]
                                             for m in out["members"])
    out["todays_own_changes"] = sum(
        not all(m[k]["failed_stages"] == m["before"]["failed_stages"] and
                m[k]["failure"] == m["before"]["failure"] and
                m[k]["last_stable"] == m["before"]["last_stable"]
                for k in m if k.startswith("before_x")) for m in out["members"])
    print(json.dumps({k: out[k] for k in out if k != "members"}), flush=True)
    return out


def figure(rows, path):
    """Bars per case: steps and seconds over before, on the eigen step with the same budgets
    and with the budgets over its gain; how many members kept their answer written above."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np
    fig, ax = plt.subplots(figsize=(10, 4.8))
    x = np.arange(len(rows))
    bars = (("steps_ratio_after", "steps, same budgets", "tab:blue", -0.3),
            ("seconds_ratio_after", "seconds, same budgets", "tab:cyan", -0.1),
            ("steps_ratio_same_time", "steps, budgets / gain", "tab:orange", 0.1),
            ("seconds_ratio_same_time", "seconds, budgets / gain", "tab:olive", 0.3))
    for key, label, color, shift in bars:
        ax.bar(x + shift, [r[key] for r in rows], 0.2, label=label, color=color)
    ax.axhline(0.5, color="tab:red", ls="--", lw=1, label="item 4's goal: half the steps")
    ax.axhline(1.0, color="k", lw=0.6)
    for i, r in enumerate(rows):
        n = len(r["members"])
        top = max(r[k] for k, *_ in bars)
        ax.text(i, top + 0.04, f"gain {r['gain']:.2f}\nsame answer: {r['same_answers_after']}/{n}"
                f" | {r['same_answers_same_time']}/{n}\nin today's spread: "
                f"{r.get('in_todays_spread_same_time', '-')}/{n}", ha="center", fontsize=7)
    ax.set_xticks(x, [r["case"] for r in rows], fontsize=8)
    ax.set_ylabel("eigen step / bounded step (all quick members)")
    ax.set_ylim(0, 1.75)
    ax.set_title("Quick DEM runs of the staged cases on the step from the largest eigenvalue "
                 "against the bounded step\nlabels: members with the bounded step's answer "
                 "(same budgets | budgets / gain);\nin today's spread: the budgets / gain "
                 "run's answer is one of the bounded step's at 0.9, 1 and 1.1 x its budgets",
                 fontsize=8)
    ax.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.09), ncol=5)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main(argv=None):
    from scenes import machine
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cases", nargs="+", default=CASES, choices=CASES)
    ap.add_argument("--solver", type=json.loads, default={"step_estimate": "eigen"})
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--spread", type=float, nargs="*", default=[0.9, 1.1],
                    help="also run the bounded step with every budget times each of these: "
                         "today's own answers under another budget")
    a = ap.parse_args(argv)
    rows = [measure(name, a.solver, a.workers, a.spread) for name in a.cases]
    (HERE / "results" / "case_steps.json").write_text(
        json.dumps({"machine": machine(), "cases": rows}, indent=1) + "\n")
    figure(rows, HERE / "results" / "case_steps.png")


if __name__ == "__main__":
    main()
