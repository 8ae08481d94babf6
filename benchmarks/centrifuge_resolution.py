"""Error against run time of the Adhikary centrifuge case: failure g by block size.

One damage-model g-ramp (flaw T = 1.1 MPa) per block edge length (40 g levels bisected to 5 g,
kinetic damping, a step limit per level that grows as the blocks get smaller), run through ``comparisons.adhikary.run_member`` (the case's own code). The error is
taken against the experiment's 80-85 g (zero inside the range) and the thesis's 70 g.

    python benchmarks/centrifuge_resolution.py [--edges 0.008 0.006 0.004]

Writes benchmarks/results/centrifuge_resolution.json and .png.
"""
from __future__ import annotations

import argparse
import json
import platform
from pathlib import Path

from comparisons.adhikary import run_member
from comparisons.results import metric_error

# edge (m) -> (g levels, steps per level): 40 g levels bisected to 5 g, the quick case's solver
# (kinetic damping); finer blocks settle more slowly (more blocks along a column: more steps
# per period of its lowest mode)
SETTINGS = {0.008: (list(range(40, 321, 40)), 30_000), 0.006: (list(range(40, 321, 40)), 40_000),
            0.004: (list(range(40, 321, 40)), 60_000), 0.003: (list(range(40, 321, 40)), 80_000)}
REFINE_TO = 5.0


def run(edge: float, seed: int = 1) -> dict:
    levels, steps = SETTINGS.get(edge, SETTINGS[0.004])
    r = run_member(dict(label=f"edge {edge}", params=dict(edge_length=edge, seed=seed,
                                                          flaw_tensile=1.1e6),
                        g_levels=levels, max_steps=steps, refine_to=REFINE_TO))
    return {"edge_m": edge, "blocks": r["blocks"], "contacts": r["contacts"],
            "g_step": levels[1] - levels[0], "g_resolution": REFINE_TO,
            "max_steps_per_level": steps,
            "failure_g": r["failure_g"], "last_stable_g": r["last_stable_g"],
            "seconds": r["runtime_s"],
            "error_vs_experiment": metric_error(r["failure_g"], [80.0, 85.0]),
            "error_vs_thesis": metric_error(r["failure_g"], 70.0)}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--edges", type=float, nargs="+", default=[0.008, 0.006, 0.004])
    a = ap.parse_args(argv)
    rows = []
    for edge in a.edges:
        rows.append(run(edge))
        print(json.dumps(rows[-1]), flush=True)
    out = Path(__file__).parent / "results"
    out.mkdir(exist_ok=True)
    (out / "centrifuge_resolution.json").write_text(json.dumps(
        {"machine": f"{platform.machine()} {platform.platform()}", "rows": rows}, indent=2))
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(5, 4))
    for r in rows:
        e = r["error_vs_experiment"]["rel_error"]
        ax.plot(r["seconds"], 100 * (e if e is not None else float("nan")), "o")
        ax.annotate(f"{1e3 * r['edge_m']:.0f} mm", (r["seconds"], 100 * (e or 0)))
    ax.set_xlabel("run time (s)")
    ax.set_ylabel("failure g error vs experiment (%)")
    ax.set_title("Adhikary centrifuge, damage model, T = 1.1 MPa")
    fig.tight_layout()
    fig.savefig(out / "centrifuge_resolution.png", dpi=110)


if __name__ == "__main__":
    main()
