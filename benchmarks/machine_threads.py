"""What the machine gives a second thread, measured next to the threaded step (issue 29 item 1).

    python benchmarks/machine_threads.py --blocks 10000 --rounds 15

Two numbers that the threaded step's speed-up (``two_threads.py``) is judged against:

- **Two copies** (``ceiling``): two processes, each stepping its own serial model of the
  bonded specimen, against one of them alone, in alternating rounds. 2 x (time alone) / (time
  of the pair) is the throughput two cores give this very workload when nothing is shared and
  nothing waits: the ceiling of any two-thread step on this machine.
- **Start delay** (``start_delay``): a parallel region of two iterations, each spinning for
  ``work_us``, entered back to back with a serial gap between (as the step's shared-block pass
  is); the delay from entering the region to the later iteration's start, read from
  ``clock_gettime(CLOCK_MONOTONIC)`` (libc through ctypes, inside the numba code). With TBB the
  second thread has gone to sleep between regions; with OpenMP (libgomp) it spins a while first.

Prints JSON; ``two_threads.py`` calls both and stores them with its rows.
"""
from __future__ import annotations

import argparse
import ctypes
import json
import multiprocessing as mp
import os
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))


def build(n_blocks, threads, base_load=False):
    """The bonded specimen of ``throughput.py`` as a model on ``threads`` threads, compiled
    (also ``two_threads.py``'s models)."""
    from throughput import loaded, specimen
    m = loaded(specimen(n_blocks), threads=threads)
    if base_load:                       # on the fixed base: moves nothing, two-region step
        m.apply_load("base", fy=-1e3)
    m.cycle(20)                                     # compile or load the cache
    return m


def _worker(conn, n_blocks):
    import sys
    sys.path.insert(0, HERE)
    m = build(n_blocks, 1)
    conn.send("ready")
    while True:
        steps = conn.recv()
        if steps is None:
            return
        t0 = time.perf_counter()
        m.cycle(steps)
        conn.send(time.perf_counter() - t0)


def ceiling(n_blocks, rounds, steps) -> dict:
    """2 x (one serial model alone) / (two at once, in two processes): the median over
    ``rounds`` rounds of each round's ratio (its two runs are next to each other in time, so a
    slow spell of the host touches both), and the best-of-rounds ratio (noisier: its two
    times can come from different spells, and it has exceeded 2)."""
    ctx = mp.get_context("spawn")
    pipes, procs = [], []
    for _ in range(2):
        a, b = ctx.Pipe()
        p = ctx.Process(target=_worker, args=(b, n_blocks))
        p.start()
        b.close()                      # the child's end: a child that dies is then an EOFError
        pipes.append(a)
        procs.append(p)
    try:
        for a in pipes:
            a.recv()
        alone, pair = [], []
        for _ in range(rounds):
            pipes[0].send(steps)
            alone.append(pipes[0].recv())
            for a in pipes:
                a.send(steps)
            pair.append(max(a.recv() for a in pipes))
    finally:
        for a in pipes:
            try:
                a.send(None)
            except OSError:            # that child is gone already
                pass
        for p in procs:
            p.join()
    rounds_ratio = 2 * np.array(alone) / np.array(pair)     # each round's own pair of runs
    return {"two_copies": round(float(np.median(rounds_ratio)), 3),
            "two_copies_best": round(2 * min(alone) / min(pair), 3),
            "two_copies_ms_alone": round(1e3 * min(alone) / steps, 4)}


def _clock():
    libc = ctypes.CDLL(None)
    f = libc.clock_gettime
    f.restype = ctypes.c_int
    f.argtypes = [ctypes.c_int, ctypes.c_void_p]
    return f


def _region_kernels():
    from numba import njit, prange
    clock_gettime = _clock()

    @njit
    def now(buf, j):                      # CLOCK_MONOTONIC = 1; one (sec, nsec) row per thread
        clock_gettime(1, buf[j].ctypes.data)
        return buf[j, 0] + 1e-9 * buf[j, 1]

    @njit(parallel=True)
    def region(buf, out, k, work_us):
        out[k, 0] = now(buf, 2)
        for jp in prange(2):
            j = np.int64(jp)
            t0 = now(buf, j)
            out[k, 1 + j] = t0
            while now(buf, j) - t0 < 1e-6 * work_us:
                pass

    @njit
    def run(n, buf, out, work_us, gap_us):
        for k in range(n):
            region(buf, out, k, work_us)
            t0 = now(buf, 2)
            while now(buf, 2) - t0 < 1e-6 * gap_us:
                pass

    return run


def start_delay(work_us=700.0, gap_us=40.0, regions=3000) -> dict:
    """Median and 90th percentile (us) of the later iteration's start after entering a
    two-iteration region; ``work_us`` and ``gap_us`` as a 1e4-block step's chunk and shared
    pass."""
    import numba
    numba.set_num_threads(2)
    run = _region_kernels()
    buf = np.zeros((3, 2), np.int64)
    out = np.zeros((regions, 3))
    run(10, buf, out, work_us, gap_us)
    run(regions, buf, out, work_us, gap_us)
    later = 1e6 * (out[:, 1:].max(axis=1) - out[:, 0])
    return {"layer": numba.threading_layer(), "work_us": work_us, "gap_us": gap_us,
            "start_delay_us_median": round(float(np.median(later)), 1),
            "start_delay_us_p90": round(float(np.percentile(later, 90)), 1)}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--blocks", type=int, default=10_000)
    ap.add_argument("--rounds", type=int, default=15)
    ap.add_argument("--steps", type=int, default=200)
    a = ap.parse_args()
    print(json.dumps(start_delay()), flush=True)
    print(json.dumps(ceiling(a.blocks, a.rounds, a.steps)), flush=True)


if __name__ == "__main__":
    main()
