"""numba's first compile of a serial model's step, from an empty cache, in a fresh process.

    .venv/bin/python benchmarks/first_compile.py [--deformable] [--rounds 1]

Each round starts a new Python process with its own empty ``NUMBA_CACHE_DIR``, builds a small
bonded brick wall (rigid blocks, or with ``--deformable`` the same wall with deformable
blocks), runs one step and then a short solve, and reports the seconds of the build (the
contact search's kernels), of the first step (the step's compile) and of the solve, with the
top-level compiles numba reports (``numba:compile`` events, seconds each, nested compiles
counted in their callers too). This is what a first ``./dev demo`` or a first sweep member
pays before it steps (docs/performance.md, "The first compile"). Writes
``results/benchmarks/first_compile.json``.
"""
from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
from outdir import results_dir  # noqa: E402

ROOT = HERE.parent


def one_round(deformable: bool) -> dict:
    """Build, step once and solve a small wall in this process; the times and compiles."""
    from numba.core import event

    events = []

    class Listener(event.Listener):
        def on_start(self, ev):
            events.append([ev.data["dispatcher"].py_func.__qualname__, time.perf_counter(), None])

        def on_end(self, ev):
            name = ev.data["dispatcher"].py_func.__qualname__
            for e in reversed(events):
                if e[2] is None and e[0] == name:
                    e[2] = time.perf_counter()
                    break

    event.register("numba:compile", Listener())
    from dem_core.contact.materials import Material
    from dem_core.geometry.simple_blocks import brick_grid
    from dem_core.model import Model

    t0 = time.perf_counter()
    bs = brick_grid(3, 3, 0.1, 0.1)
    options = dict(deformable={"*": 0.05}, block_E=1e9) if deformable else {}
    m = Model(bs, {"flaw:*": Material(kn=1e9, ks=1e9, tensile_strength=1e5, cohesion=1e5,
                                      friction=30)}, density=2500, **options)
    m.fix("bottom")
    m.set_gravity(1.0)
    t1 = time.perf_counter()
    m.cycle(1)
    t2 = time.perf_counter()
    m.solve(ratio=1e-5, max_steps=200)
    t3 = time.perf_counter()
    tops = sorted(((e[2] - e[1], e[0]) for e in events if e[2]), reverse=True)[:12]
    return {"build_s": t1 - t0, "first_step_s": t2 - t1, "solve_s": t3 - t2,
            "compiles_s": {name: round(d, 1) for d, name in tops}}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--deformable", action="store_true", help="deformable blocks")
    ap.add_argument("--rounds", type=int, default=1)
    ap.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.child:
        print(json.dumps(one_round(args.deformable)))
        return
    rounds = []
    for _ in range(args.rounds):
        env = dict(os.environ, NUMBA_CACHE_DIR=tempfile.mkdtemp(prefix="numba-cache-"))
        cmd = [sys.executable, __file__, "--child"] + (["--deformable"] if args.deformable
                                                       else [])
        out = subprocess.run(cmd, env=env, cwd=ROOT, capture_output=True, text=True,
                             check=True).stdout
        rounds.append(json.loads(out.strip().splitlines()[-1]))
        print(json.dumps({k: round(v, 1) for k, v in rounds[-1].items()
                          if k.endswith("_s")}))
    name = "first_compile" + ("_deformable" if args.deformable else "") + ".json"
    path = results_dir() / name
    from scenes import machine
    path.write_text(json.dumps({"machine": machine(), "rounds": rounds}, indent=1))
    print(f"written {path}")


if __name__ == "__main__":
    main()
