"""Two threads against one on the whole step, and where the threaded step spends its time.

    python benchmarks/two_threads.py                       # 1e3, 3e3, 1e4, 1e5 blocks
    python benchmarks/two_threads.py --blocks 10000 --rounds 3 --layer omp

The bonded Voronoi specimen of ``throughput.py`` (under 50 g on a fixed base). Per size three
models, built and compiled first: one thread; two threads; and two threads with a load on the
fixed base (it moves nothing, but gravity is then not the only force besides the contacts',
so the threaded step takes its two-region shape: ``step.run_steps_threaded``). Then
``--rounds`` rounds, each timing ``steps`` steps of ``Model.cycle`` on each model in turn (the
order reversed every other round), so all see the same machine; many short rounds, because
the host's second core comes and goes. Reported: ms per step (best and median of the rounds),
the speed-ups (one-thread best / two-thread best) and whether the runs end in the same state
bit for bit (they must), and the machine's ceiling at that size: two serial copies in two
processes against one (``machine_threads.ceiling``); once per run, the delay before a
parallel region's second thread starts (``machine_threads.start_delay``). Then the threaded
step's parts at each size, each the
same numba kernel the step calls, run ``steps`` times inside one numba call (no Python
between calls): the contact pass (``parallel.add_contact_forces_parallel``: chunks, crack
log, shared blocks), damping and integration (``integration.advance_parallel``), gravity
(``components.add_gravity``), against the serial kernels (the one-region step,
``region.run_steps_region``, is the whole step of the gravity-only model above). Writes
``results/benchmarks/two_threads.json`` and ``two_threads.png`` (``--reference``:
``benchmarks/results/``).
"""
from __future__ import annotations

import argparse
import json
import os
import statistics
import time

import numpy as np

import outdir
from machine_threads import build, ceiling, start_delay   # the model, the machine's own numbers

HERE = os.path.dirname(os.path.abspath(__file__))
STEPS = {1000: 1500, 10_000: 200, 100_000: 20}


def _loops():
    from numba import njit

    from dem_core.components import add_gravity
    from dem_core.contact.forces import add_contact_forces
    from dem_core.step.threads.parallel import add_contact_forces_parallel
    from dem_core.step.integration import advance, advance_parallel

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
    from dem_core.step.threads.parallel import parallel_bundle
    par = parallel_bundle(m.contacts, m.n_blocks, 2, m.edge_elements)
    integ = m.integrator()
    g = m.parts().gravity
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
    models = {"1": build(n_blocks, 1), "2": build(n_blocks, 2),
              "2r": build(n_blocks, 2, base_load=True)}
    times = {k: [] for k in models}
    for r in range(rounds):
        for k in (list(models) if r % 2 == 0 else list(models)[::-1]):
            t0 = time.perf_counter()
            models[k].cycle(steps)
            times[k].append((time.perf_counter() - t0) / steps)
    one = models["1"]
    same = all(bool(np.array_equal(one.state.pos, m.state.pos)
                    and np.array_equal(one.state.theta, m.state.theta))
               for m in models.values())
    row = {"blocks": one.n_blocks, "contacts": int(one.contacts.n), "steps": steps,
           "rounds": rounds, "bit_for_bit": same}
    for k in models:                    # 2: one region per step; 2r: two regions
        row[f"ms_per_step_{k}_best"] = round(1e3 * min(times[k]), 4)
        row[f"ms_per_step_{k}_median"] = round(1e3 * statistics.median(times[k]), 4)
    for k, name in (("2", ""), ("2r", "_two_regions")):
        row["speedup" + name + "_rounds"] = round(float(np.median(
            np.array(times["1"]) / np.array(times[k]))), 3)     # each round's own ratio
        row["speedup" + name + "_best"] = round(min(times["1"]) / min(times[k]), 3)
        row["speedup" + name + "_median"] = round(statistics.median(times["1"])
                                                  / statistics.median(times[k]), 3)
    row["ns_per_update_1"] = round(1e9 * min(times["1"]) / one.contacts.n, 2)
    row.update(parts(models["2"], steps, loops))
    row.update(ceiling(n_blocks, rounds, steps))
    return row


def figure(rows, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(11, 5))
    b = [r["blocks"] for r in rows]
    ax.plot(b, [r["speedup_best"] for r in rows], "o-",
            label="whole step, gravity only: one region (best of rounds)")
    ax.plot(b, [r["speedup_two_regions_best"] for r in rows], "o:",
            label="whole step, other forces too: two regions")
    ax.plot(b, [r["contacts_serial_ms"] / r["contacts_threaded_ms"] for r in rows], "s--",
            label="contact pass alone")
    ax.plot(b, [r["advance_serial_ms"] / r["advance_threaded_ms"] for r in rows], "^--",
            label="damping + integration alone")
    ax.plot(b, [r["speedup_rounds"] for r in rows], "o-", color="tab:blue", alpha=0.45,
            label="whole step, one region (median of each round's ratio)")
    ax.plot(b, [r["two_copies"] for r in rows], "k^-",
            label="two serial copies in two processes, the machine's ceiling (median of "
                  "each round's ratio)")
    ax.axhline(1.7, color="k", lw=0.8, ls=":", label="goal 1.7x")
    ax.axhline(1.0, color="0.5", lw=0.8)
    ax.set_xscale("log")
    ax.set_xlabel("blocks (bonded Voronoi specimen)")
    ax.set_ylabel("speed-up, 2 threads / 1 thread")
    ax.set_title("Two threads against one, same run", fontsize=10)
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--blocks", type=int, nargs="*", default=[1000, 3000, 10_000, 100_000])
    ap.add_argument("--rounds", type=int, default=15)
    ap.add_argument("--out", default=None,
                    help="folder (default results/benchmarks/; --reference: benchmarks/results/)")
    outdir.add_reference_flag(ap)
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
    start = start_delay()
    print(json.dumps(start), flush=True)
    rows = []
    for n in a.blocks:
        steps = STEPS.get(n, max(20, int(2e6 / n)))
        row = compare(n, a.rounds, steps, loops)
        print(json.dumps(row), flush=True)
        rows.append(row)
    a.out = a.out or str(outdir.results_dir(a.reference))
    os.makedirs(a.out, exist_ok=True)
    name = "two_threads" if a.layer == "default" else f"two_threads_{a.layer}"
    with open(os.path.join(a.out, name + ".json"), "w") as f:
        json.dump({"machine": machine(), "threading_layer": numba.threading_layer(),
                   "region_start": start, "rows": rows}, f, indent=1)
    figure(rows, os.path.join(a.out, name + ".png"))


if __name__ == "__main__":
    main()
