"""What softening flaws (``dem_core/contact/softening.py``) cost against brittle ones, side by
side in one run.

    python benchmarks/softening_cost.py --blocks 100000        # one JSON line per size
    python benchmarks/softening_cost.py --blocks 10000 100000 --steps 300

The specimen is benchmarks/throughput.py's bonded Voronoi square under 50 g with the thesis's
plaster flaws, once brittle (today's law) and once with fracture energies G_I = 50 J/m^2 and
G_II = 500 J/m^2 (linear). Both models are built, warmed up and then timed in turns
(``--repeats``, the best of each kept), so that both see the same machine. Reported: seconds per
step and ns per contact update of each, their ratio, and the contacts on the softening branch
(kappa > 0) at the end: under 50 g many flaws at the base are past their peak, so the branch
itself is exercised, not only the extra column the elastic path reads.
"""
from __future__ import annotations

import argparse
import json
import platform
import time


def models(n_blocks):
    from throughput import loaded, specimen
    from dem_core.contact.materials import Material

    bs = specimen(n_blocks)
    brittle = loaded(bs)
    m = loaded(bs)
    soft = Material(kn=40e9, ks=20e9, tensile_strength=1.1e6, cohesion=1.2e6, friction=37,
                    fracture_energy_I=50.0, fracture_energy_II=500.0)
    m.materials = {k: soft for k in m.materials}
    for name in list(m.materials):
        m.set_material(name)                 # the table is made again from the materials
    return bs, brittle, m


def measure(n_blocks, steps, repeats):
    bs, brittle, soft = models(n_blocks)
    for m in (brittle, soft):
        m.cycle(20)                          # compile / load the caches
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
            "machine": f"{platform.node()} {platform.machine()} {platform.processor()}"}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--blocks", type=int, nargs="+", default=[100_000])
    ap.add_argument("--steps", type=int, default=200)
    ap.add_argument("--repeats", type=int, default=3)
    a = ap.parse_args()
    for n in a.blocks:
        print(json.dumps(measure(n, a.steps, a.repeats)), flush=True)


if __name__ == "__main__":
    main()
