"""Steps and seconds per case, before and after: each staged case's quick DEM runs on the
bounded time step (today's default) and on the step from the largest eigenvalue (issue 29
item 4, "report steps and seconds per case before and after").

    .venv/bin/python benchmarks/trials/case_steps.py [--cases underdip lornex ...] [--solver JSON]

For each case (default: the six staged cases; adhikary and longtan, the centrifuge ramps, are
measured by ``fewer_steps.py``), the quick variant's sweep members (``members``; the continuum
is not run) are run through the case's own ``run_member``, two members side by side, each way
of ``WAYS`` against today's (``solver={}``, the variant's budgets):

- ``after``: ``--solver`` (default ``{"step_estimate": "eigen"}``), the budgets unchanged;
- ``same_time``: ``--solver`` with every budget of the variant (its settings ending in
  "steps") divided by the step's gain on the case (the smallest over the members of the eigen
  critical step over the bounded one of the built model), so each solve covers the simulated
  time it did before, as the adhikary and longtan quick variants do;
- ``settle`` (not with ``--no-settle``): today's step and budgets with the case's ``settle``
  setting, every solve and search level stopped once settled (``staged.settled_stages``);
- ``settle_same_time``: ``same_time`` with ``settle``.

With ``--reference`` (default 2) the bounded step runs again with every budget times that
factor: the answer of more simulated time a level, which each way's answer and today's own are
compared with (``as_reference_*``; the tenth session found a ramp's answer at today's budget to
be the budget's, and twice the budget's the better reference, docs/performance.md).
With ``--spread`` (default 0.9 1.1) the bounded step runs again with every budget times each
factor: a member's answer counts as "in today's spread" when it equals one of the bounded
step's answers over these budgets (how the thirteenth session judged "the same answer" for a
chaotic search, docs/performance.md). Per member: steps (all stages), seconds, each stage's
verdict, the stages that failed and its search stage's failure and last stable levels; its
answer is the same when the last three match (``answer``). One JSON line a case to stdout;
all in results/benchmarks/case_steps.json and a figure, case_steps.png (the committed record:
benchmarks/results/case_steps.json and .png) (per case and in all,
for each way: steps over today's, the share of members in today's spread and the share with
the reference's answer).
"""
from __future__ import annotations

import argparse
import importlib
import json
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
BENCHMARKS = HERE.parent                  # a trial uses the benchmarks' modules (trials/README.md)
sys.path.insert(0, str(BENCHMARKS))
sys.path.insert(0, str(BENCHMARKS.parent))

import outdir  # noqa: E402

CASES = ["underdip", "coal_buckling", "highwood", "lornex", "checkerboard", "common_toppling"]


FAILED = ("failed", "unstable")
# the runs compared with today's (the bounded step, the variant's budgets), and their labels
WAYS = {"after": "eigen step, same budgets", "same_time": "eigen step, budgets / gain",
        "settle": "settle, same budgets", "settle_same_time": "eigen step + settle, budgets / gain"}


def answer(run: dict) -> dict:
    """What a member's run concluded: the stages that failed (their indices), and its search's
    failure and last stable levels. (Each stage's verdict is kept beside it: a solve that ends
    "moving" on one step and "equilibrium" on the other has the same answer.)"""
    search = run.get("search") or {}
    return {"failed_stages": [i for i, s in enumerate(run["stages"]) if s["verdict"] in FAILED],
            "failure": search.get("failure"), "last_stable": search.get("last_stable")}


def measure(name: str, solver: dict, workers: int, spread=(0.9, 1.1), settle=True,
            reference=2.0) -> dict:
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

    def budgets(factor):              # every budget of the variant times ``factor``
        return {k: int(round(x * factor)) for k, x in out["budgets"].items()}
    over_gain = budgets(1.0 / out["gain"])
    sweep("same_time", dict(v, solver=solver, **over_gain))
    if settle:                        # every solve and level stopped once settled
        sweep("settle", dict(v, solver={}, settle=True))
        sweep("settle_same_time", dict(v, solver=solver, settle=True, **over_gain))
    for f in spread:                  # today's own answers under another budget
        sweep(f"before_x{f:g}", dict(v, solver={}, **budgets(f)))
    if reference:                     # the answer of more simulated time a level (module doc)
        out["reference_factor"] = reference
        sweep("reference", dict(v, solver={}, **budgets(reference)))
    for i, b in enumerate(runs["before"]):
        row = {"label": b["label"]}
        for key in runs:
            r = runs[key][i]
            row[key] = {"steps": sum(s["steps"] for s in r["stages"]),
                        "seconds": round(r["runtime_s"], 1), **answer(r),
                        "verdicts": [s["verdict"] for s in r["stages"]]}
            row[f"same_answer_{key}"] = answer(b) == answer(r)
        todays = [answer(runs[k][i]) for k in runs if k.startswith("before")]
        for key in WAYS:
            if key in runs:
                row[f"in_todays_spread_{key}"] = answer(runs[key][i]) in todays
        if reference:
            for key in ("before", *(k for k in WAYS if k in runs)):
                row[f"as_reference_{key}"] = answer(runs[key][i]) == answer(runs["reference"][i])
        out["members"].append(row)
    for key in (k for k in WAYS if k in runs):
        for what in ("steps", "seconds"):
            before = sum(m["before"][what] for m in out["members"])
            now = sum(m[key][what] for m in out["members"])
            out[f"{what}_ratio_{key}"] = round(now / before, 3) if before else None
        out[f"same_answers_{key}"] = sum(m[f"same_answer_{key}"] for m in out["members"])
        out[f"in_todays_spread_{key}"] = sum(m[f"in_todays_spread_{key}"]
                                             for m in out["members"])
    for key in ("before", *WAYS):
        if f"as_reference_{key}" in out["members"][0]:
            out[f"as_reference_{key}"] = sum(m[f"as_reference_{key}"] for m in out["members"])
    out["todays_own_changes"] = sum(
        not all(m[f"same_answer_before_x{f:g}"] for f in spread) for m in out["members"])
    print(json.dumps({k: out[k] for k in out if k != "members"}), flush=True)
    return out


