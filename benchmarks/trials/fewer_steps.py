"""Steps to an answer with and without early settling (issue 29 item 4).

    python benchmarks/trials/fewer_steps.py [--edges 0.006 0.004] [--workers 2]
    python benchmarks/trials/fewer_steps.py --case longtan --edges 0.008 0.005 0.004 --workers 1
    python benchmarks/trials/fewer_steps.py --case longtan --edges 0.008 --reference 2
    python benchmarks/trials/fewer_steps.py --edges 0.006 0.004 --budgets 0.9 1 1.1
    python benchmarks/trials/fewer_steps.py --replot fewer_steps_budgets
    python benchmarks/trials/fewer_steps.py --edges 0.006 0.004 --budgets 0.9 1 1.1 \
        --solver '{"step_estimate": "eigen"}' --today fewer_steps_budgets

The Adhikary base run (flaw T = 1.1 MPa, the full variant's ramp: 10 g levels, the failed level
bisected and closed in 1 g steps; ``benchmarks/centrifuge_resolution.member``) at each block
edge, once as today (every level that neither fails nor reaches the force ratio runs to its
step limit) and once with ``settle`` (a level stops as "settled" once it has hardly moved and
not cracked over two windows of a tenth of the step limit: ``dem_core.output.monitor.settled``).
Reports per run the failure g, the last stable g, steps (and those of the failed levels),
seconds and the levels' verdicts, and per edge the ratio of steps and of seconds (settle /
today) and the change of failure g.
Steps do not depend on the machine; seconds do (the machine is named in the JSON).
``--case longtan``: the Longtan base run the same way (its full variant's ramp and step limits).
``--reference K``: a third run per edge, today's search with K x the steps a level, whose
failure g tells whether today's answer is converged in its step budget (the reference the two
are judged against; docs/performance.md, "A settled level must be slowing down").
``--solver JSON``: further ``Model`` options for the settling search only (e.g.
``{"step_estimate": "eigen"}``: the step from the largest eigenvalue, ``dem_core.step.critical_step``),
so the pair compares today's search with settling on that solver; the file name gets the
options' values. ``--today NAME``: take today's runs (same edges and budgets) from
``results/NAME.json`` instead of running them again (their steps and answers do not depend on
the machine; their seconds were taken then, so the seconds ratio is across runs).
``--budgets B ...``: both searches at each of these multiples of the steps a level. A change of
budget that changes no physics moves the failure g by the model's own reproducibility; the
spread of today's answers over the budgets is what "the same answer" can be judged against
(docs/performance.md, "How reproducible today's answer is"). The figure (same name, .png)
shows failure g against steps, one panel per edge.

Writes results/benchmarks/fewer_steps.json (``fewer_steps_longtan.json`` for Longtan;
``..._reference.json`` with ``--reference``, ``..._budgets.json`` with ``--budgets``); the
committed records of 2026-11-27 that docs/performance.md quotes are in benchmarks/results/.
"""
from __future__ import annotations

import argparse
import json
import platform
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # the benchmarks (trials/README.md)

