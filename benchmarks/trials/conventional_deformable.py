"""The thesis's conventional model of the centrifuge slopes: joints only, the columns between
them deformable (``dem_core.workflow.scene.conventional``), raised in g to failure.

    python benchmarks/trials/conventional_deformable.py --case adhikary --zone 0.005
    python benchmarks/trials/conventional_deformable.py --case adhikary --zone 0.005 --plastic
    python benchmarks/trials/conventional_deformable.py --case longtan --zone 0.004 --levels 100 300 20

The thesis's conventional UDEC failed at 115 g (Adhikary, thesis 4.2.3) and 146 g (Longtan,
4.3.3); the case modules' ``conventional`` members glue the Voronoi flaws of rigid blocks and
do not fail up to 300 / 600 g (docs/comparisons.md). Here the same scene (the cases' base run:
Adhikary 6 mm flaws, T 1.1 MPa, g raised in 10 g levels to 300 g; Longtan in its conventional
mode, with its persistent cross joints and smeared base cohesion) is built without its flaws,
every joint-bounded block meshed into constant-strain zones of ``--zone`` m (E, nu of the
blocks; elastic, or with ``--plastic`` Mohr-Coulomb with the flaws' c, phi and T, the intact
rock's strength the damage model uses: the thesis's conventional model had plastic zones,
its fig. 4.7 shows their plasticity indicators). Each block touching the model's base is held at its base gridpoints
(docs/mechanics.md, "Held deformable blocks").

Prints a line per level (g, verdict, steps, A's displacement, seconds) and a JSON line at the
end (failure g, last stable g, blocks, zones, steps, run time, machine); ``--out`` also writes
it to a file.
"""
from __future__ import annotations

import argparse
import json
import platform
import time

import numpy as np

from dem_core.workflow.scene import build_model, conventional
from dem_core.workflow.stages import RaiseGravity


def _scene(case):
    if case == "adhikary":
        from comparisons.scenes import adhikary
        return adhikary.base_run(), 115.0
    from comparisons.scenes import longtan
    p = longtan.LongtanParams(conventional=True)
    return longtan.scene(p), 146.0


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--case", choices=["adhikary", "longtan"], default="adhikary")
    ap.add_argument("--zone", type=float, default=0.005, help="zone size, m")
    ap.add_argument("--plastic", action="store_true",
                    help="Mohr-Coulomb zones with the flaws' strength (scene.conventional)")
    ap.add_argument("--levels", type=float, nargs=3, default=None, metavar=("FROM", "TO", "BY"),
                    help="g levels (default: the scene's ramp, or 20 to 600 by 20 for longtan)")
    ap.add_argument("--max-steps", type=int, default=None, help="step limit of a level")
    ap.add_argument("--refine-to", type=float, default=None, help="bisect the failure to, g")
    ap.add_argument("--out", default=None, help="JSON file")
    a = ap.parse_args()
    sc, thesis = _scene(a.case)
    ramp = sc.stages[0] if sc.stages else RaiseGravity(tuple(np.arange(20.0, 601.0, 20.0)),
                                                       max_steps=40_000,
                                                       failure_displacement=0.005, creep=2e-4,
                                                       watch=("A", "B"))
    levels = ramp.g_levels if a.levels is None else tuple(
        float(g) for g in np.arange(a.levels[0], a.levels[1] + 1e-9, a.levels[2]))
    ramp = RaiseGravity(levels, ratio=ramp.ratio, max_steps=a.max_steps or ramp.max_steps,
                        failure_displacement=ramp.failure_displacement, creep=ramp.creep,
                        watch=ramp.watch, refine_to=a.refine_to)
    t0 = time.perf_counter()
    model = build_model(conventional(sc, a.zone, plastic=a.plastic))
    z = model.zone_state
    print(f"{a.case} conventional, {'Mohr-Coulomb' if a.plastic else 'elastic'} zones {a.zone} m:"
          f" {model.n_blocks} blocks, "
          f"{len(z.area)} zones, {len(z.x)} gridpoints, dt {model.dt:.3g} s, "
          f"set-up {time.perf_counter() - t0:.1f} s", flush=True)

    def on_level(m, r):
        print(f"  {r.level[-1]:6.1f} g  {r.verdict[-1]:10s} {r.steps[-1]:7d} steps  "
              f"A {np.hypot(*m.point_motion('A')[:2]) * 1e3:7.3f} mm  "
              f"{time.perf_counter() - t0:7.0f} s", flush=True)

    steps, verdict, out = ramp.run(model, on_level=on_level)
    rec = out["ramp"]
    row = {"case": a.case, "zone_m": a.zone, "plastic": a.plastic,
           "yielded_zones": int((model.zone_state.yielded != 0).sum()), "blocks": model.n_blocks, "zones": len(z.area),
           "gridpoints": len(z.x), "dt_s": model.dt, "failure_g": rec.failure_g,
           "last_stable_g": rec.last_stable_g, "thesis_g": thesis, "verdict": verdict,
           "steps": steps, "runtime_s": round(time.perf_counter() - t0, 1),
           "error_vs_thesis": (None if rec.failure_g is None
                               else round(rec.failure_g / thesis - 1.0, 3)),
           "machine": platform.processor() or platform.machine()}
    print(json.dumps(row), flush=True)
    if a.out:
        with open(a.out, "w") as fh:
            json.dump(row, fh, indent=1)


if __name__ == "__main__":
    main()
