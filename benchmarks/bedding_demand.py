"""How much of the Adhikary beds an elastic slope loads beyond a bedding cohesion, DEM and continuum.

The thesis's bedding-cohesion study (15 vs 5 kPa: 70 vs 50 g) needs beds that keep their
cohesion over much of the ramp. This benchmark asks the elastic question behind that, with both
methods on the same section: at gravity level ``--g`` the slope is solved with every strength
out of reach (elastic), the shear and normal stress on the bedding planes (dip 81 degrees into
the slope) are taken, and because elastic stress scales with g, the g at which each piece of bed
would first need more than cohesion ``c`` plus friction 23 degrees follows:

    g_slip = g * c / (|tau| - sigma_n tan 23)      (never, if the bracket is <= 0)

Reported per method: the median normal and shear stress on the beds (kPa, compression +), the
ratio of summed |tau| to summed sigma_n, and, for c = 5 and 15 kPa, the share of bed length (DEM:
bedding contacts, their forces summed over each shared edge) or of rock area (continuum: traction
on the bedding direction in each cell) past its strength at 10, 20, 40 and 70 g. Slip sheds load
onto the neighbours, so these shares are lower bounds on the beds that have slipped by each g.
Only the slope above the base is counted.

    python benchmarks/bedding_demand.py [--g 10] [--edge 0.006] [--h 0.006]

Writes results/benchmarks/bedding_demand.json.
"""
from __future__ import annotations

import argparse
import json
import math
import platform
import time
from pathlib import Path

import numpy as np

from comparisons.scenes import adhikary as scene

G_LEVELS = (10, 20, 40, 70)
COHESIONS_KPA = (5.0, 15.0)
OUT_OF_REACH = 1e12     # Pa: strengths nothing reaches (the elastic solution)


def slip_shares(sn, ts, weight, friction_deg, g):
    """Share of ``weight`` whose elastic stress (at ``g``) exceeds c + sn tan(phi) by each
    g-level of ``G_LEVELS``, for each cohesion of ``COHESIONS_KPA`` (dict kPa -> list)."""
    excess = np.abs(ts) - np.maximum(sn, 0.0) * math.tan(math.radians(friction_deg))
    out = {}
    for c in COHESIONS_KPA:
        g_slip = np.full(len(sn), np.inf)
        loaded = excess > 0
        g_slip[loaded] = g * c * 1e3 / excess[loaded]
        out[f"{c:g}"] = [float(weight[g_slip <= level].sum() / weight.sum())
                         for level in G_LEVELS]
    return out


def _summary(sn, ts, weight, friction_deg, g):
    return {"median_sigma_n_kpa": float(np.median(sn) / 1e3),
            "median_abs_tau_kpa": float(np.median(np.abs(ts)) / 1e3),
            "sum_abs_tau_over_sum_sigma_n": float(np.sum(np.abs(ts) * weight)
                                                 / np.sum(sn * weight)),
            "share_in_tension": float(weight[sn <= 0].sum() / weight.sum()),
            "share_past_strength_by_g": slip_shares(sn, ts, weight, friction_deg, g)}


