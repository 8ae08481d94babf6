"""Time per step of a cracked slope: the Adhikary centrifuge scene at 8 mm blocks, 60 g.

    .venv/bin/python benchmarks/trials/cracked_step.py [--edge-elements] [--steps 3000]

Builds the scene (``comparisons.scenes.adhikary``, 8 mm cells), raises gravity to 60 g, runs
200 steps (compile or load the caches, and let the flaws crack) and times ``--steps`` more.
Unlike ``throughput.py`` (a bonded specimen that hardly cracks), a third of the contacts here
are open or slipping, so the kernel's slip and opening paths count. Prints one JSON line:
blocks, contacts, broken, slipping, ms per step.
"""
from __future__ import annotations

import argparse
import json
import time


def run(edge_elements=False, steps=3000) -> dict:
    from comparisons.scenes import adhikary
    from dem_core.workflow.scene import build_model

    sc = adhikary.scene(adhikary.AdhikaryParams(edge_length=0.008, relax_iterations=5),
                        stages=[])
    sc.solver["edge_elements"] = edge_elements
    m = build_model(sc)
    m.set_gravity(60.0)
    m.cycle(200)
    t0 = time.perf_counter()
    m.cycle(steps)
    seconds = time.perf_counter() - t0
    c = m.contacts
    return {"edge_elements": edge_elements, "blocks": m.n_blocks, "contacts": c.n,
            "broken": int((c.broken[:c.n] > 0).sum()), "slipping": int(c.slipping[:c.n].sum()),
            "ms_per_step": 1e3 * seconds / steps}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--edge-elements", action="store_true")
    ap.add_argument("--steps", type=int, default=3000)
    args = ap.parse_args(argv)
    print(json.dumps(run(args.edge_elements, args.steps)))


if __name__ == "__main__":
    main()
