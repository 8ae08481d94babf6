"""Contact-update throughput of the explicit solver on a bonded Voronoi specimen under gravity.

    python benchmarks/throughput.py --blocks 100000          # one JSON line
    python benchmarks/throughput.py --scaling                # 1,000 .. 100,000 blocks

A square Voronoi specimen (flaws: kn 40 GPa/m, ks 20 GPa/m, T 1.1 MPa, c 1.2 MPa, friction 37,
the thesis's plaster) sits on a fixed base under 50 g. After a warm-up (numba compile, first
steps) the timed run is ``--steps`` steps of ``Model.cycle`` (contact forces, law, damping,
integration, movement check; contact searches when triggered are included).
``contact_updates_per_s_per_core`` = point contacts x steps / seconds / threads; ``--threads 2``
runs the threaded contact kernel (``dem_core.step.threads.parallel``; ``Model(threads=2)``).
"""
from __future__ import annotations

import argparse
import json
import math
import platform
import time

import numpy as np


def specimen(n_blocks, seed=0):
    from dem_core.geometry import GeometrySpec, Voronoi, build_block_system, rectangle

    edge = 0.005
    side = math.sqrt(n_blocks * 2.6 * edge * edge)    # a hexagon of edge h has area 2.6 h^2
    spec = GeometrySpec(regions=[rectangle("rock", 0, 0, side, side),
                                 rectangle("base", 0, -edge * 2, side, 0)],
                        voronoi={"rock": Voronoi(edge_length=edge, seed=seed,
                                                 relax_iterations=5)})
    return build_block_system(spec)


def loaded(bs, **options):
    """The Model of specimen ``bs`` as timed here: the thesis's plaster flaws, its base fixed,
    50 g; ``options`` are Model options (``threads=2``, ...)."""
    from dem_core.contact.materials import Material
    from dem_core.model import Model

    flaw = Material(kn=40e9, ks=20e9, tensile_strength=1.1e6, cohesion=1.2e6, friction=37)
    m = Model(bs, {"flaw:*": flaw, "boundary:*": flaw}, density=1700, history_every=10**9,
              **options)
    m.fix("base")
    m.set_gravity(50.0)
    return m


def run(n_blocks, steps, seed=0, threads=1):
    t0 = time.perf_counter()
    bs = specimen(n_blocks, seed)
    t_geom = time.perf_counter() - t0
    t0 = time.perf_counter()
    m = loaded(bs, threads=threads)
    t_setup = time.perf_counter() - t0
    m.cycle(20)                                       # warm-up (compile or load the cache)
    step0, searches0 = m.step, 0
    t0 = time.perf_counter()
    m.cycle(steps)
    seconds = time.perf_counter() - t0
    nc = m.contacts.n
    return {
        "blocks": bs.n_blocks, "contacts": int(nc), "steps": int(m.step - step0),
        "seconds": round(seconds, 4), "threads": threads,
        "contact_updates_per_s_per_core": round(nc * steps / seconds / threads),
        "ns_per_contact_update": round(1e9 * seconds / (nc * steps), 2),
        "seconds_per_step": seconds / steps, "geometry_seconds": round(t_geom, 2),
        "setup_seconds": round(t_setup, 2), "cracks": int(m.cracks.count[0]),
        "machine": f"{platform.node()} {platform.machine()} {platform.platform()}",
        "numpy": np.__version__,
    }


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--blocks", type=int, default=100_000)
    ap.add_argument("--steps", type=int, default=500)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--scaling", action="store_true",
                    help="run 1e3, 3e3, 1e4, 3e4, 1e5 blocks; one JSON line each")
    a = ap.parse_args()
    sizes = [1000, 3000, 10_000, 30_000, 100_000] if a.scaling else [a.blocks]
    for n in sizes:
        print(json.dumps(run(n, a.steps, a.seed, a.threads)), flush=True)


if __name__ == "__main__":
    main()
