"""What deformable blocks cost: a step, and a second of simulated time, against rigid blocks.

    python benchmarks/deformable_cost.py [--blocks 200] [--steps 2000]

The bonded Voronoi specimen of ``throughput.specimen`` (flaws kn 40 GPa/m, ks 20 GPa/m, the
thesis's plaster; density 1700; a fixed base; 50 g) is stepped with rigid blocks and with every
rock block deformable (``Model(deformable={"rock": h})``, block E 10 GPa, nu 0.25) for zone
sizes h of one and one half Voronoi edge (5 mm). After a warm-up (compile, first steps) the
timed run is ``--steps`` steps of ``Model.cycle``; the minimum of ``--reps`` alternating
rounds is kept. Reported: gridpoints and zones, time per step, the automatic time step (the
zones' own bound and the boundary gridpoints' share of the contact springs make it smaller),
and the cost of a simulated second relative to the rigid model; the last variant has mass
scaling (quasi-static runs: gridpoints stiffer than the blocks' median get heavier, so the
step is the rigid model's). One thread.
Writes results/benchmarks/deformable_cost.json (``--reference``: benchmarks/results/).
"""
from __future__ import annotations

import argparse
import json
import platform
import time

import outdir
import throughput


def _model(bs, size, mass_scaling=False):
    from dem_core.contact.materials import Material
    from dem_core.model import Model

    flaw = Material(kn=40e9, ks=20e9, tensile_strength=1.1e6, cohesion=1.2e6, friction=37)
    m = Model(bs, {"flaw:*": flaw, "boundary:*": flaw}, density=1700, history_every=10**9,
              block_E=10e9, block_nu=0.25,
              deformable=None if size is None else {"rock": size}, mass_scaling=mass_scaling)
    m.fix("base")
    m.set_gravity(50.0)
    return m


def main(blocks=200, steps=2000, reps=3, reference=False):
    bs = throughput.specimen(blocks)
    variants = {"rigid": None, "zones_5mm": 0.005, "zones_2.5mm": 0.0025,
                "zones_5mm_mass_scaled": 0.005}
    models = {k: _model(bs, h, k.endswith("mass_scaled")) for k, h in variants.items()}
    for m in models.values():
        m.cycle(200)                                   # compile, first steps
    best = {k: float("inf") for k in variants}
    for _ in range(reps):
        for k, m in models.items():
            t0 = time.perf_counter()
            m.cycle(steps)
            best[k] = min(best[k], (time.perf_counter() - t0) / steps)
    rigid = models["rigid"]
    rows = {}
    for k, m in models.items():
        z = m.zone_state
        rows[k] = {"zone_size_m": variants[k], "gridpoints": int(z.mass.shape[0]),
                   "zones": int(z.area.shape[0]), "contacts": int(m.contacts.n),
                   "us_per_step": round(1e6 * best[k], 2),
                   "step_cost_vs_rigid": round(best[k] / best["rigid"], 2),
                   "dt_s": m.dt, "dt_vs_rigid": round(m.dt / rigid.dt, 4),
                   "cost_per_simulated_s_vs_rigid": round(
                       (best[k] / m.dt) / (best["rigid"] / rigid.dt), 1)}
    out = {"benchmark": "deformable_cost", "blocks": int(bs.n_blocks), "steps": steps,
           "reps": reps, "threads": 1,
           "machine": f"{platform.node()} {platform.machine()} {platform.platform()}",
           "date": time.strftime("%Y-%m-%d"), "variants": rows}
    path = outdir.results_dir(reference) / "deformable_cost.json"
    path.write_text(json.dumps(out, indent=1) + "\n")
    print(json.dumps(out, indent=1))
    return out


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--blocks", type=int, default=200)
    ap.add_argument("--steps", type=int, default=2000)
    ap.add_argument("--reps", type=int, default=3)
    outdir.add_reference_flag(ap)
    a = ap.parse_args()
    main(a.blocks, a.steps, a.reps, a.reference)
