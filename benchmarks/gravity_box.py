"""Local tension in bonded Voronoi rock under its own weight, and what a low T does to it.

A 60 m x 60 m box of Voronoi blocks (no joints), base fixed, sides on smooth walls, the
weathered Checkerboard rock's elastic constants (E 3.6 GPa, nu 0.27, density 2700 kg/m3), flaw
stiffness by eq. 3.7 (kn = (K + 4G/3) / edge) and ks = ratio x kn, flaws unbreakable, brought
to equilibrium under gravity (force ratio 1e-6). A continuum in this box is in compression
everywhere (sv = rho g depth, sh = nu / (1 - nu) sv); the rigid blocks' contacts are not: each
contact's normal stress sn divided by the geostatic sv at its depth shows the scatter (contacts
more than 10 m from the sides and the base, 5 m from the top). Then each flaw's T is set to a
value (c 2.5 MPa, friction 35 kept) and the box solved again: how many bonds break.

    python benchmarks/gravity_box.py [--edges 6 1.3] [--ratios 0.1 0.4 1.0] [--tensile 25e3 1e5 3e5]
                                     [--zones 1.3 0.65]

``--zones``: the same boxes with deformable blocks (``Model(deformable=...)``, zones of that
size; 6 m blocks get zones of a quarter of their edge).

Prints one JSON line per run and writes results/benchmarks/gravity_box.json and .png (the
distribution of sn / sv per setting; ``--reference``: benchmarks/results/). docs/cases/checkerboard.md ("Why 1.3 m flaws fail at
T = c") quotes it: the thesis's back-calculated T of 25-650 kPa in a 60 m weathered zone is of
the order of the tension that rigid-block contacts carry under gravity alone.
"""
from __future__ import annotations

import argparse
import json
import time
import warnings

import numpy as np

from dem_core.contact.contacts import SHEAR, TENSION
from dem_core.contact.elastic import kn_from_zone
from dem_core.geometry import GeometrySpec, Voronoi, rectangle
from dem_core.contact.materials import Material
from dem_core.units import STANDARD_GRAVITY
from dem_core.workflow.scene import Boundary, Scene, build_model
from dem_core.workflow.stages import ChangeMaterial, Gravity, Solve, run_stages

import outdir

SIDE, RHO, E, NU, COHESION = 60.0, 2700.0, 3.6e9, 0.27, 2.5e6
GROUPS = {"base": {"touching": "bottom"}, "left side": {"touching": "left"},
          "right side": {"touching": "right"},
          "side walls": {"union": ["left side", "right side"]},
          "sides": {"minus": ["side walls", "base"]}}


def box(edge, ratio, edge_elements=False, zone=None):
    kn = kn_from_zone(E, NU, edge)
    geo = GeometrySpec([rectangle("rock", 0.0, 0.0, SIDE, SIDE)],
                       voronoi={"rock": Voronoi(edge_length=edge, seed=1, relax_iterations=10)})
    flaw = Material(kn=kn, ks=ratio * kn, tensile_strength=1e12, cohesion=1e12, friction=35.0)
    return Scene(geo, {"flaw:rock": flaw}, density=RHO, block_E=E, block_nu=NU, groups=GROUPS,
                 boundaries=[Boundary("base"), Boundary("sides", x=True, y=False, rotation=True)],
                 solver=dict({"mass_scaling": True, "damping": 0.8, "edge_elements": edge_elements},
                             **({"deformable": {"*": zone}} if zone else {})))


def stress_ratio(m):
    """sn / (rho g depth) of the intact contacts away from the box's walls and top."""
    c, n = m.contacts, m.contacts.n
    xy = 0.5 * (m.state.pos[c.block_a[:n]] + m.state.pos[c.block_b[:n]])
    inner = ((xy[:, 0] > 10) & (xy[:, 0] < SIDE - 10) & (xy[:, 1] > 10) & (xy[:, 1] < SIDE - 5)
             & (c.broken[:n] == 0))
    return c.sn[:n][inner] / (RHO * STANDARD_GRAVITY * (SIDE - xy[inner, 1]))


