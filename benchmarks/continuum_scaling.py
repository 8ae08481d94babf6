"""Benchmark of continuum_ref: solve time and Newton iterations against dofs, and the footing
error against run time under refinement. Writes JSON (machine named) to results/benchmarks/
(``--reference``: benchmarks/results/).

Usage: .venv/bin/python benchmarks/continuum_scaling.py [--quick]
"""
import argparse
import json
import math
import platform
import sys
import time

import numpy as np

from continuum_ref.materials import Elastic, MohrCoulomb
from continuum_ref.mesh import PolygonRegion, build_mesh, refine_near
from continuum_ref.model import ContinuumModel

import outdir

FACE, HEIGHT = 61.0, 0.33          # centrifuge slope of thesis section 4.2 (model scale, m)


def slope_mesh(h):
    toe = 0.1
    crest = toe + HEIGHT / math.tan(math.radians(FACE))
    ext = [(0, 0), (0.4, 0), (0.4, 0.395), (crest, 0.395), (toe, 0.395 - HEIGHT),
           (0, 0.395 - HEIGHT)]
    return build_mesh([PolygonRegion("rock", ext)], h, points={"crest": (crest, 0.395)})


def slope_case(h, material, g_level):
    t0 = time.perf_counter()
    md = slope_mesh(h)
    model = ContinuumModel(md, material, 2427.0)        # 23.8 kN/m3
    model.fix(lambda x: np.isclose(x[1], 0.0), (0, 1))
    model.fix(lambda x: np.isclose(x[0], 0.0) | np.isclose(x[0], 0.4), (0,))
    model._build_forms()
    t1 = time.perf_counter()
    result = model.solve_gravity(g_level, first_step=g_level / 10)
    t2 = time.perf_counter()
    return {"h": h, "dofs": int(model.V.dofmap.index_map.size_global * 2),
            "setup_s": t1 - t0, "solve_s": t2 - t1, "converged": result.converged,
            "steps": result.steps, "newton_iterations": result.newton_iterations,
            "crest_ux_m": result.displacement["crest"][0],
            "yielded_cells": int(np.sum(model.yield_indicator()["shear"] > 0))}


def footing_case(h_min, h_max=0.3):
    c, half = 1e4, 0.5
    t0 = time.perf_counter()
    md = build_mesh([PolygonRegion("soil", [(0, -2), (3, -2), (3, 0), (half, 0), (0, 0)])],
                    h_max, size_field=refine_near([(half, 0.0)], h_min, h_max, 0.05, 1.0))
    model = ContinuumModel(md, MohrCoulomb(E=1e7, nu=0.3, cohesion=c, friction=0.0), 0.0)
    model.fix(lambda x: np.isclose(x[0], 0.0) | np.isclose(x[0], 3.0), (0,))
    model.fix(lambda x: np.isclose(x[1], -2.0), (0, 1))
    under = lambda x: np.isclose(x[1], 0.0) & (x[0] <= half + 1e-9)  # noqa: E731
    model.fix(under, (1,), value=(-0.02,))
    iters = 0
    for k in range(1, 11):
        r = model.solve_load(0.1 * k)
        iters += r.newton_iterations
    q = -model.reaction(under, 1) / half / c
    elapsed = time.perf_counter() - t0
    exact = 2 + math.pi
    return {"h_min": h_min, "dofs": int(model.V.dofmap.index_map.size_global * 2),
            "q_over_c": q, "rel_error": (q - exact) / exact, "run_time_s": elapsed,
            "newton_iterations": iters, "converged": r.converged}


def main(quick, reference=False):
    hs = [0.04, 0.02, 0.01] if quick else [0.04, 0.02, 0.01, 0.006]
    elastic = Elastic(E=2.6e9, nu=0.16)
    plastic = MohrCoulomb(E=2.6e9, nu=0.16, cohesion=50e3, friction=30.0, dilation=0.0,
                          tensile_strength=20e3)
    out = {"machine": platform.node(), "processor": platform.processor() or platform.machine(),
           "python": sys.version.split()[0], "date": time.strftime("%Y-%m-%d %H:%M"),
           "elastic_slope_100g": [slope_case(h, elastic, 100.0) for h in hs],
           "mohr_coulomb_slope_60g": [slope_case(h, plastic, 60.0) for h in hs],
           "footing": [footing_case(hm) for hm in ([0.1, 0.05, 0.03] if quick
                                                   else [0.1, 0.05, 0.03, 0.015, 0.008])]}
    path = outdir.results_dir(reference) / "continuum_scaling.json"
    path.write_text(json.dumps(out, indent=2))
    print(json.dumps(out, indent=2))


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="coarser meshes only")
    outdir.add_reference_flag(ap)
    a = ap.parse_args()
    main(a.quick, a.reference)
