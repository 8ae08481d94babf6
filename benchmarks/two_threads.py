"""Two threads against one on the whole step, and where the threaded step spends its time.

    python benchmarks/two_threads.py                       # 1e3, 1e4, 1e5 blocks
    python benchmarks/two_threads.py --blocks 10000 --rounds 3 --layer omp

The bonded Voronoi specimen of ``throughput.py`` (under 50 g on a fixed base). Per size one
model per thread count, both built and compiled first; then ``--rounds`` rounds, each timing
``steps`` steps of ``Model.cycle`` on one thread and on two, alternating (the order swapped
every round), so both see the same machine. Reported: ms per step (best and median of the
rounds), the speed-up (one-thread best / two-thread best) and whether the two runs end in the
same state bit for bit (they must). Then the threaded step's parts at each size, each the
same numba kernel the step calls, run ``steps`` times inside one numba call (no Python
between calls): the contact pass (``parallel.add_contact_forces_parallel``: chunks, crack
log, shared blocks), damping and integration (``step.advance_parallel``), gravity
(``components.add_gravity``), against the serial kernels. Writes
``benchmarks/results/two_threads.json`` and ``two_threads.png``.
"""
from __future__ import annotations

import argparse
import json
import os
import statistics
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
STEPS = {1000: 4000, 10_000: 600, 100_000: 60}


def build(n_blocks, threads):
    from dem_core.materials import Material
    from dem_core.model import Model

    from throughput import specimen
    bs = specimen(n_blocks)
    flaw = Material(kn=40e9, ks=20e9, tensile_strength=1.1e6, cohesion=1.2e6, friction=37)
    m = Model(bs, {"flaw:*": flaw, "boundary:*": flaw}, density=1700, history_every=10**9,
              threads=threads)
    m.fix("base")
    m.set_gravity(50.0)
    m.cycle(20)                                     # compile or load the cache
    return m


def _loops():
    from numba import njit

    from dem_core.components import add_gravity
    from dem_core.forces import add_contact_forces
    from dem_core.parallel import add_contact_forces_parallel
    from dem_core.step import advance, advance_parallel

    @njit
    def contacts_serial(n, c, strength, s, cracks, rnd, dfm):
        for _ in range(n):
            s.force[:] = 0.0
            add_contact_forces(c, strength, s, cracks, 0.0, rnd, False, dfm)

    @njit
    def contacts_threaded(n, c, strength, s, cracks, rnd, par, dfm):
        for _ in range(n):
            add_contact_forces_parallel(c, strength, s, cracks, 0.0, rnd, par, False, dfm)

    @njit
    def advance_serial(n, s, p, integ):
        for _ in range(n):
            advance(s, p, integ, 0.0)                # kick 0: the blocks stay where they are

    @njit
    def advance_threaded(n, s, p, integ):
        for _ in range(n):
            advance_parallel(s, p, integ, 0.0)

    @njit
    def gravity(n, g, s, p):
        for _ in range(n):
            add_gravity(g, s, p)

    return contacts_serial, contacts_threaded, advance_serial, advance_threaded, gravity


def parts(m, steps, loops):
    """Seconds per step of each part of the step, serial and threaded kernels, on ``m``."""
    contacts_serial, contacts_threaded, advance_serial, advance_threaded, gravity = loops
    import numba
    numba.set_num_threads(2)
    from dem_core.parallel import parallel_bundle
    par = parallel_bundle(m.contacts, m.n_blocks, 2)
    integ = m._integrator()
    g = m._components()[0]
    strength = m.table.strength_array()
    out = {}
    for name, fn, args in (
            ("contacts_serial", contacts_serial,
             (m.contacts, strength, m.state, m.cracks, m.corners, m.zone_state)),
            ("contacts_threaded", contacts_threaded,
             (m.contacts, strength, m.state, m.cracks, m.corners, par, m.zone_state)),
            ("advance_serial", advance_serial, (m.state, m.props, integ)),
            ("advance_threaded", advance_threaded, (m.state, m.props, integ)),
            ("gravity", gravity, (g, m.state, m.props))):
        fn(2, *args)                                 # compile
        best = np.inf
        for _ in range(3):
            t0 = time.perf_counter()
            fn(steps, *args)
            best = min(best, time.perf_counter() - t0)
        out[name + "_ms"] = round(1e3 * best / steps, 4)
    return out


