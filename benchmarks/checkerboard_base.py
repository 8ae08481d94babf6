"""Checkerboard Creek: does the cut stand at its weathered strengths (T = c) before any T is
lowered? The scene's base stages only (gravity at 10 x strength, the real strengths, the
water table, each solved), for one extent, flaw size, cut height and UCS.

    python benchmarks/checkerboard_base.py --extent section --edge 6      # whole section
    python benchmarks/checkerboard_base.py --extent window --edge 1.3     # quick window
    python benchmarks/checkerboard_base.py --extent section --edge 1.3 --cut 50
    python benchmarks/checkerboard_base.py --extent section --edge 1.3 --edge-elements
    python benchmarks/checkerboard_base.py --extent section --edge 1.3 --insitu 0.37

Prints one line per solved stage (verdict, steps, cracks so far, the monitoring points'
displacement in m, seconds) and a JSON line at the end. The quick variant's model is
``--extent window --edge 6``; the full variant's ``--extent section --edge 1.3``
(docs/cases/checkerboard.md, "Full variant").
"""
from __future__ import annotations

import argparse
import dataclasses
import json
import time
import warnings


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--extent", choices=["section", "window"], default="section")
    ap.add_argument("--edge", type=float, default=1.3, help="flaw edge near the cut, m")
    ap.add_argument("--cut", type=float, default=70.0, help="cut height, m")
    ap.add_argument("--ucs", type=float, default=60.0, help="MPa")
    ap.add_argument("--steps", type=int, default=150_000, help="step limit of each solve")
    ap.add_argument("--insitu", type=float, default=None, metavar="K",
                    help="start from the geostatic field sv = rho g depth, sh = K sv "
                         "(dem_core.insitu.InSitu) before the gravity stage")
    ap.add_argument("--edge-elements", action="store_true",
                    help="each shared edge one linear element (Model(edge_elements=True))")
    a = ap.parse_args()
    warnings.simplefilter("ignore")        # (the scene's own notes)
    from comparisons import checkerboard as cbk
    from comparisons.scenes import checkerboard as scene
    from dem_core.scene import build_model
    from dem_core.stages import run_stages

    common = dict(cbk._COMMON) if a.extent == "window" else {}
    p = scene.CheckerboardParams(**dict(common, edge_length=a.edge, cut_height=a.cut,
                                        ucs=a.ucs * 1e6))
    stages = scene.base_stages(p, a.steps)
    if a.insitu is not None:
        from dem_core.insitu import InSitu
        stages = [InSitu.geostatic(scene.DENSITY, a.insitu)] + stages
    sc = scene.scene(p, stages)
    if a.edge_elements:
        sc = dataclasses.replace(sc, solver=dict(sc.solver, edge_elements=True))
    m = build_model(sc)
    print(f"{a.extent}, {a.edge} m flaws, cut {a.cut} m, UCS {a.ucs} MPa, edge elements "
          f"{a.edge_elements}, in-situ k {a.insitu}: {m.n_blocks} blocks, "
          f"{m.contacts.n} contacts", flush=True)
    t0 = time.time()
    out = []
    for r in run_stages(m, sc.stages, progress=lambda *x, **k: None):
        if r.steps:
            pts = {k: [round(x, 2) for x in v] for k, v in r.points.items()}
            print(f"  {r.kind}: {r.verdict}, {r.steps} steps, cracks {r.cracks}, {pts}, "
                  f"{r.seconds:.0f} s", flush=True)
            out.append(dict(kind=r.kind, verdict=r.verdict, steps=r.steps, cracks=r.cracks,
                            points=pts))
    print(json.dumps(dict(extent=a.extent, edge=a.edge, cut=a.cut, ucs=a.ucs,
                          edge_elements=a.edge_elements, insitu_k=a.insitu,
                          blocks=int(m.n_blocks), stages=out,
                          seconds=round(time.time() - t0)), default=str))


if __name__ == "__main__":
    main()