def figure(rows, path):
    """Per case and in all, for each way of running (``WAYS``): steps over today's (left), the
    share of members whose answer is in today's spread (middle) and, with a reference run, the
    share whose answer is the reference's, today's own among them (right)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np
    ways = [k for k in WAYS if all(f"steps_ratio_{k}" in r for r in rows)]
    names = [r["case"] for r in rows] + ["all"]
    before = [sum(m["before"]["steps"] for m in r["members"]) for r in rows]
    n = [len(r["members"]) for r in rows]
    ref = all("as_reference_before" in r for r in rows)
    fig, axes = plt.subplots(1, 3 if ref else 2, figsize=(18 if ref else 13, 5.2))
    a1, a2 = axes[:2]
    x = np.arange(len(names))
    width = 0.8 / len(ways)
    colors = ("tab:blue", "tab:orange", "tab:green", "tab:purple")
    for w, (key, color) in enumerate(zip(ways, colors)):
        steps = [r[f"steps_ratio_{key}"] for r in rows]
        steps.append(sum(s * b for s, b in zip(steps, before)) / sum(before))
        spread = [r[f"in_todays_spread_{key}"] / k for r, k in zip(rows, n)]
        spread.append(sum(r[f"in_todays_spread_{key}"] for r in rows) / sum(n))
        shift = (w - (len(ways) - 1) / 2) * width
        a1.bar(x + shift, steps, width, color=color, label=WAYS[key])
        a2.bar(x + shift, spread, width, color=color, label=WAYS[key])
    if ref:
        a3 = axes[2]
        keys = ["before", *ways]
        width3 = 0.8 / len(keys)
        for w, (key, color) in enumerate(zip(keys, ("0.5", *colors))):
            share = [r[f"as_reference_{key}"] / k for r, k in zip(rows, n)]
            share.append(sum(r[f"as_reference_{key}"] for r in rows) / sum(n))
            a3.bar(x + (w - (len(keys) - 1) / 2) * width3, share, width3, color=color,
                   label="today" if key == "before" else None)
        a3.set_ylim(0, 1.05)
        a3.set_ylabel("members whose answer is the reference's")
        a3.set_title(f"Answers equal to the reference: today's step with "
                     f"{rows[0]['reference_factor']:g} x the budgets", fontsize=9)
    a1.axhline(0.5, color="tab:red", ls="--", lw=1, label="item 4's goal: half the steps")
    a1.axhline(1.0, color="k", lw=0.6)
    a1.set_ylabel("steps / today's steps (all quick members of the case)")
    a1.set_ylim(0, 1.2)
    a2.set_ylabel("members whose answer is in today's spread")
    a2.set_ylim(0, 1.05)
    for ax in axes:
        ax.set_xticks(x, [f"{c} ({k})" for c, k in zip(names, n + [sum(n)])], fontsize=8,
                      rotation=25, ha="right")
    a1.set_title("Steps over today's (bounded step, the variant's budgets)", fontsize=9)
    a2.set_title("Answers in today's spread (failed stages and search levels equal to\n"
                 "today's at 0.9, 1 or 1.1 x the budgets); (n): members", fontsize=9)
    handles, labels = a1.get_legend_handles_labels()
    if ref:
        h3, l3 = axes[2].get_legend_handles_labels()
        handles, labels = handles + h3, labels + l3
    fig.legend(handles, labels, fontsize=8, loc="lower center", ncol=6)
    fig.tight_layout(rect=(0, 0.07, 1, 1))
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main(argv=None):
    from scenes import machine
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cases", nargs="+", default=CASES, choices=CASES)
    ap.add_argument("--solver", type=json.loads, default={"step_estimate": "eigen"})
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--no-settle", action="store_true",
                    help="leave out the two runs with settle=True")
    ap.add_argument("--reference", type=float, default=2.0,
                    help="also run the bounded step with every budget times this (0: not): "
                         "the reference answer each way is compared with")
    ap.add_argument("--spread", type=float, nargs="*", default=[0.9, 1.1],
                    help="also run the bounded step with every budget times each of these: "
                         "today's own answers under another budget")
    a = ap.parse_args(argv)
    rows = [measure(name, a.solver, a.workers, a.spread, not a.no_settle, a.reference)
            for name in a.cases]
    (outdir.results_dir() / "case_steps.json").write_text(
        json.dumps({"machine": machine(), "cases": rows}, indent=1) + "\n")
    figure(rows, outdir.results_dir() / "case_steps.png")


if __name__ == "__main__":
    main()