def compare(n_blocks, rounds, steps, loops):
    models = {t: build(n_blocks, t) for t in (1, 2)}
    times = {1: [], 2: []}
    for r in range(rounds):
        for t in ((1, 2) if r % 2 == 0 else (2, 1)):
            t0 = time.perf_counter()
            models[t].cycle(steps)
            times[t].append((time.perf_counter() - t0) / steps)
    one, two = models[1], models[2]
    same = bool(np.array_equal(one.state.pos, two.state.pos)
                and np.array_equal(one.state.theta, two.state.theta))
    row = {"blocks": one.n_blocks, "contacts": int(one.contacts.n), "steps": steps,
           "rounds": rounds, "bit_for_bit": same}
    for t in (1, 2):
        row[f"ms_per_step_{t}_best"] = round(1e3 * min(times[t]), 4)
        row[f"ms_per_step_{t}_median"] = round(1e3 * statistics.median(times[t]), 4)
    row["speedup_best"] = round(min(times[1]) / min(times[2]), 3)
    row["speedup_median"] = round(statistics.median(times[1]) / statistics.median(times[2]), 3)
    row["ns_per_update_1"] = round(1e9 * min(times[1]) / one.contacts.n, 2)
    row.update(parts(two, steps, loops))
    return row


def figure(rows, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6, 4))
    b = [r["blocks"] for r in rows]
    ax.plot(b, [r["speedup_best"] for r in rows], "o-", label="whole step (best of rounds)")
    ax.plot(b, [r["contacts_serial_ms"] / r["contacts_threaded_ms"] for r in rows], "s--",
            label="contact pass alone")
    ax.plot(b, [r["advance_serial_ms"] / r["advance_threaded_ms"] for r in rows], "^--",
            label="damping + integration alone")
    ax.axhline(1.7, color="k", lw=0.8, ls=":", label="goal 1.7x")
    ax.axhline(1.0, color="0.5", lw=0.8)
    ax.set_xscale("log")
    ax.set_xlabel("blocks (bonded Voronoi specimen)")
    ax.set_ylabel("speed-up, 2 threads / 1 thread")
    ax.set_title("Two threads against one, same run", fontsize=10)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--blocks", type=int, nargs="*", default=[1000, 10_000, 100_000])
    ap.add_argument("--rounds", type=int, default=4)
    ap.add_argument("--out", default=os.path.join(HERE, "results"))
    ap.add_argument("--layer", default="default", choices=["default", "tbb", "omp", "workqueue"],
                    help="numba threading layer (default: numba's choice, tbb when installed)")
    a = ap.parse_args()
    import numba
    if a.layer != "default":
        numba.config.THREADING_LAYER = a.layer
    import sys
    sys.path.insert(0, HERE)
    from scenes import machine
    loops = _loops()
    rows = []
    for n in a.blocks:
        steps = STEPS.get(n, max(20, int(6e6 / n)))
        row = compare(n, a.rounds, steps, loops)
        print(json.dumps(row), flush=True)
        rows.append(row)
    os.makedirs(a.out, exist_ok=True)
    name = "two_threads" if a.layer == "default" else f"two_threads_{a.layer}"
    with open(os.path.join(a.out, name + ".json"), "w") as f:
        json.dump({"machine": machine(), "threading_layer": numba.threading_layer(),
                   "rows": rows}, f, indent=1)
    figure(rows, os.path.join(a.out, name + ".png"))


if __name__ == "__main__":
    main()
