"""A million blocks: tessellation time, model memory and the per-contact rate against 1e5.

    python benchmarks/million.py                      # 1e6 blocks, then 1e5 for the rate
    python benchmarks/million.py --blocks 200000 --steps 20

The bonded Voronoi specimen of ``throughput.py`` (a square of 5 mm cells, 5 Lloyd iterations,
on a fixed base under 50 g). For each size: the tessellation's wall time
(``build_block_system``), the model's set-up time (``Model``: masses, contacts, stiffness,
time step), the process's resident memory after each (and its peak), and ``--steps`` steps of
``Model.cycle`` on one thread after a 20-step warm-up: ns per contact update. The largest size
runs first, so the peak memory is its own. Issue 29's goals: tessellation under 5 minutes, the
model under 8 GB, the same per-contact rate as at 1e5 blocks. Writes
``benchmarks/results/million.json``.
"""
from __future__ import annotations

import argparse
import json
import os
import resource
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))


def huge_gb() -> float:
    """Resident memory of this process in transparent huge pages now, GB (0 where the kernel
    has none): large arrays in 4 kB pages cost a TLB miss per page touched."""
    try:
        with open("/proc/self/smaps_rollup") as f:
            for line in f:
                if line.startswith("AnonHugePages:"):
                    return int(line.split()[1]) * 1024 / 1e9
    except OSError:
        pass
    return 0.0


def rss_gb() -> float:
    """Resident memory of this process now, GB."""
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE") / 1e9


def peak_gb() -> float:
    """Highest resident memory of this process so far, GB (Linux: ru_maxrss in kB)."""
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024 / 1e9


def one_size(n_blocks, steps):
    from dem_core.materials import Material
    from dem_core.model import Model

    from throughput import specimen
    row = {"target_blocks": n_blocks, "rss_start_gb": round(rss_gb(), 3)}
    t0 = time.perf_counter()
    bs = specimen(n_blocks)
    row["tessellation_s"] = round(time.perf_counter() - t0, 1)
    row["blocks"] = int(bs.n_blocks)
    row["rss_after_tessellation_gb"] = round(rss_gb(), 3)
    flaw = Material(kn=40e9, ks=20e9, tensile_strength=1.1e6, cohesion=1.2e6, friction=37)
    t0 = time.perf_counter()
    m = Model(bs, {"flaw:*": flaw, "boundary:*": flaw}, density=1700, history_every=10**9)
    m.fix("base")
    m.set_gravity(50.0)
    row["model_setup_s"] = round(time.perf_counter() - t0, 1)
    row["contacts"] = int(m.contacts.n)
    row["rss_with_model_gb"] = round(rss_gb(), 3)
    m.cycle(20)
    t0 = time.perf_counter()
    m.cycle(steps)
    sec = time.perf_counter() - t0
    row.update(steps=steps, seconds=round(sec, 2),
               ns_per_contact_update=round(1e9 * sec / (m.contacts.n * steps), 2),
               rss_after_steps_gb=round(rss_gb(), 3), huge_pages_gb=round(huge_gb(), 3),
               peak_rss_gb=round(peak_gb(), 3))
    del m, bs
    return row


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--blocks", type=int, default=1_000_000)
    ap.add_argument("--reference", type=int, default=100_000,
                    help="the size whose per-contact rate is the reference")
    ap.add_argument("--steps", type=int, default=30)
    ap.add_argument("--out", default=os.path.join(HERE, "results"))
    a = ap.parse_args()
    sys.path.insert(0, HERE)
    from scenes import machine
    rows = []
    for n, steps in ((a.blocks, a.steps), (a.reference, 10 * a.steps)):
        row = one_size(n, steps)
        print(json.dumps(row), flush=True)
        rows.append(row)
    big, ref = rows
    summary = {"machine": machine(), "rows": rows,
               "rate_ratio": round(big["ns_per_contact_update"] / ref["ns_per_contact_update"], 3),
               "goals": {"tessellation_under_5_min": big["tessellation_s"] < 300,
                         "model_under_8_gb": big["peak_rss_gb"] < 8.0}}
    print(json.dumps({k: summary[k] for k in ("rate_ratio", "goals")}))
    os.makedirs(a.out, exist_ok=True)
    with open(os.path.join(a.out, "million.json"), "w") as f:
        json.dump(summary, f, indent=1)


if __name__ == "__main__":
    main()