import outdir  # noqa: E402
from centrifuge_resolution import member, run_member  # noqa: E402
from comparisons.sweep import run_sweep  # noqa: E402


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--edges", type=float, nargs="+", default=[0.006, 0.004])
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--case", choices=("adhikary", "longtan"), default="adhikary")
    ap.add_argument("--reference", type=float, default=0.0, metavar="K",
                    help="also run today's search with K x the steps a level (the reference "
                         "answer: is today's converged in its step budget?); 0: not")
    ap.add_argument("--budgets", type=float, nargs="+", default=[1.0], metavar="B",
                    help="run both searches at each of these multiples of the steps a level "
                         "(today's reproducibility under a change that changes no physics)")
    ap.add_argument("--solver", type=json.loads, default={}, metavar="JSON",
                    help="Model options for the settling search, e.g. "
                         "'{\"step_estimate\": \"eigen\"}'")
    ap.add_argument("--today", metavar="NAME",
                    help="reuse today's runs from NAME.json (results/benchmarks/, else "
                         "the committed benchmarks/results/)")
    ap.add_argument("--replot", metavar="NAME",
                    help="run nothing: draw NAME.json's rows (as --today) into NAME.png")
    a = ap.parse_args(argv)
    out = outdir.results_dir()
    if a.replot:
        rows = json.loads(outdir.find(f"{a.replot}.json").read_text())["rows"]
        for r in rows:          # files written before --budgets: no reference flag
            r.setdefault("reference", r["budget"] != 1.0 and not r["settle"])
        figure(rows, rows[0]["case"], out / f"{a.replot}.png")
        return
    if any(not b > 0 for b in a.budgets) or a.reference < 0 or a.reference in a.budgets:
        ap.error(f"budgets must be > 0 and --reference (0: none) one that is not among them, "
                 f"got {a.budgets}, {a.reference}")
    stored = _stored_today(out, a.today, a.edges, a.budgets) if a.today else []
    runs = [(settle, b) for b in a.budgets for settle in ((True,) if a.today else (False, True))]
    runs += [(False, a.reference)] if a.reference > 0 else []
    members = []
    for edge in a.edges:
        for settle, budget in runs:
            m = member(edge, case=a.case)
            m["settle"] = settle
            if settle:
                m["solver"] = {**m["solver"], **a.solver}
            m["max_steps"] = int(budget * m["max_steps"])
            m["budget"] = budget
            m["reference"] = not settle and budget == a.reference
            m["label"] += (" settle" if settle else " today") + (
                f" x{budget:g}" if budget != 1.0 else "")
            members.append(m)
    rows = list(stored)
    for m, r in zip(members, run_sweep(run_member, members, a.workers)):
        failed = sum(k for k, v in zip(r["level_steps"], r["verdict"]) if v == "failed")
        rows.append({"case": a.case, "edge_m": m["params"]["edge_length"], "settle": m["settle"],
                     "solver": a.solver if m["settle"] else {},
                     "budget": m["budget"], "reference": m["reference"],
                     "max_steps_per_level": m["max_steps"], "blocks": r["blocks"],
                     "failure_g": r["failure_g"], "last_stable_g": r["last_stable_g"],
                     "steps": r["steps"], "failed_level_steps": failed,
                     "seconds": round(r["runtime_s"], 1),
                     "g_run": r["g"], "verdicts": r["verdict"], "level_steps": r["level_steps"],
                     # numerical blow-ups: of a failing level (counted as failed), or at rest
                     "blowups": r.get("blowups") or [], "unstable": r.get("unstable")})
        print(json.dumps(rows[-1]), flush=True)
    pairs = [pair(rows, edge, b) for edge in a.edges for b in a.budgets]
    for p in pairs:
        print(json.dumps(p), flush=True)
    spread = [spread_of(rows, edge) for edge in a.edges]
    name = "fewer_steps" + ("" if a.case == "adhikary" else f"_{a.case}") + (
        "_reference" if a.reference > 0 else "") + ("_budgets" if a.budgets != [1.0] else "") + (
        "".join(f"_{v}" for v in a.solver.values()))
    (out / f"{name}.json").write_text(json.dumps(
        {"machine": f"{platform.machine()} {platform.platform()}", "workers": a.workers,
         "rows": rows, "pairs": pairs, "spread": spread, **totals(rows)}, indent=2))
    figure(rows, a.case, out / f"{name}.png")


def _stored_today(out, name, edges, budgets) -> list:
    """Today's rows (no settling, not the reference) of ``<name>.json`` (``outdir.find``) at
    these edges and budgets, each marked ``reused``; SystemExit naming what is missing."""
    rows = json.loads(outdir.find(f"{name}.json").read_text())["rows"]
    keep = [dict(r, reused=name) for r in rows if not r["settle"] and not r.get("reference")
            and r["edge_m"] in edges and r["budget"] in budgets]
    have = {(r["edge_m"], r["budget"]) for r in keep}
    missing = [(e, b) for e in edges for b in budgets if (e, b) not in have]
    if missing:
        raise SystemExit(f"{name}.json has no today's run at (edge, budget) {missing}")
    return keep


