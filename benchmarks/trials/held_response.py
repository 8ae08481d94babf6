"""The response time N_r measured two ways at every measurement a member makes (issue 57):
the library's rule (``response._elastic``: intact contacts strong, broken ones on their
residual law, open contacts closed at zero stress) and one of

- "held" (``--rule held``): the same, and every broken contact that touches (elastic normal
  stress > 0 at the snapshot) held as well: made intact on the strong table for the
  measurement, so that a crack under compression takes a small load step elastically as an
  intact joint does, while an open crack stays on its residual law (no tension);
- "differential" (the default): the movement is the difference between the model after the
  load step and the same model run without it, so that a mechanism already under way drops
  out.

The member runs on the library's value; each measurement prints both. Question: can either
bring Lornex's measurement after a failing mining solve to rest (the library's stops at its
400,000-step cap: broken flaws slide on, loose blocks topple)?

Found (AMD EPYC 2-core, 2026-11-30): neither. Lornex T = 1 MPa after its first failing mining
solve: held, 400,000 (319 touching cracks held, 763 open); differential, 400,000: four blocks
diverge by 4-14 cm between the two runs from 2,400 steps on (chaotic loose blocks) and 24-33 by
more than 1 cm later, while the median difference settles at 2 mm by 3,000 steps. On the
Adhikary T = 1.4 slope (6 mm) held gives 7,500 / 4,800 / 3,800 steps after 40 / 60 / 80 g
against the library's 6,000 / 9,400 / 9,400: the cracked slope's slower response is partly
slip on closed cracks. Kept instead: a model in motion keeps its N_r across an excavation
(``Model.in_motion``, docs/history.md).

    .venv/bin/python benchmarks/trials/held_response.py CASE LABEL [--rule held] [--most N]
    .venv/bin/python benchmarks/trials/held_response.py --load FILE.npz x x   (differential,
        printed at each test point, on a model saved by lornex_response_time.py --save)

Printed, no file.
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path[:0] = [str(ROOT / "benchmarks"), str(ROOT)]


def held(elastic):
    def hold(model):
        c = model.contacts
        n = c.count[0]
        touching = (c.broken[:n] != 0) & (c.sn_elastic[:n] > 0)
        elastic(model)
        c.broken[:n][touching] = 0
        c.damage[:n][touching] = 0.0
        hold.count = int(touching.sum()), int((c.broken[:n] != 0).sum())
    return hold


def differential(model, watch=(), check=None):
    """N_r from the difference between the model after the load step and the same model run
    without it (every other rule the library's): motion that does not come from the load step
    (a mechanism already under way) is in both runs and drops out."""
    from dem_core.workflow import response
    check = int(check or max(model.history.every, 100))
    snap = model.snapshot()
    try:
        response._elastic(model)
        free = model.snapshot()
        g = np.asarray(model.gravity, dtype=float)
        model.gravity = g * (1 + response.LOAD_STEP) if np.hypot(*g) > 0 else g + (0.0, -response.SMALL_G)
        loaded = model.snapshot()
        start = np.zeros_like(response.positions(model, watch))
        last, done, point, quiet = start, 0, response.FIRST * check, 0
        while done < response.MOST:
            model.restore(free)
            model.cycle(point - done)
            base = response.positions(model, watch)
            free = model.snapshot()
            model.restore(loaded)
            model.cycle(point - done)
            now = response.positions(model, watch) - base
            loaded = model.snapshot()
            done = point
            total, recent = response._largest(now, start), response._largest(now, last)
            quiet = quiet + 1 if recent <= response.AT_REST * total else 0
            if VERBOSE:
                d = np.hypot(*now.T)
                print(f"  {done}: largest {total:.3g}, recent {recent:.3g}, median "
                      f"{np.median(d):.3g}, 99 % {np.quantile(d, 0.99):.3g}, blocks > 1 cm "
                      f"{int((d > 0.01).sum())}", flush=True)
            if quiet == 2:
                break
            last = now
            point = min(response.MOST, check * int(np.ceil(response.GROWTH * point / check)))
    finally:
        model.restore(snap)
    return int(done)


VERBOSE = False


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--load", help="measure a model saved by lornex_response_time.py --save")
    ap.add_argument("case")
    ap.add_argument("label")
    ap.add_argument("--rule", choices=("differential", "held"), default="differential")
    ap.add_argument("--most", type=int, default=None, help="cap of each measurement")
    args = ap.parse_args(argv)
    from dem_core.workflow import response
    if args.most:
        response.MOST = args.most
    if args.load:
        from dem_core.model import Model
        m = Model.load(args.load)
        global VERBOSE
        VERBOSE = True
        t = time.time()
        print(f"differential N_r {differential(m)} ({time.time() - t:.0f} s)", flush=True)
        return
    from verdict_budgets import members, quick_variant
    measure, elastic = response.measure_response, response._elastic
    hold = held(elastic)

    def both(model, watch=(), check=None):
        t = time.time()
        now = measure(model, watch, check)
        t1 = time.time()
        if args.rule == "held":
            response._elastic = hold
            try:
                h = measure(model, watch, check)
            finally:
                response._elastic = elastic
            extra = f"; {hold.count[0]} touching cracks held, {hold.count[1]} left open"
        else:
            h, extra = differential(model, watch, check), ""
        print(f"N_r as now {now} ({t1 - t:.0f} s), {args.rule} {h} ({time.time() - t1:.0f} s"
              f"{extra})", flush=True)
        return now

    from dem_core import model as model_module
    model_module.measure_response = both
    judge = response.judge

    def judged(model, st, n_r, check, moved, trace):
        res = judge(model, st, n_r, check, moved, trace)
        print(f"solve: {res.verdict} at {res.steps} steps (N_r = {n_r})", flush=True)
        return res

    response.judge = judged
    case, v = quick_variant(args.case)
    out = case.run_member(next(m for m in members(case, v, "response", 1)
                               if m["label"] == args.label))
    print(out if not isinstance(out, dict) else {k: out[k] for k in list(out)[:6]})


if __name__ == "__main__":
    main()
