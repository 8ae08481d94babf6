"""Common toppling: T at rupture against the slope height fig 5.6 does not give (issue 54).

The case (``comparisons.common_toppling``) assumes a 120 m slope. A toppling column's
bending stress at its base grows as gamma H^2 / t (t the layer thickness, fixed at 6 m by the
thesis), so the T at which the table 5.2 model ruptures measures the assumed height as much
as the rock. This runs the quick's "6 m, table 5.2" member (3 m flaws in a 24 m zone, the
quick's T schedule 10 -> 7, 4, 2, 1, 0.5, 0.25 MPa refined to 0.25 MPa, the case's solver and
judge) at several heights (``ToppleParams.slope_height``; the 12 lifts are H / 12 high) and
prints, per height: T at rupture (first failed) and last stable, the rupture surface's length
against the height, cracks, blocks and run time; then the height at which the
gamma H^2 scaling of the 120 m answer reaches the thesis's 6.8-7 MPa. Writes
results/benchmarks/common_toppling_height.json and .png (``--reference``:
benchmarks/results/).

    python benchmarks/trials/common_toppling_height.py [--heights 120 180 240] [--workers 2]
        [--reference]
"""
from __future__ import annotations

import argparse
import json
import math
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
sys.path.insert(0, str(Path(__file__).resolve().parents[2]))

import outdir  # noqa: E402
from scenes import machine  # noqa: E402
from comparisons import common_toppling as case  # noqa: E402
from comparisons.scenes import common_toppling as scene  # noqa: E402
from comparisons.sweep import run_sweep  # noqa: E402
from comparisons.staged import stopped_before_search  # noqa: E402

MPA = 1e6
THESIS = (6.8, 7.0)             # MPa: 7 held, 6.8 ruptured (table 5.2, 6 m model)


def height_members(heights, seed: int = 1) -> list:
    """The quick's table 5.2 member at each height (m)."""
    v = case.VARIANTS["quick"]
    base = next(m for m in case.members(v, seed) if m["label"] == "6 m, table 5.2")
    out = []
    for h in heights:
        m = json.loads(json.dumps(base))
        m["params"]["slope_height"] = float(h)
        m["label"] = f"H = {h:g} m"
        out.append(m)
    return out


def row(run: dict) -> dict:
    """One height's answer (MPa, m, s). A run that stopped before its T schedule (a stage
    ended in ``STOPS``) failed at the T it had then: ``T_START`` once the study's strengths
    were set (``failed_before_schedule`` names the stage), None while still at the gravity
    stage's strength (the slope cannot stand at all)."""
    h = run["params"]["slope_height"]
    early = stopped_before_search(run)
    if early is None:
        stable, failed = case._t_at_rupture(run)
    else:
        assigned = any(s["kind"] == "change_material" for s in run["stages"][:early["stage"]])
        early["at_study_strength"] = assigned
        stable, failed = None, (case.T_START / MPA if assigned else None)
    rupture = run["rupture"]
    return {"height_m": h, "t_at_rupture_MPa": failed, "last_stable_MPa": stable,
            "failed_before_schedule": early,
            "rupture_length_m": None if rupture is None else rupture["length_m"],
            "through_going": case.has_rupture(run, h), "cracks": run["cracks"],
            "blocks": run["blocks"], "runtime_s": run["runtime_s"]}


def height_for(t_mpa: float, ref: dict) -> float | None:
    """Height (m) at which gamma H^2 / t scaling of ``ref``'s T at rupture reaches ``t_mpa``."""
    t0 = ref["t_at_rupture_MPa"]
    return None if not t0 else ref["height_m"] * math.sqrt(t_mpa / t0)


