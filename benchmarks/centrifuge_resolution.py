"""Error against run time of the Adhikary centrifuge case: failure g by block size.

One damage-model g-ramp (flaw T = 1.1 MPa) per block edge length with the full variant's solver
(10 g levels, the failed level bisected and the ramp closed in 1 g steps, the thesis's loading;
kinetic damping; a step limit per level that grows as the blocks get smaller), run through
``comparisons.adhikary.run_member`` (the case's own code), the block sizes spread over
``--workers`` processes. The error is taken against the experiment's 80-85 g (zero inside the
range) and the thesis's 70 g.

    python benchmarks/centrifuge_resolution.py [--edges 0.008 0.006 0.004] [--seeds 1]
                                               [--tensile 1.1] [--workers 2] [--edge-elements]

Every edge is run with every tessellation seed of ``--seeds`` (the scatter of one block size)
and every flaw tensile strength of ``--tensile`` (MPa; whether a T trend outlasts that scatter).
``--edge-elements`` runs the blocks' shared edges as linear elements (``Model(edge_elements=True)``:
the bending strength of a bonded edge no longer depends on the block size, issue 24 item 1).

Writes benchmarks/results/centrifuge_resolution.json and .png (``--name`` renames them).
"""
from __future__ import annotations

import argparse
import json
import platform
from pathlib import Path

from comparisons.adhikary import VARIANTS, run_member
from comparisons.results import metric_error
from comparisons.sweep import run_sweep

FULL = VARIANTS["full"]
# edge (m) -> steps per level: finer blocks settle more slowly (more blocks along a column:
# more steps per period of its lowest mode); 6 mm is the case's own setting
MAX_STEPS = {0.008: 30_000, 0.006: FULL["max_steps"], 0.004: 60_000, 0.003: 80_000}


def member(edge: float, seed: int = 1, tensile_mpa: float = 1.1,
           edge_elements: bool = False) -> dict:
    """The sweep member of one block size (the case's base run at another edge, seed or T)."""
    return dict(label=f"edge {edge} seed {seed} T {tensile_mpa}",
                solver=dict(edge_elements=edge_elements),
                params=dict(edge_length=edge, seed=seed, flaw_tensile=tensile_mpa * 1e6,
                            relax_iterations=FULL["relax_iterations"]),
                g_levels=FULL["g_levels"], max_steps=MAX_STEPS.get(edge, MAX_STEPS[0.003]),
                refine_to=FULL["refine_to"])


def row(m: dict, r: dict) -> dict:
    return {"edge_m": m["params"]["edge_length"], "seed": m["params"]["seed"],
            "flaw_tensile_mpa": m["params"]["flaw_tensile"] / 1e6,
            "edge_elements": m["solver"]["edge_elements"],
            "blocks": r["blocks"],
            "contacts": r["contacts"], "g_step": m["g_levels"][1] - m["g_levels"][0],
            "g_resolution": m["refine_to"], "max_steps_per_level": m["max_steps"],
            "failure_g": r["failure_g"], "last_stable_g": r["last_stable_g"],
            "levels": len(r["g"]), "steps": r["steps"], "seconds": r["runtime_s"],
            # the levels in the order run (bisection and the 1 g closing steps come last)
            "g_run": r["g"], "verdicts": r["verdict"],
            # the rupture surface of the failed state (comparisons.adhikary: experiment 12-20
            # degrees above the joint normal)
            "rupture": None if r.get("rupture") is None else {
                k: r["rupture"][k] for k in ("angle_above_joint_normal_deg", "depth_m",
                                             "n_cracks")},
            "error_vs_experiment": metric_error(r["failure_g"], [80.0, 85.0]),
            "error_vs_thesis": metric_error(r["failure_g"], 70.0)}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--edges", type=float, nargs="+", default=[0.008, 0.006, 0.004])
    ap.add_argument("--seeds", type=int, nargs="+", default=[1])
    ap.add_argument("--tensile", type=float, nargs="+", default=[1.1], help="flaw T (MPa)")
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--edge-elements", action="store_true",
                    help="shared edges as linear elements (Model(edge_elements=True))")
    ap.add_argument("--name", default="centrifuge_resolution",
                    help="file name of the results (without .json / .png)")
    a = ap.parse_args(argv)
    members = [member(edge, seed, t, a.edge_elements) for edge in a.edges for seed in a.seeds
               for t in a.tensile]
    rows = [row(m, r) for m, r in zip(members, run_sweep(run_member, members, a.workers))]
    for r in rows:
        print(json.dumps(r), flush=True)
    out = Path(__file__).parent / "results"
    out.mkdir(exist_ok=True)
    (out / f"{a.name}.json").write_text(json.dumps(
        {"machine": f"{platform.machine()} {platform.platform()}", "workers": a.workers,
         "rows": rows}, indent=2))
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(5, 4))
    for r in rows:
        e = r["error_vs_experiment"]["rel_error"]
        ax.plot(r["seconds"], 100 * (e if e is not None else float("nan")), "o")
        ax.annotate(f"{1e3 * r['edge_m']:.0f} mm, seed {r['seed']}, "
                    f"T {r['flaw_tensile_mpa']:g}",
                    (r["seconds"], 100 * (e or 0)))
    ax.set_xlabel("run time (s)")
    ax.set_ylabel("failure g error vs experiment (%)")
    ax.set_title("Adhikary centrifuge, damage model"
                 + (", edge elements" if a.edge_elements else ", end springs"))
    fig.tight_layout()
    fig.savefig(out / f"{a.name}.png", dpi=110)


if __name__ == "__main__":
    main()
