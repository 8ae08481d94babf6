"""What softening flaws (``dem_core/contact/softening.py``) cost against brittle ones, side by
side in one run.

    python benchmarks/softening_cost.py --blocks 100000        # one JSON line per size
    python benchmarks/softening_cost.py --blocks 10000 100000 --steps 300

The specimen is benchmarks/throughput.py's bonded Voronoi square under 50 g, with weak flaws
(T 0.02 MPa, c 0.05 MPa: ``WEAK``), once brittle (today's law) and once with fracture energies
G_I = 1 J/m^2 and G_II = 10 J/m^2 (linear). Both models are built, warmed up and then timed in turns
(``--repeats``, the best of each kept), so that both see the same machine. Reported: seconds per
step and ns per contact update of each, their ratio, and the contacts on the softening branch
(kappa > 0) at the end, so that the branch itself is seen to be exercised, not only the test the
elastic path makes.
"""
from __future__ import annotations

import argparse
import json
import platform
import time


# flaws weak enough that those near the base pass their peak within the timed steps at 50 g
WEAK = dict(kn=40e9, ks=20e9, tensile_strength=0.02e6, cohesion=0.05e6, friction=37.0)
G_I, G_II = 1.0, 10.0          # J/m^2 (200 and 160 times the snap-back limits)


def models(n_blocks):
    from throughput import loaded, specimen
    from dem_core.contact.materials import Material

    bs = specimen(n_blocks)
    brittle, m = loaded(bs), loaded(bs)
    for model, flaw in ((brittle, Material(**WEAK)),
                        (m, Material(**WEAK, fracture_energy_I=G_I, fracture_energy_II=G_II))):
        for name in list(model.materials):
            model.materials[name] = flaw
            model.set_material(name)         # the table is made again from the materials
    return bs, brittle, m


def measure(n_blocks, steps, repeats, warmup):
    bs, brittle, soft = models(n_blocks)
    for m in (brittle, soft):
        m.cycle(warmup)                      # compile, and load until flaws soften
    best = {"brittle": float("inf"), "softening": float("inf")}
    for _ in range(repeats):
        for name, m in (("brittle", brittle), ("softening", soft)):
            t0 = time.perf_counter()
            m.cycle(steps)
            best[name] = min(best[name], (time.perf_counter() - t0) / steps)
    nc = soft.contacts.n
    return {"blocks": int(bs.n_blocks), "contacts": int(nc), "steps": steps,
            "repeats": repeats,
            "brittle_s_per_step": best["brittle"], "softening_s_per_step": best["softening"],
            "brittle_ns_per_contact": round(1e9 * best["brittle"] / brittle.contacts.n, 2),
            "softening_ns_per_contact": round(1e9 * best["softening"] / nc, 2),
            "ratio": round(best["softening"] / best["brittle"], 3),
            "softening_contacts": int((soft.contacts.live("damage") > 0).sum()),
            "brittle_cracks": int(brittle.cracks.count[0]), "warmup": warmup,
            "machine": f"{platform.node()} {platform.machine()} {platform.processor()}"}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--blocks", type=int, nargs="+", default=[100_000])
    ap.add_argument("--steps", type=int, default=200)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--warmup", type=int, default=2000,
                    help="steps before timing (the load reaches the base and flaws soften)")
    a = ap.parse_args()
    for n in a.blocks:
        print(json.dumps(measure(n, a.steps, a.repeats, a.warmup)), flush=True)


if __name__ == "__main__":
    main()
