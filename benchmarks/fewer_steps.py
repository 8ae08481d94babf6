"""Steps to an answer with and without early settling (issue 29 item 4).

    python benchmarks/fewer_steps.py [--edges 0.006 0.004] [--workers 2]
    python benchmarks/fewer_steps.py --case longtan --edges 0.008 0.005 0.004 --workers 1

The Adhikary base run (flaw T = 1.1 MPa, the full variant's ramp: 10 g levels, the failed level
bisected and closed in 1 g steps; ``benchmarks/centrifuge_resolution.member``) at each block
edge, once as today (every level that neither fails nor reaches the force ratio runs to its
step limit) and once with ``settle`` (a level stops as "settled" once it has hardly moved and
not cracked over two windows of a tenth of the step limit: ``dem_core.monitor.settled``).
Reports per run the failure g, the last stable g, steps, seconds and the levels' verdicts, and
per edge the ratio of steps and of seconds (settle / today) and the change of failure g.
Steps do not depend on the machine; seconds do (the machine is named in the JSON).
``--case longtan``: the Longtan base run the same way (its full variant's ramp and step limits).

Writes benchmarks/results/fewer_steps.json (``fewer_steps_longtan.json`` for Longtan).
"""
from __future__ import annotations

import argparse
import json
import platform
from pathlib import Path

from centrifuge_resolution import member, run_member
from comparisons.sweep import run_sweep


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--edges", type=float, nargs="+", default=[0.006, 0.004])
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--case", choices=("adhikary", "longtan"), default="adhikary")
    a = ap.parse_args(argv)
    members = []
    for edge in a.edges:
        for settle in (False, True):
            m = member(edge, case=a.case)
            m["settle"] = settle
            m["label"] += " settle" if settle else " today"
            members.append(m)
    rows = []
    for m, r in zip(members, run_sweep(run_member, members, a.workers)):
        rows.append({"case": a.case, "edge_m": m["params"]["edge_length"], "settle": m["settle"],
                     "max_steps_per_level": m["max_steps"], "blocks": r["blocks"],
                     "failure_g": r["failure_g"], "last_stable_g": r["last_stable_g"],
                     "steps": r["steps"], "seconds": round(r["runtime_s"], 1),
                     "g_run": r["g"], "verdicts": r["verdict"]})
        print(json.dumps(rows[-1]), flush=True)
    pairs = []
    for today, settle in zip(rows[::2], rows[1::2]):
        pairs.append({"edge_m": today["edge_m"],
                      "steps_ratio": round(settle["steps"] / today["steps"], 3),
                      "seconds_ratio": round(settle["seconds"] / today["seconds"], 3),
                      "failure_g_today": today["failure_g"],
                      "failure_g_settle": settle["failure_g"]})
        print(json.dumps(pairs[-1]), flush=True)
    out = Path(__file__).parent / "results"
    out.mkdir(exist_ok=True)
    name = "fewer_steps.json" if a.case == "adhikary" else f"fewer_steps_{a.case}.json"
    (out / name).write_text(json.dumps(
        {"machine": f"{platform.machine()} {platform.platform()}", "workers": a.workers,
         "rows": rows, "pairs": pairs, **totals(rows)}, indent=2))


def totals(rows) -> dict:
    """Steps and seconds with settling over those without, summed over every edge."""
    def total(key, settle):
        return sum(r[key] for r in rows if r["settle"] == settle)
    return {f"{key}_ratio_all": round(total(key, True) / total(key, False), 3)
            for key in ("steps", "seconds")}


if __name__ == "__main__":
    main()
