"""The lab UCS floor of the lajtai case with deformable Voronoi blocks, against rigid ones.

    python benchmarks/trials/deformable_ucs.py                       # rigid, zones 3.5 mm
    python benchmarks/trials/deformable_ucs.py --zones 0 0.0035 0.00175 --cohesion 0.05e6 1.2e6
    python benchmarks/trials/deformable_ucs.py --calibrate --zones 0.0035 0.00175   # c for 4.1 MPa

Measured numbers: ``benchmarks/results/deformable_ucs.jsonl`` and docs/comparisons.md (lajtai,
"The UCS floor with deformable blocks").

Each run is the quick variant's unconfined compression test (``comparisons.lajtai``: the 2:1
Voronoi specimen, 7 mm blocks, seed 1, loading rate 1.5e-7 m per step, strain limit 2 %), its
scene's solver given ``deformable = {"rock": zone size}``: the specimen's blocks deformable, the
platens rigid (0: rigid blocks, the case as it is). At a flaw cohesion near zero the specimen breaks early
and its peak is the friction-and-interlock "floor" (docs/comparisons.md, lajtai: 4.41 MPa with
rigid blocks against the thesis's 4.1 MPa). Issue 24 asks whether deformable blocks, which the
thesis's UDEC had, bring it down. One JSON line per run: UCS (MPa), the strain at the peak,
cracks, steps, zones, run time (s), the machine. ``--calibrate`` runs the case's own cohesion
calibration (``comparisons.lab.calibrate_cohesion``, the thesis's 4.1 MPa to 2 %, from the
thesis's c = 1.2 MPa, at most 7 tests) at each zone size instead: one JSON line per zone size
with the calibrated c, its UCS, whether it converged and the history of (c, UCS).
"""
from __future__ import annotations

import argparse
import json
import platform
import time

from comparisons import lab
from comparisons.scenes import lajtai as scene
from dem_core.workflow.scene import build_model
from dem_core.workflow.stages import run_stages
from rounding_ucs import quick_ucs_scene


def ucs(zone, cohesion, seed=1):
    """One quick-variant UCS test with deformable blocks of zone size ``zone`` m (0: rigid)."""
    sc = quick_ucs_scene(cohesion, seed, **({"deformable": {"rock": zone}} if zone > 0 else {}))
    t0 = time.perf_counter()
    m = build_model(sc)
    records = run_stages(m, sc.stages)
    cv = lab.curve_of(records[-1], m, t0, 1.0 / scene.UCS_HEIGHT, "gauge",
                      1.0 / scene.UCS_WIDTH)
    return {"zone_m": zone, "cohesion_mpa": cohesion / 1e6, "ucs_mpa": round(cv.peak / 1e6, 4),
            "strain_at_peak": round(cv.x_at_peak, 6), "cracks": cv.cracks,
            "steps": cv.steps, "blocks": cv.n_blocks, "contacts": int(m.contacts.n),
            "zones": int(len(m.zone_state.area)),
            "runtime_s": round(time.perf_counter() - t0, 1),
            "machine": f"{platform.node()} {platform.machine()} {platform.processor()}"}


def calibrate(zone, seed=1):
    """The lajtai calibration (flaw c for UCS 4.1 MPa) with deformable blocks of ``zone`` m."""
    t0 = time.perf_counter()
    cal = lab.calibrate_cohesion(lambda c: ucs(zone, c, seed)["ucs_mpa"] * 1e6,
                                 scene.THESIS_UCS, scene.THESIS_COHESION, rel_tol=0.02,
                                 max_runs=7)
    return {"zone_m": zone, "calibrated_cohesion_mpa": round(cal["cohesion"] / 1e6, 4),
            "ucs_mpa": round(cal["ucs"] / 1e6, 4), "converged": cal["converged"],
            "history_mpa": [[round(c / 1e6, 4), round(u / 1e6, 4)] for c, u in cal["history"]],
            "runtime_s": round(time.perf_counter() - t0, 1),
            "machine": f"{platform.node()} {platform.machine()} {platform.processor()}"}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--zones", type=float, nargs="+", default=[0.0, 0.0035],
                    help="zone sizes, m (0: rigid blocks)")
    ap.add_argument("--cohesion", type=float, nargs="+", default=[0.05e6],
                    help="flaw cohesion(s), Pa (default 0.05 MPa: the floor)")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--calibrate", action="store_true",
                    help="calibrate the flaw cohesion to the thesis's UCS at each zone size")
    ap.add_argument("--out", default=None, help="append the JSON lines to this file")
    a = ap.parse_args()
    runs = ([(calibrate, z) for z in a.zones] if a.calibrate else
            [(lambda z, s, c=c: ucs(z, c, s), z) for c in a.cohesion for z in a.zones])
    for fn, z in runs:
            row = json.dumps(fn(z, a.seed))
            print(row, flush=True)
            if a.out:
                with open(a.out, "a") as fh:
                    fh.write(row + "\n")


if __name__ == "__main__":
    main()