def run(edge, ratio, edge_elements, tensiles, zone=None):
    t0 = time.perf_counter()
    m = build_model(box(edge, ratio, edge_elements, zone))
    r = run_stages(m, [Gravity(1.0), Solve(ratio=1e-6, max_steps=300_000)])[-1]
    q = stress_ratio(m)
    row = dict(edge_m=edge, ks_over_kn=ratio, edge_elements=edge_elements, zone_m=zone,
               blocks=int(m.n_blocks), contacts=int(m.contacts.n), verdict=r.verdict,
               steps=r.steps, contacts_measured=int(q.size),
               mean_sn_over_sv=round(float(q.mean()), 3),
               fraction_in_tension=round(float((q < 0).mean()), 4),
               fraction_below_minus_0_1=round(float((q < -0.1).mean()), 4),
               percentiles_1_5_50_95_99=[round(float(x), 3)
                                         for x in np.percentile(q, [1, 5, 50, 95, 99])],
               min_sn_over_sv=round(float(q.min()), 3), sn_over_sv=np.sort(q).tolist())
    snap = m.snapshot()
    row["tensile"] = []
    for t in tensiles:
        m.restore(snap)
        r2 = run_stages(m, [ChangeMaterial("flaw:rock", {"tensile_strength": t,
                                                         "cohesion": COHESION}),
                            Solve(ratio=1e-6, max_steps=300_000)])[-1]
        b = m.contacts.broken[:m.contacts.n]
        row["tensile"].append(dict(T_pa=t, verdict=r2.verdict, steps=r2.steps,
                                   broken_fraction=round(float(((b == TENSION) | (b == SHEAR))
                                                               .mean()), 4)))
    row["seconds"] = round(time.perf_counter() - t0, 1)
    return row


def figure(rows, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7.5, 4.8))
    for r in rows:
        q = np.asarray(r["sn_over_sv"])
        lab = (f"{r['edge_m']} m blocks, ks/kn {r['ks_over_kn']}"
               + (", edge elements" if r["edge_elements"] else "")
               + (f", deformable ({r['zone_m']} m zones)" if r["zone_m"] else ""))
        ax.plot(q, np.arange(1, q.size + 1) / q.size, label=lab,
                ls="--" if r["zone_m"] else "-")
    ax.axvline(0.0, color="k", lw=0.8)
    ax.set_xlim(-0.45, 0.6)
    ax.set_ylim(0.0, 0.3)   # the tension tail
    ax.set_xlabel("contact normal stress / geostatic vertical stress  (compression +)")
    ax.set_ylabel("fraction of contacts below")
    ax.set_title("Bonded Voronoi box under gravity (rigid: solid, deformable: dashed):\n"
                 "contacts in tension are left of 0", fontsize=10)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--edges", type=float, nargs="+", default=[6.0, 1.3])
    ap.add_argument("--ratios", type=float, nargs="+", default=[0.1, 0.4, 1.0])
    ap.add_argument("--tensile", type=float, nargs="+", default=[25e3, 1e5, 3e5])
    ap.add_argument("--zones", type=float, nargs="*", default=[1.3, 0.65],
                    help="zone sizes (m) of the deformable runs of the finest box")
    outdir.add_reference_flag(ap)
    a = ap.parse_args()
    warnings.simplefilter("ignore")
    rows = []
    settings = [(e, 0.1, False, None) for e in a.edges] + [(a.edges[-1], 0.1, True, None)]
    settings += [(a.edges[-1], k, False, None) for k in a.ratios if k != 0.1]
    if a.zones:
        settings += [(a.edges[0], 0.1, False, a.edges[0] / 4)]
        settings += [(a.edges[-1], 0.1, False, z) for z in a.zones]
    for edge, ratio, ee, zone in settings:
        rows.append(run(edge, ratio, ee, a.tensile, zone))
        print(json.dumps({k: v for k, v in rows[-1].items() if k != "sn_over_sv"}), flush=True)
    out = outdir.results_dir(a.reference)
    (out / "gravity_box.json").write_text(json.dumps(
        {"rows": [{k: v for k, v in r.items() if k != "sn_over_sv"} for r in rows]}, indent=2))
    figure(rows, out / "gravity_box.png")


if __name__ == "__main__":
    main()
