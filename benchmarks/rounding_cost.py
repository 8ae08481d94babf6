"""What rounded corners (``rounding="auto"``, the default since 2026-12-02) cost per step,
side by side with sharp corners (``rounding=0``), on two specimens:

    python benchmarks/rounding_cost.py --blocks 10000            # one JSON line per specimen

- ``bonded``: benchmarks/throughput.py's bonded Voronoi square under 50 g. Its contacts are
  the shared edges the tessellation made, which rounding leaves sharp (``face`` = 1): the cost
  of the option where it has nothing to do.
- ``pile``: the same cells shrunk by 1e-4 of their size about their centroids, so that no two
  share an edge and every contact is a corner on a face made by the search (``face`` = 0),
  every one of them rounded, settled under 1 g on the fixed base: the worst case.

Each model is built and stepped to rest first (the pile's contacts found and closed); then the
two models are timed in alternating rounds of ``--steps`` steps (``--rounds``); reported: the
fastest round's ns per contact update of each, their ratio (rounded over sharp) and the median
of the rounds' ratios. Searches that come due inside a round are included.
"""
from __future__ import annotations

import argparse
import json
import platform
import time

import numpy as np


def pile(bs, shrink=1e-4):
    """The cells of ``bs`` (BlockSystem) shrunk about their centroids by ``shrink``, the base
    ("base" group) kept, as a new BlockSystem whose contacts the search makes."""
    from dem_core.geometry.simple_blocks import from_polygons

    polys = []
    for b in range(bs.n_blocks):
        v = np.asarray(bs.block_vertices(b), float)
        c = bs.centroid[b]
        polys.append([tuple(p) for p in c + (1.0 - shrink) * (v - c)])
    base = [int(b) for b in bs.groups["base"]]
    return from_polygons(polys, edge_material="flaw:rock", groups={"base": base})


def model(bs, rounding, gravity):
    from dem_core.contact.materials import Material
    from dem_core.model import Model

    flaw = Material(kn=40e9, ks=20e9, tensile_strength=1.1e6, cohesion=1.2e6, friction=37)
    m = Model(bs, {"flaw:*": flaw, "boundary:*": flaw}, density=1700, history_every=10**9,
              new_contact_material="flaw:rock", rounding=rounding)
    m.fix("base")
    m.set_gravity(gravity)
    return m


def measure(name, bs, gravity, steps, rounds, settle):
    pair = {r: model(bs, r, gravity) for r in ("auto", 0.0)}
    for m in pair.values():
        m.cycle(settle)
    times = {r: [] for r in pair}
    for _ in range(rounds):
        for r, m in pair.items():
            t0 = time.perf_counter()
            m.cycle(steps)
            times[r].append((time.perf_counter() - t0) / (m.contacts.n * steps))
    c = pair["auto"].contacts
    rounded = int(((c.face[:c.n] == 0) & (c.vertex_a[:c.n] >= 0)).sum())
    best = {r: min(t) for r, t in times.items()}
    ratios = [a / b for a, b in zip(times["auto"], times[0.0])]
    return {"specimen": name, "blocks": bs.n_blocks, "contacts_rounded_model": int(c.n),
            "rounded_contacts": rounded, "contacts_sharp_model": int(pair[0.0].contacts.n),
            "ns_per_contact_update_rounded": round(1e9 * best["auto"], 2),
            "ns_per_contact_update_sharp": round(1e9 * best[0.0], 2),
            "ratio_fastest_rounds": round(best["auto"] / best[0.0], 3),
            "ratio_median_of_rounds": round(float(np.median(ratios)), 3),
            "steps_per_round": steps, "rounds": rounds,
            "machine": f"{platform.node()} {platform.processor() or platform.machine()}"}


def main():
    from throughput import specimen

    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--blocks", type=int, default=10_000)
    ap.add_argument("--steps", type=int, default=200)
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--settle", type=int, default=2000)
    a = ap.parse_args()
    bs = specimen(a.blocks)
    print(json.dumps(measure("bonded", bs, 50.0, a.steps, a.rounds, a.settle)), flush=True)
    print(json.dumps(measure("pile", pile(bs), 1.0, a.steps, a.rounds, a.settle)), flush=True)


if __name__ == "__main__":
    main()
