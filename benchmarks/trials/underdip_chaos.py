"""How far the quick underdip run's failure details move under a last-bit change of one input.

    python benchmarks/trials/underdip_chaos.py [--rel 0 2.2e-16 1e-12]

Runs ``comparisons.underdip.run("quick")`` once per relative change of the rock's density
(2500 (1 + rel) kg/m^3; rel = 2.2e-16 is one unit in the last place) and prints, per run, the
first failed cohesion (kPa) of the schedule at T = 0 and the toppled zone: the height of the
fastest block (fraction of H, ``start_height_fraction``), the lowest moving block's height and
the number of moving blocks. A quantity that moves under a 1-ULP change is chaotic: it cannot be
a finding, nor be asserted by a test. Writes results/benchmarks/underdip_chaos.json
(the committed record: benchmarks/results/underdip_chaos.json).
"""
from __future__ import annotations

import argparse
import dataclasses
import json
import platform
import time
from pathlib import Path

from comparisons import underdip
from comparisons.scenes import underdip as scene


def run(rel: float) -> dict:
    """The quick variant with the density scaled by (1 + rel)."""
    make = scene.UnderdipParams
    scene.UnderdipParams = lambda **kw: dataclasses.replace(make(**kw),
                                                            density=2500.0 * (1.0 + rel))
    try:
        t0 = time.perf_counter()
        dem = underdip.run("quick", seed=1).methods["dem"]
    finally:
        scene.UnderdipParams = make
    top = dem["toppled"] or {}
    return {"rel_density_change": rel, "c_failure_kPa": dem["c_failure_kPa"],
            "start_height_fraction": top.get("start_height_fraction"),
            "lowest_height_fraction": top.get("lowest_height_fraction"),
            "moving_blocks": top.get("blocks"), "seconds": time.perf_counter() - t0}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rel", type=float, nargs="+", default=[0.0, 2.2e-16, 1e-12])
    args = ap.parse_args(argv)
    rows = []
    for rel in args.rel:
        rows.append(run(rel))
        print(json.dumps(rows[-1]), flush=True)
    out = Path(__file__).resolve().parents[2] / "results" / "benchmarks" / "underdip_chaos.json"
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps({"machine": platform.processor() or platform.machine(),
                               "rows": rows}, indent=1))


if __name__ == "__main__":
    main()
