"""Strength-reduction factor of safety against mesh size, run time and Bishop's method.

The slope of tests/test_continuum_ssr.py (H = 10 m, 45 deg, c = 20 kPa, phi = 30 deg, gamma =
20 kN/m3, 3 m of foundation on a rigid base), meshed at h near the face and 3 h elsewhere (P2).
For each flow rule (and first F step: 0.25, or 0.02 for psi = 0 as well) and h: F (last
converged), first failed F, whether a mechanism formed
(`continuum_ref.ssr`), the upturn ratio, Newton iterations, cells, run time (mesh + gravity +
SSR) and the error against Bishop's simplified method on the same section. A water-table row
(mid-height, effective stress) is added per flow rule at the coarsest h.

Usage: .venv/bin/python benchmarks/ssr_mesh.py [--quick] [--h 1 0.5 0.25 0.125]
Writes results/benchmarks/ssr_mesh.json.
"""
import argparse
import json
import math
import platform
import sys
import time
from pathlib import Path

from continuum_ref import limit_equilibrium as le
from continuum_ref import ssr
from continuum_ref.materials import MohrCoulomb
from dem_core.workflow.water import WaterTable

import outdir

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "examples"))
from c_phi_slope import C, GAMMA, GROUND, PHI, WATER, slope_model  # noqa: E402  (the section)


def run(h, material, bishop, water=None, first_step=0.25):
    t0 = time.perf_counter()
    model = slope_model(h, material, water)
    result = ssr.factor_of_safety(model, [material], f_max=3.0, first_step=first_step)
    return {"h": h, "cells": len(model.triangles()[1]), "F": result.value,
            "first_failed": result.first_failed, "mechanism": result.mechanism,
            "upturn": result.upturn, "newton_iterations": result.newton_iterations,
            "run_s": time.perf_counter() - t0, "bishop": bishop,
            "error_vs_bishop": result.value / bishop - 1.0, "water": water is not None}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true", help="h = 1, 0.5 only")
    ap.add_argument("--h", type=float, nargs="+", default=[1.0, 0.5, 0.25, 0.125])
    args = ap.parse_args()
    sizes = [1.0, 0.5] if args.quick else args.h
    t0 = time.perf_counter()
    dry = le.critical_circle(GROUND, C, PHI, GAMMA, bottom=0.0)
    t_bishop = time.perf_counter() - t0
    wet = le.critical_circle(GROUND, C, PHI, GAMMA, pore_pressure=WaterTable(WATER).pressure,
                             bottom=0.0)
    print(f"Bishop dry F = {dry.factor:.4f} ({t_bishop:.2f} s, {dry.evaluated} circles), "
          f"water table F = {wet.factor:.4f}")
    rows = []
    print(f"{'flow':>12} {'water':>5} {'h (m)':>6} {'cells':>6} {'F':>7} {'failed':>7} "
          f"{'mech':>5} {'upturn':>8} {'its':>5} {'time s':>7} {'vs Bishop':>9}")
    flows = (("psi = phi", None, 0.25, sizes), ("psi = 0", 0.0, 0.25, sizes),
             ("psi=0,dF.02", 0.0, 0.02, sizes[:3]))
    for flow, psi, first_step, hs in flows:
        mat = MohrCoulomb(E=1e8, nu=0.3, cohesion=C, friction=PHI, dilation=psi)
        cases = [(h, None, dry.factor) for h in hs] + [(sizes[0], WaterTable(WATER),
                                                        wet.factor)]
        for h, water, bishop in cases:
            row = dict(run(h, mat, bishop, water, first_step), flow=flow, first_step=first_step)
            rows.append(row)
            print(f"{flow:>12} {str(row['water']):>5} {h:6.3f} {row['cells']:6d} "
                  f"{row['F']:7.4f} {row['first_failed'] or math.nan:7.4f} "
                  f"{str(row['mechanism']):>5} {row['upturn']:8.3g} "
                  f"{row['newton_iterations']:5d} {row['run_s']:7.1f} "
                  f"{row['error_vs_bishop']:+9.2%}", flush=True)
    out = outdir.results_dir() / "ssr_mesh.json"
    out.write_text(json.dumps({"machine": platform.node(), "bishop_dry": dry.factor,
                               "bishop_water": wet.factor, "rows": rows}, indent=1))
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