def dem_bedding_stress(edge: float, g: float):
    """Elastic DEM at ``g``: per shared bedding edge, the mean normal and shear stress (Pa) and
    the edge length (m); plus the solver's steps and run time."""
    t0 = time.perf_counter()
    p = scene.AdhikaryParams(edge_length=edge, relax_iterations=10,
                             bedding_cohesion=OUT_OF_REACH, bedding_tensile=OUT_OF_REACH,
                             flaw_cohesion=OUT_OF_REACH, flaw_tensile_strength=OUT_OF_REACH)
    model = scene.build_model(p, mass_scaling=True, damping=0.8, kinetic_damping=50)
    model.set_gravity(g)
    res = model.solve(ratio=1e-5, max_steps=100_000)
    if res.verdict != "equilibrium":
        raise RuntimeError(f"the elastic DEM slope did not settle at {g} g: {res}")
    c, n = model.contacts, model.contacts.n
    bedding = np.array([model.table.names[m].startswith("joint:") for m in c.material[:n]])
    a, b = c.block_a[:n][bedding], c.block_b[:n][bedding]
    # a shared edge's two contacts have opposite owners; its stresses on B are in one frame
    # either way (contacts.py), so the edge's force is the plain length-weighted sum
    edge_id = np.unique(np.column_stack([np.minimum(a, b), np.maximum(a, b)]), axis=0,
                        return_inverse=True)[1].ravel()
    length = c.length[:n][bedding]
    total = np.bincount(edge_id, weights=length)
    sn = np.bincount(edge_id, weights=c.sn[:n][bedding] * length) / total
    ts = np.bincount(edge_id, weights=c.ts[:n][bedding] * length) / total
    # keep edges above the base (the fixed blocks' beds carry the clamp, not the slope)
    rot = model.state.theta[a]
    y_contact = model.state.pos[a, 1] + (np.sin(rot) * c.point_a[:n][bedding][:, 0]
                                         + np.cos(rot) * c.point_a[:n][bedding][:, 1])
    y = np.bincount(edge_id, weights=y_contact * length) / total
    above = y > p.base_thickness
    return sn[above], ts[above], total[above], res.steps, time.perf_counter() - t0


def continuum_bedding_stress(h: float, g: float):
    """Elastic continuum (E 2.6 GPa, nu 0.16) at ``g``: normal and shear traction (Pa) on the
    bedding direction in each cell above the base, the cell areas (m2) and the run time."""
    from continuum_ref.materials import Elastic
    from continuum_ref.mesh import mesh_from_geometry
    from continuum_ref.model import ContinuumModel

    t0 = time.perf_counter()
    p = scene.AdhikaryParams()
    mesh = mesh_from_geometry(scene.geometry(p), h)
    model = ContinuumModel(mesh, Elastic(E=p.block_E, nu=p.block_nu), scene.DENSITY)
    model.fix(lambda x: x[1] < 1e-9)
    model.fix(lambda x: (x[0] < 1e-9) | (x[0] > p.width - 1e-9), components=(0,))
    model.solve_gravity(g)
    s = model.stress()                                 # [xx, yy, zz, xy], tension +
    xy, tri = model.triangles()
    corners = xy[tri]
    centre_y = corners[:, :, 1].mean(axis=1)
    e1, e2 = corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]
    area = 0.5 * np.abs(e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0])
    dip = math.radians(p.joint_dip)
    along = np.array([-math.cos(dip), -math.sin(dip)])  # down-dip, into the slope (left)
    normal = np.array([-along[1], along[0]])
    traction = np.column_stack([s[:, 0] * normal[0] + s[:, 3] * normal[1],
                                s[:, 3] * normal[0] + s[:, 1] * normal[1]])
    sn, ts = -(traction @ normal), traction @ along
    above = centre_y > p.base_thickness
    return sn[above], ts[above], area[above], time.perf_counter() - t0


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--g", type=float, default=10.0, help="g-level of the elastic solutions")
    ap.add_argument("--edge", type=float, default=0.006, help="DEM block edge (m)")
    ap.add_argument("--h", type=float, default=0.006, help="continuum mesh size (m)")
    a = ap.parse_args(argv)
    friction = scene.AdhikaryParams().bedding_friction
    sn, ts, w, steps, dem_s = dem_bedding_stress(a.edge, a.g)
    dem = dict(_summary(sn, ts, w, friction, a.g), edges=int(len(sn)), steps=int(steps),
               seconds=dem_s)
    sn, ts, w, fe_s = continuum_bedding_stress(a.h, a.g)
    fe = dict(_summary(sn, ts, w, friction, a.g), cells=int(len(sn)), seconds=fe_s)
    out = {"machine": f"{platform.machine()} {platform.platform()}", "g": a.g,
           "edge_m": a.edge, "h_m": a.h, "g_levels": list(G_LEVELS),
           "bedding_friction_deg": friction, "dem": dem, "continuum": fe}
    print(json.dumps(out, indent=1))
    import sys
    sys.path.insert(0, str(Path(__file__).resolve().parent))      # also as benchmarks.<this>
    import outdir
    (outdir.results_dir() / "bedding_demand.json").write_text(json.dumps(out, indent=1))


if __name__ == "__main__":
    main()
