"""The lab UCS of the lajtai case with rounded corners (``Model(rounding=d)``), against sharp.

    python benchmarks/trials/rounding_ucs.py                         # d = 0, 1 %, 3 % of the edge
    python benchmarks/trials/rounding_ucs.py --fractions 0 0.01 --cohesion 0.05e6 1.2e6

Measured numbers: ``benchmarks/results/rounding_ucs.json`` and docs/comparisons.md (lajtai).

Each run is the quick variant's unconfined compression test (``comparisons.lajtai``: the 2:1
Voronoi specimen, 7 mm blocks, seed 1, loading rate 1.5e-7 m per step, strain limit 2 %) with
the scene's solver given ``rounding = fraction x edge length``. At a flaw cohesion near zero
the specimen breaks early and its peak is the friction-and-interlock "floor" of
docs/comparisons.md (lajtai, problem 2: 4.41-4.42 MPa sharp, the thesis 4.1 MPa). One JSON
line per run: UCS (MPa), the strain at the peak, cracks, steps, run time (s), the machine.
"""
from __future__ import annotations

import argparse
import dataclasses
import json
import platform
import time

from comparisons import lab, lajtai
from comparisons.scenes import lajtai as scene
from dem_core.workflow.scene import build_model
from dem_core.workflow.stages import run_stages


def quick_ucs_scene(cohesion, seed=1, **solver):
    """The quick variant's UCS test as a scene (the case's own, ``lajtai.ucs_scene_of``; the
    thesis's flaws with ``cohesion``, Pa), its solver options updated with ``solver``."""
    sc = lajtai.ucs_scene_of(lajtai.ucs_query(dict(lajtai.VARIANTS["quick"], seed=seed),
                                              cohesion))
    return dataclasses.replace(sc, solver={**sc.solver, **solver})


def ucs(fraction, cohesion, seed=1):
    """One quick-variant UCS test with rounding = fraction x the block edge; a dict."""
    edge = lajtai.VARIANTS["quick"]["ucs_edge"]
    sc = quick_ucs_scene(cohesion, seed, rounding=fraction * edge)
    t0 = time.perf_counter()
    m = build_model(sc)
    records = run_stages(m, sc.stages)
    cv = lab.curve_of(records[-1], m, t0, 1.0 / scene.UCS_HEIGHT, "gauge",
                      1.0 / scene.UCS_WIDTH)
    return {"rounding_fraction_of_edge": fraction, "rounding_m": fraction * edge,
            "cohesion_mpa": cohesion / 1e6, "ucs_mpa": round(cv.peak / 1e6, 4),
            "strain_at_peak": round(cv.x_at_peak, 6), "cracks": cv.cracks,
            "steps": cv.steps, "blocks": cv.n_blocks, "contacts": int(m.contacts.n),
            "runtime_s": round(time.perf_counter() - t0, 1),
            "machine": f"{platform.node()} {platform.machine()} {platform.processor()}"}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--fractions", type=float, nargs="+", default=[0.0, 0.01, 0.03])
    ap.add_argument("--cohesion", type=float, nargs="+", default=[0.05e6],
                    help="flaw cohesion(s), Pa (default 0.05 MPa: the floor)")
    ap.add_argument("--seed", type=int, default=1)
    a = ap.parse_args()
    for c in a.cohesion:
        for f in a.fractions:
            print(json.dumps(ucs(f, c, a.seed)), flush=True)


if __name__ == "__main__":
    main()