def pair(rows, edge, budget) -> dict:
    """Settle against today at one edge and budget: ratios of steps and seconds, failure g."""
    of = [r for r in rows if r["edge_m"] == edge and r["budget"] == budget and not
          r["reference"]]
    today, settle = [next(r for r in of if r["settle"] == s) for s in (False, True)]
    out = {"edge_m": edge, "budget": budget,
           "steps_ratio": round(settle["steps"] / today["steps"], 3),
           "seconds_ratio": round(settle["seconds"] / today["seconds"], 3),
           "failure_g_today": today["failure_g"], "failure_g_settle": settle["failure_g"]}
    ref = [r for r in rows if r["edge_m"] == edge and r["reference"]]
    if ref:
        out["failure_g_reference"] = ref[0]["failure_g"]
        out["reference_budget"] = ref[0]["budget"]
    return out


def spread_of(rows, edge) -> dict:
    """Per search, over the budgets at one edge: the failure g's range and mean (None for a
    run that stood to the last level counts as no answer) and the steps summed."""
    out = {"edge_m": edge}
    for key, settle in (("today", False), ("settle", True)):
        of = [r for r in rows if r["edge_m"] == edge and r["settle"] == settle
              and not r["reference"]]
        g = [r["failure_g"] for r in of if r["failure_g"] is not None]
        out[key] = {"budgets": [r["budget"] for r in of], "failure_g": [r["failure_g"] for r in of],
                    "min_g": min(g) if g else None, "max_g": max(g) if g else None,
                    "mean_g": round(sum(g) / len(g), 3) if g else None,
                    "steps": sum(r["steps"] for r in of)}
    out["steps_ratio"] = round(out["settle"]["steps"] / out["today"]["steps"], 3)
    return out


def totals(rows) -> dict:
    """Steps and seconds with settling over those without, summed over every edge and budget
    (the reference runs left out)."""
    def total(key, settle):
        return sum(r[key] for r in rows if r["settle"] == settle and not r["reference"])
    return {f"{key}_ratio_all": round(total(key, True) / total(key, False), 3)
            for key in ("steps", "seconds")}


def figure(rows, case, path):
    """Failure g against steps to the answer, one panel per edge: today's searches (circles),
    settling ones (triangles), the reference (square), each marked with its budget."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    edges = sorted({r["edge_m"] for r in rows}, reverse=True)
    fig, axes = plt.subplots(1, len(edges), figsize=(5.5 * len(edges), 5.4), squeeze=False)
    budgets = sorted({r["budget"] for r in rows if not r["reference"]})
    for ax, edge in zip(axes[0], edges):
        for r in (r for r in rows if r["edge_m"] == edge):
            style = ("s", "k", "today, reference budget") if r["reference"] else (
                ("^", "tab:orange", "settling" + "".join(f", {k} {v}" for k, v in
                                                         r.get("solver", {}).items()))
                if r["settle"] else ("o", "tab:blue", "today"))
            g = r["failure_g"] if r["failure_g"] is not None else float("nan")
            ax.plot(r["steps"] / 1e3, g, style[0], color=style[1], ms=8, label=style[2])
            # labels of neighbouring budgets apart: above, below, further above
            i = budgets.index(r["budget"]) % 3 if r["budget"] in budgets else 0
            ax.annotate(f"x{r['budget']:g}", (r["steps"] / 1e3, g), textcoords="offset points",
                        xytext=(6, (5, -12, 14)[i]), fontsize=8)
        g = [r["failure_g"] for r in rows if r["edge_m"] == edge and not r["settle"]
             and not r["reference"] and r["failure_g"] is not None]
        if len(g) > 1:
            ax.axhspan(min(g), max(g), color="tab:blue", alpha=0.1,
                       label="today's answers' range over the budgets")
        handles, labels = ax.get_legend_handles_labels()
        keep = {l: h for h, l in zip(handles, labels)}
        ax.legend(keep.values(), keep.keys(), fontsize=8, loc="upper center",  # off the data
                  bbox_to_anchor=(0.5, -0.16), ncol=2)
        ax.set_xlabel("steps to the answer (thousands)")
        ax.set_ylabel("failure g")
        ax.set_xlim(0, 1.12 * max(r["steps"] for r in rows if r["edge_m"] == edge) / 1e3)
        ax.margins(y=0.15)
        ax.set_title(f"{case}, {edge * 1e3:g} mm blocks (xB: B times today's steps a level)",
                     fontsize=9)
        ax.grid(alpha=0.3)
    fig.suptitle("Early settling against today's search: the answer and its cost", fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


if __name__ == "__main__":
    main()