def figure(rows: list):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    fig, ax = plt.subplots(figsize=(7, 5.6))
    h = np.array([r["height_m"] for r in rows])
    failed = [(r["height_m"], r["t_at_rupture_MPa"]) for r in rows
              if r["t_at_rupture_MPa"] is not None and r["failed_before_schedule"] is None]
    early = [(r["height_m"], r["t_at_rupture_MPa"]) for r in rows
             if r["t_at_rupture_MPa"] is not None and r["failed_before_schedule"]]
    stable = [(r["height_m"], r["last_stable_MPa"]) for r in rows
              if r["last_stable_MPa"] is not None]
    if failed:
        ax.plot(*zip(*failed), "o-", color="C3", label="DEM: first failed T (rupture)")
    if early:
        ax.plot(*zip(*early), "v", ms=10, color="C3",
                label=f"DEM: fails at the schedule's start, T = {case.T_START / MPA:g} MPa")
    never = [r["height_m"] for r in rows if r["failed_before_schedule"]
             and not r["failed_before_schedule"]["at_study_strength"]]
    if never:
        ax.plot(never, [0.3] * len(never), "x", ms=10, mew=2, color="k",
                label="DEM: fails in the excavation, rock at 50 MPa (no T can hold it)")
    if stable:
        ax.plot(*zip(*stable), "^--", mfc="none", color="C0", label="DEM: last stable T")
    ref = next((r for r in rows if r["t_at_rupture_MPa"]
                and r["failed_before_schedule"] is None), None)
    if ref is not None:
        hh = np.linspace(h.min(), max(h.max(), height_for(THESIS[1], ref)), 100)
        ax.plot(hh, ref["t_at_rupture_MPa"] * (hh / ref["height_m"]) ** 2, ":", color="0.4",
                label=f"gamma H^2 scaling of the {ref['height_m']:g} m answer")
    ax.axhspan(*THESIS, color="C2", alpha=0.3, label="thesis, 6 m model: 6.8-7 MPa")
    ax.set_xlabel("slope height H (m; fig 5.6's is not given, the case assumes 120)")
    ax.set_ylabel("flaw tensile strength T (MPa)")
    ax.set_title("common toppling, 6 m layers, table 5.2, 3 m flaws: T at rupture vs height",
                 fontsize=9)
    ax.set_ylim(0, 1.1 * case.T_START / MPA)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7.5, loc="upper center", bbox_to_anchor=(0.5, -0.14), ncol=2)
    fig.tight_layout()
    return fig


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--heights", type=float, nargs="+", default=[120.0, 180.0, 240.0])
    ap.add_argument("--workers", type=int, default=2)
    outdir.add_reference_flag(ap)
    a = ap.parse_args(argv)
    bad = [h for h in a.heights if not (math.isfinite(h) and h >= 2 * scene.N_LIFTS)]
    if bad:
        raise SystemExit(f"--heights: each must be a finite height >= {2 * scene.N_LIFTS} m "
                         f"(12 lifts of at least 2 m), got {bad}")
    out = outdir.results_dir(a.reference)
    runs = run_sweep(case.run_member, height_members(a.heights), workers=a.workers,
                     progress=print)
    rows = sorted((row(r) for r in runs), key=lambda r: r["height_m"])
    ref = next((r for r in rows if r["height_m"] == scene.SLOPE_HEIGHT
                and r["t_at_rupture_MPa"]), None)
    result = {"machine": machine(), "member": "6 m, table 5.2 (quick)", "rows": rows,
              "thesis_MPa": THESIS,
              "height_for_thesis_by_scaling_m": None if ref is None else
              [height_for(t, ref) for t in THESIS]}
    (out / "common_toppling_height.json").write_text(json.dumps(result, indent=1))
    figure(rows).savefig(out / "common_toppling_height.png", dpi=120)
    print("H (m) | T at rupture | last stable | rupture (m) | through | cracks | blocks | s "
          "| failed before the schedule")
    for r in rows:
        print(f"{r['height_m']:g} | {r['t_at_rupture_MPa']} | {r['last_stable_MPa']} | "
              f"{r['rupture_length_m'] and round(r['rupture_length_m'], 1)} | "
              f"{r['through_going']} | {r['cracks']} | {r['blocks']} | {r['runtime_s']:.0f} | "
              f"{r['failed_before_schedule']}")
    print(f"gamma H^2 scaling reaches 6.8-7 MPa at H = "
          f"{result['height_for_thesis_by_scaling_m']} m; {out / 'common_toppling_height'}.png")


if __name__ == "__main__":
    main()
