"""Why the response time N_r of the Lornex slope hits its cap after a failing mining solve
(issue 57; docs/history.md, "rest needs a decaying ratio; a mechanism must be seen twice").

Runs a quick Lornex member on the response judge to its first failing solve, then measures
N_r (``response.measure_response``) on that state in variants, and finally lists the blocks
that move most after a 5 % gravity step from rest with every contact's slip held:

- "as now": intact contacts strong, broken ones on their residual law (the library's rule);
- "slip held, from rest": broken contacts' residual cohesion strong as well, velocities zeroed;
- the same with the 99th percentile of the blocks' movement in place of the largest.

Found (T = 1 MPa, first failing solve at 223,200 steps, N_r = 2,400 before it): every variant
stops at the 400,000-step cap; with slip held and from rest, 4 of 546 blocks move more than
1 cm, back and forth by 5-20 cm on 2-8 contacts, while the fifth stays at 6.6 mm.

    .venv/bin/python benchmarks/trials/lornex_response_time.py [--member "T=1 MPa"]

Printed, no file; about 8 minutes.
"""
from __future__ import annotations

import argparse
import os
import sys
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path[:0] = [str(ROOT / "benchmarks"), str(ROOT)]


def _from_rest(model):
    model.state.vel[:] = 0.0
    model.cables.node_vel[:] = 0.0
    model.liners.node_vel[:] = 0.0
    model.zone_state.v[:] = 0.0


def _slip_held(model, elastic):
    from dem_core.contact.materials import material_table
    from dem_core.workflow import response
    elastic(model)                      # closes open contacts at zero stress, as the library
    strong = {k: replace(m, tensile_strength=response.STRONG, cohesion=response.STRONG,
                         residual_cohesion=response.STRONG) for k, m in model.materials.items()}
    model.table = material_table(model.table.names, strong, model.unbreakable)
    _from_rest(model)


def _q99(a, b):
    return float(np.quantile(np.hypot(*(a - b).T), 0.99)) if a.size else 0.0


def probe(model, check):
    from dem_core.workflow import response
    elastic, largest = response._elastic, response._largest
    variants = (("as now", elastic, largest),
                ("slip held, from rest", lambda m: _slip_held(m, elastic), largest),
                ("slip held, from rest, 99th percentile", lambda m: _slip_held(m, elastic), _q99))
    for name, el, lg in variants:
        response._elastic, response._largest = el, lg
        t = time.time()
        print(f"N_r {name}: {response.measure_response(model, check=check)} steps "
              f"({time.time() - t:.0f} s)", flush=True)
    response._elastic, response._largest = elastic, largest
    _slip_held(model, elastic)
    model.gravity = np.asarray(model.gravity, float) * (1 + response.LOAD_STEP)
    p0, act = model.state.pos[:, :2].copy(), model.props.active > 0
    c = model.contacts
    for k in range(4):
        model.cycle(25_000)
        d = np.hypot(*(model.state.pos[:, :2] - p0).T) * act
        top = np.argsort(d)[-5:][::-1]
        n = c.count[0]
        touching = [int(((c.block_a[:n] == b) | (c.block_b[:n] == b)).sum()) for b in top]
        print(f"{(k + 1) * 25_000} steps: largest movements {np.round(d[top], 4)} m of blocks "
              f"{top.tolist()} ({touching} contacts); {int((d > 0.01).sum())} of "
              f"{int(act.sum())} blocks moved > 1 cm", flush=True)


QUANTILES = (0.5, 0.8, 0.9, 0.95, 0.98, 0.99, 1.0)


def quantiles(model, check, most=400_000):
    """The library's measurement (intact contacts strong, broken ones as they are), printing
    at each test point, for each quantile q of the blocks' movements, the q-quantile of the
    movement since the test point before over the q-quantile of the movement since the load
    step, and the step at which a rest test on that quantile would have passed."""
    from dem_core.workflow import response
    snap = model.snapshot()
    response._elastic(model)
    model.gravity = np.asarray(model.gravity, float) * (1 + response.LOAD_STEP)
    start = response.positions(model, ())
    last, done, point = start, 0, response.FIRST * check
    quiet = {q: 0 for q in QUANTILES}
    rest = {q: None for q in QUANTILES}
    while done < most and any(v is None for v in rest.values()):
        model.cycle(point - done)
        done = point
        now = response.positions(model, ())
        tot, rec = np.hypot(*(now - start).T), np.hypot(*(now - last).T)
        row = []
        for q in QUANTILES:
            a, b = float(np.quantile(tot, q)), float(np.quantile(rec, q))
            quiet[q] = quiet[q] + 1 if b <= response.AT_REST * a else 0
            if quiet[q] == 2 and rest[q] is None:
                rest[q] = done
            row.append(f"{q:g}: {b / a if a else 0:.3f} of {a:.3g}")
        print(f"{done:7d} ratio {model.unbalanced_ratio():.2g}  " + "; ".join(row), flush=True)
        last = now
        point = check * int(np.ceil(response.GROWTH * point / check))
    print("N_r by quantile:", rest, flush=True)
    model.restore(snap)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--member", default="T=1 MPa")
    ap.add_argument("--save", help="write the model at its first failing solve to this .npz")
    ap.add_argument("--load", help="probe a model saved by --save (quantiles only)")
    args = ap.parse_args(argv)
    from dem_core.workflow import response
    from verdict_budgets import members, quick_variant
    if args.load:
        from dem_core.model import Model
        model = Model.load(args.load)
        quantiles(model, max(model.history.every, 100))
        return
    judge = response.judge

    def probing(model, st, n_r, check, moved, trace):
        res = judge(model, st, n_r, check, moved, trace)
        print(f"solve: {res.verdict} at {res.steps} steps (N_r = {n_r})", flush=True)
        if res.verdict == "failing":
            if args.save:
                model.save(args.save)
                quantiles(model, check)
            else:
                probe(model, check)
            os._exit(0)
        return res

    response.judge = probing
    case, v = quick_variant("lornex")
    case.run_member(next(m for m in members(case, v, "response", 1)
                         if m["label"] == args.member))


if __name__ == "__main__":
    main()
