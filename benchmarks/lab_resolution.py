"""Error against run time of the lab case (lajtai): UCS and one direct-shear envelope point.

Runs ``comparisons.lajtai.accuracy_study`` (the case's own code): the UCS test and the k = 0,
sn = 1.2 MPa direct-shear peak at several block edges (stiffness scaled by eq. 3.7) and, at the
thesis's 7 mm, several time-step safety factors; errors against the finest edge. Flaw cohesion
= Table 3.1's 1.2 MPa.

    python benchmarks/lab_resolution.py [--quick | --full]

quick: edges 5, 7, 11 mm, safety 0.3 and 0.9 at 7 mm; full: edges 4..14 mm. Writes
results/benchmarks/lab_resolution.json and .png (``--reference``: benchmarks/results/).
"""
from __future__ import annotations

import time

import scenes
from comparisons import lajtai
from comparisons.scenes import lajtai as lajtai_scene

EDGES = {"quick": [0.005, 0.007, 0.011], "full": [0.004, 0.005, 0.006, 0.007, 0.009, 0.011,
                                                   0.014]}


def main(argv=None):
    ap = scenes.quick_or_full_parser(__doc__.splitlines()[0])
    a = ap.parse_args(argv)
    mode = "full" if a.full else "quick"
    cfg = dict(lajtai.VARIANTS["quick"], seed=1, accuracy_edges=EDGES[mode],
               accuracy_safety=[0.3, 0.9], workers=1)
    t0 = time.perf_counter()
    study = lajtai.accuracy_study(cfg, lajtai_scene.THESIS_COHESION, print)
    out = {"machine": scenes.machine(), "mode": mode, "default": {"edge_m": 0.007, "safety": 0.5},
           **study, "wall_seconds": time.perf_counter() - t0}
    path = scenes.write_json("lab_resolution", out, a.reference)
    plot(out, scenes.results_dir(a.reference) / "lab_resolution.png")
    print(f"wrote {path}")


def plot(out, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    for ax, key, title in ((axes[0], "ucs", "UCS"), (axes[1], "shear", "shear peak, sn 1.2 MPa")):
        for r in out["rows"]:
            default = abs(r["edge_m"] - 0.007) < 1e-9 and r["safety"] == 0.5
            err = max(100 * r[f"{key}_rel_error"], 1e-2)        # the reference sits at 0
            ax.loglog(r[f"{key}_runtime_s"], err, "s" if default else "o",
                      color="red" if default else "C0", ms=8 if default else 5)
            ax.annotate(f"{r['edge_m'] * 1e3:g} mm" + ("" if r["safety"] == 0.5 else
                                                       f", sf {r['safety']:g}"),
                        (r[f"{key}_runtime_s"], err), fontsize=7)
        ax.set_xlabel("run time (s)")
        ax.set_ylabel("error vs finest edge (%)")
        ax.set_title(f"lajtai {title} (red: the thesis's 7 mm, safety 0.5)")
        ax.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


if __name__ == "__main__":
    main()
