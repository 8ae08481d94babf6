"""Flexural strength of one Voronoi column against beam theory, at several block sizes.

A column 0.3 m long and 10 mm wide (an Adhikary & Dyskin bed), clamped at its base, under
gravity tilted 9 degrees from its axis (the beds dip 81 degrees), flaws T = 1.1 MPa, c = 1.6 MPa,
friction 37, kn 700 / ks 600 GPa/m, block E 2.6 GPa. Euler-Bernoulli: the clamp's outer fibre
reaches T at g = T w^2 / (3 rho g0 sin(9 deg) w L^2) = 10.9 g. The DEM failure g (g raised 2 g at
a time) shows how many blocks across a column the damage model needs in bending.

    python benchmarks/column_bending.py [--edges 0.006 0.004 0.003] [--zones 0.006 0.003]

Each block size runs with the edges as linear elements (``Model(edge_elements=True)``) and as
independent end springs (the default), and with ``--zones`` also with deformable blocks (zones
of each size; UDEC-DM's blocks: each face split into ceil(L / h) segments, one contact pair
per segment, so a face of one segment is two end springs again). Prints one JSON line per run (edge_m, edge_elements,
blocks, failure_g, last_stable_g, beam_theory_g, ratio, seconds) and writes
results/benchmarks/column_bending.json and .png (``--name`` renames them).
"""
from __future__ import annotations

import argparse
import json
import math
import time

import numpy as np

from dem_core.geometry import GeometrySpec, Region, Voronoi, build_block_system, rectangle
from dem_core.workflow.gravity_ramp import raise_gravity
from dem_core.contact.materials import Material
from dem_core.model import Model

import outdir

LENGTH, WIDTH, TILT, DENSITY, TENSILE = 0.3, 0.010, 9.0, 2426.0, 1.1e6


class _TiltedGravity:
    """Adapter: the ramp sets g-levels; gravity acts along the tilted direction."""

    def __init__(self, model):
        self.model = model
        t = math.radians(TILT)
        self.direction = (math.sin(t), -math.cos(t))

    def __getattr__(self, name):
        return getattr(self.model, name)

    def set_gravity(self, g_level):
        self.model.set_gravity(g_level, direction=self.direction)


def run(edge: float, edge_elements: bool = True, zone: float = 0.0) -> dict:
    t0 = time.perf_counter()
    col = Region("rock", [(0, 0), (WIDTH, 0), (WIDTH, LENGTH), (0, LENGTH)])
    base = rectangle("base", -0.01, -0.01, WIDTH + 0.01, 0.0)
    bs = build_block_system(GeometrySpec([col, base], voronoi={"rock": Voronoi(edge, seed=1)}))
    flaw = Material(kn=700e9, ks=600e9, tensile_strength=TENSILE, cohesion=1.6e6, friction=37)
    glue = Material(kn=700e9, ks=600e9, breakable=False)
    model = Model(bs, {"flaw:*": flaw, "boundary:*": glue}, density=DENSITY, block_E=2.6e9,
                  block_nu=0.16, mass_scaling=True, edge_elements=edge_elements,
                  deformable={"rock": zone} if zone > 0 else None)
    model.fix("base")
    model.add_history_point("tip", (WIDTH / 2, LENGTH - 0.001))
    rec = raise_gravity(_TiltedGravity(model), np.arange(6.0, 80.0, 2.0), ratio=1e-5,
                        max_steps=300_000, failure_displacement=0.05, watch=("tip",))
    q1 = DENSITY * 9.81 * math.sin(math.radians(TILT)) * WIDTH
    beam_g = TENSILE / (6 * q1 * LENGTH ** 2 / 2 / WIDTH ** 2)
    return {"edge_m": edge, "edge_elements": edge_elements, "zone_m": zone,
            "blocks": bs.n_blocks,
            "failure_g": rec.failure_g,
            "last_stable_g": rec.last_stable_g, "beam_theory_g": beam_g,
            "ratio": None if rec.failure_g is None else rec.failure_g / beam_g,
            "seconds": time.perf_counter() - t0}


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--edges", type=float, nargs="+", default=[0.006, 0.004])
    parser.add_argument("--zones", type=float, nargs="+", default=[], metavar="H",
                        help="also run each edge with deformable blocks of these zone sizes (m)")
    parser.add_argument("--name", default="column_bending")
    args = parser.parse_args(argv)
    rows = []
    for edge in args.edges:
        for mode in (True, False):
            rows.append(run(edge, mode))
            print(json.dumps(rows[-1]), flush=True)
        for zone in args.zones:
            rows.append(run(edge, False, zone))
            print(json.dumps(rows[-1]), flush=True)
    out = outdir.results_dir()
    (out / f"{args.name}.json").write_text(json.dumps({"rows": rows}, indent=2))
    picture(rows, out / f"{args.name}.png")


def picture(rows, path):
    """Failure g against block size: each bracket (last stable to first failed level) with the
    edges as linear elements, as independent end springs and with deformable blocks, and beam
    theory."""
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6, 4.2))
    series = [("edges as linear elements (edge_elements=True)", "o", "C0",
               lambda r: r.get("edge_elements", True) and not r.get("zone_m")),
              ("edge ends as independent springs (default)", "s", "0.6",
               lambda r: not r.get("edge_elements", True) and not r.get("zone_m"))]
    for i, z in enumerate(sorted({r["zone_m"] for r in rows if r.get("zone_m")})):
        series.append((f"deformable blocks, {1e3 * z:g} mm zones", "^", f"C{i + 1}",
                       lambda r, z=z: r.get("zone_m") == z))
    for j, (label, style, colour, pick) in enumerate(series):
        sel = [r for r in rows if pick(r) and r["failure_g"] is not None]
        if not sel:
            continue
        mm = np.array([1e3 * r["edge_m"] for r in sel]) + 0.08 * (j - 1)   # side by side
        lo = np.array([r["last_stable_g"] for r in sel], float)
        hi = np.array([r["failure_g"] for r in sel], float)
        ax.errorbar(mm, 0.5 * (lo + hi), yerr=0.5 * (hi - lo), fmt=style, color=colour,
                    capsize=4, label=label + ": last stable to failed g")
    ax.axhline(rows[0]["beam_theory_g"], color="k", ls="--",
               label=f"Euler-Bernoulli ({rows[0]['beam_theory_g']:.1f} g)")
    ax.set_ylim(0, 50)
    edges = [1e3 * r["edge_m"] for r in rows]
    ax.set_xlim(min(edges) - 0.5 - (min(edges) == max(edges)), max(edges) + 0.5)
    ax.set_xlabel("block edge (mm), column 10 mm wide")
    ax.set_ylabel("g-level at which the column breaks")
    ax.set_title("One bonded Voronoi column in bending", fontsize=10)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)

if __name__ == "__main__":
    main()
