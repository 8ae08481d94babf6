"""What edge elements (``dem_core/contact/forces.py``, ``edge_correction``) cost against end
springs, side by side in one run.

    python benchmarks/edge_cost.py                      # both specimens, one JSON line each
    python benchmarks/edge_cost.py --blocks 100000 --steps 200

Two specimens, each built twice (``edge_elements=True`` and ``False``), warmed up and then timed
in turns (``--repeats``, the best of each kept), so that both see the same machine:

- ``bonded``: benchmarks/throughput.py's bonded Voronoi square under 50 g (every contact half
  of a closed edge: the element's most common branch);
- ``common_toppling``: the common toppling quick scene (3 m flaws in a 24 m zone, about 970
  blocks; comparisons/scenes/common_toppling.py) settling under 1 g, with its joints (open and
  closed edges, vertex contacts).

Reported: ms per step of each, their ratio, ns per contact, and the machine.
"""
from __future__ import annotations

import argparse
import json
import platform
import time


def _bonded(n_blocks):
    from throughput import loaded, specimen

    bs = specimen(n_blocks)
    return {e: loaded(bs, edge_elements=e) for e in (True, False)}


def _toppling(_):
    from comparisons.scenes import common_toppling as ct
    from dem_core.workflow.scene import build_model

    sc = ct.scene(ct.ToppleParams(edge_length=3.0, zone_depth=24.0, relax_iterations=10))
    out = {}
    for e in (True, False):
        m = build_model(sc, edge_elements=e)
        m.set_gravity(1.0)
        out[e] = m
    return out


SPECIMENS = {"bonded": _bonded, "common_toppling": _toppling}


def measure(name, n_blocks, steps, repeats, warmup):
    models = SPECIMENS[name](n_blocks)
    for m in models.values():
        m.cycle(warmup)                      # compile (or load), and settle a little
    best = {e: float("inf") for e in models}
    for _ in range(repeats):
        for e, m in models.items():
            t0 = time.perf_counter()
            m.cycle(steps)
            best[e] = min(best[e], (time.perf_counter() - t0) / steps)
    m = models[True]
    nc = m.contacts.n
    return {"specimen": name, "blocks": int(m.n_blocks), "contacts": int(nc), "steps": steps,
            "repeats": repeats, "warmup": warmup,
            "edges_ms_per_step": round(1e3 * best[True], 4),
            "springs_ms_per_step": round(1e3 * best[False], 4),
            "ratio": round(best[True] / best[False], 3),
            "edges_ns_per_contact": round(1e9 * best[True] / nc, 2),
            "springs_ns_per_contact": round(1e9 * best[False] / models[False].contacts.n, 2),
            "machine": f"{platform.node()} {platform.machine()} {platform.processor()}"}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--specimens", nargs="+", default=list(SPECIMENS), choices=list(SPECIMENS))
    ap.add_argument("--blocks", type=int, default=10_000, help="the bonded specimen's size")
    ap.add_argument("--steps", type=int, default=500)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--warmup", type=int, default=2000)
    a = ap.parse_args()
    for name in a.specimens:
        print(json.dumps(measure(name, a.blocks, a.steps, a.repeats, a.warmup)), flush=True)


if __name__ == "__main__":
    main()
