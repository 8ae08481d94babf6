"""Which judge is right where the two disagree? One quick member run on the budget judge with
its budgets times a large factor, printing each stage's and each search level's verdict,
steps and the watched points' displacement, so a "failing" (or "equilibrium") the response
judge gave can be checked against a much longer run.

    .venv/bin/python benchmarks/trials/long_budget_check.py CASE "MEMBER LABEL" --factor 8
        [--judge budget|response]

Writes results/benchmarks/long_budget_<case>_<label>_x<factor>_<judge>.json.
"""
from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
sys.path.insert(0, str(Path(__file__).resolve().parents[2]))

from verdict_budgets import answer, members, quick_variant  # noqa: E402


def main(argv=None):
    ap = argparse.ArgumentParser()
    ap.add_argument("case")
    ap.add_argument("label")
    ap.add_argument("--factor", type=float, default=8.0)
    ap.add_argument("--judge", default="budget", choices=["budget", "response"])
    a = ap.parse_args(argv)
    case, v = quick_variant(a.case)
    m, = [m for m in members(case, v, a.judge, a.factor) if m["label"] == a.label]
    t0 = time.perf_counter()
    run = case.run_member(m)
    out = {"case": a.case, "label": a.label, "factor": a.factor, "judge": a.judge,
           "wall_s": round(time.perf_counter() - t0, 1), "answer": answer(run),
           "stages": [{k: s[k] for k in s if k in ("kind", "verdict", "steps", "points")}
                      for s in run.get("stages", [])],
           "search": {k: run["search"][k] for k in run["search"]
                      if k in ("level", "verdict", "steps", "point_ux", "point_uy",
                               "failure", "last_stable")} if run.get("search") else None}
    print(json.dumps(out, indent=1, default=str))
    name = (f"long_budget_{a.case}_{a.label.replace(' ', '_').replace(',', '')}"
            f"_x{a.factor:g}_{a.judge}")
    folder = Path("results/benchmarks")
    folder.mkdir(parents=True, exist_ok=True)
    (folder / f"{name}.json").write_text(json.dumps(out, indent=1, default=str))


if __name__ == "__main__":
    main()
