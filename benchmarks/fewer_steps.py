"""Steps to an answer with and without early settling (issue 29 item 4).

    python benchmarks/fewer_steps.py [--edges 0.006 0.004] [--workers 2]
    python benchmarks/fewer_steps.py --case longtan --edges 0.008 0.005 0.004 --workers 1
    python benchmarks/fewer_steps.py --case longtan --edges 0.008 --reference 2

The Adhikary base run (flaw T = 1.1 MPa, the full variant's ramp: 10 g levels, the failed level
bisected and closed in 1 g steps; ``benchmarks/centrifuge_resolution.member``) at each block
edge, once as today (every level that neither fails nor reaches the force ratio runs to its
step limit) and once with ``settle`` (a level stops as "settled" once it has hardly moved and
not cracked over two windows of a tenth of the step limit: ``dem_core.monitor.settled``).
Reports per run the failure g, the last stable g, steps, seconds and the levels' verdicts, and
per edge the ratio of steps and of seconds (settle / today) and the change of failure g.
Steps do not depend on the machine; seconds do (the machine is named in the JSON).
``--case longtan``: the Longtan base run the same way (its full variant's ramp and step limits).
``--reference K``: a third run per edge, today's search with K x the steps a level, whose
failure g tells whether today's answer is converged in its step budget (the reference the two
are judged against; docs/performance.md, "A settled level must be slowing down").

Writes benchmarks/results/fewer_steps.json (``fewer_steps_longtan.json`` for Longtan;
``..._reference.json`` with ``--reference``).
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
    ap.add_argument("--reference", type=float, default=0.0, metavar="K",
                    help="also run today's search with K x the steps a level (the reference "
                         "answer: is today's converged in its step budget?); 0: not")
    a = ap.parse_args(argv)
    members = []
    for edge in a.edges:
        for settle, budget in ((False, 1.0), (True, 1.0)) + (((False, a.reference),)
                                                              if a.reference > 0 else ()):
            m = member(edge, case=a.case)
            m["settle"] = settle
            m["max_steps"] = int(budget * m["max_steps"])
            m["budget"] = budget
            m["label"] += (" settle" if settle else " today") + (
                f" x{budget:g}" if budget != 1.0 else "")
            members.append(m)
    rows = []
    for m, r in zip(members, run_sweep(run_member, members, a.workers)):
        rows.append({"case": a.case, "edge_m": m["params"]["edge_length"], "settle": m["settle"],
                     "budget": m["budget"],
                     "max_steps_per_level": m["max_steps"], "blocks": r["blocks"],
                     "failure_g": r["failure_g"], "last_stable_g": r["last_stable_g"],
                     "steps": r["steps"], "seconds": round(r["runtime_s"], 1),
                     "g_run": r["g"], "verdicts": r["verdict"]})
        print(json.dumps(rows[-1]), flush=True)
    pairs = []
    for edge in a.edges:
        of = [r for r in rows if r["edge_m"] == edge]
        today, settle = of[0], of[1]
        pairs.append({"edge_m": edge,
                      "steps_ratio": round(settle["steps"] / today["steps"], 3),
                      "seconds_ratio": round(settle["seconds"] / today["seconds"], 3),
                      "failure_g_today": today["failure_g"],
                      "failure_g_settle": settle["failure_g"]})
        if len(of) > 2:
            pairs[-1]["failure_g_reference"] = of[2]["failure_g"]
            pairs[-1]["reference_budget"] = of[2]["budget"]
        print(json.dumps(pairs[-1]), flush=True)
    out = Path(__file__).parent / "results"
    out.mkdir(exist_ok=True)
    name = "fewer_steps" + ("" if a.case == "adhikary" else f"_{a.case}") + (
        "_reference" if a.reference > 0 else "") + ".json"
    (out / name).write_text(json.dumps(
        {"machine": f"{platform.machine()} {platform.platform()}", "workers": a.workers,
         "rows": rows, "pairs": pairs, **totals(rows)}, indent=2))


def totals(rows) -> dict:
    """Steps and seconds with settling over those without, summed over every edge."""
    def total(key, settle):
        return sum(r[key] for r in rows if r["settle"] == settle and r["budget"] == 1.0)
    return {f"{key}_ratio_all": round(total(key, True) / total(key, False), 3)
            for key in ("steps", "seconds")}


if __name__ == "__main__":
    main()
