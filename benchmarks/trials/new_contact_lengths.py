"""Why the length given to a contact the search makes moves the Longtan slope (issue 52).

    .venv/bin/python benchmarks/trials/new_contact_lengths.py

The Longtan quick base member (8 mm blocks, T = 4.81 MPa, seed 1) cycled with kinetic
damping checked every step to 40 g and then 120 g, 8,000 steps each (both end at a ratio
below 1e-7), with the lengths of the contacts the search makes (``detection._new_rows``)
changed one way at a time, the interface division off:

- ``as made``: half of A's two edges at the vertex projected on B's edge (today's default);
- ``x0.5``, ``x2``, ``x0.1``, ``x0.01``: those lengths scaled;
- ``cut``: cut to B's edge (what the division gives a new contact);
- each again with the new contacts given the strongest touched face's material instead of the
  weakest (``strong``).

Per run: point A's horizontal displacement (mm), the new contacts made, how many have A's
vertex within the search margin of a vertex of B (a corner meeting a corner), how many carry
load and how many of those slip. A diagnostic: the lengths are changed by replacing
``_new_rows`` in this process only.
"""
from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))

import dem_core.contact.detection as det  # noqa: E402
from comparisons.scenes import longtan as scene  # noqa: E402
from dem_core.contact.contacts import UNBONDED  # noqa: E402
from dem_core.workflow.scene import build_model  # noqa: E402

AS_MADE, TOUCHED = det._new_rows, det._touched_material
WAYS = [("as made", 1.0, False, False), ("x0.5", 0.5, False, False), ("x2", 2.0, False, False),
        ("x0.1", 0.1, False, False), ("x0.01", 0.01, False, False), ("cut", 1.0, True, False),
        ("as made, strong", 1.0, False, True), ("x2, strong", 2.0, False, True)]


def _strongest(p, table, default, cand):
    """The strongest (highest residual friction) of the faces meeting at the contact."""
    off = p.vertex_offsets
    A, v, e = cand[:, 0], cand[:, 1], cand[:, 3]
    prev = np.where(v - 1 >= off[A], v - 1, off[A + 1] - 1)
    faces = np.column_stack([p.surface_material[e], p.surface_material[v],
                             p.surface_material[prev]])
    fr = np.where(faces >= 0, table.res_tan_friction[np.maximum(faces, 0)], -np.inf)
    chosen = faces[np.arange(len(cand)), np.argmax(fr, axis=1)]
    return np.where(chosen >= 0, chosen, default).astype(np.int32)


def corner_to_corner(p, cand, wv, margin):
    """Per candidate of ``_new_rows``: True where A's vertex lies within ``margin`` of a vertex
    of B (a corner meeting a corner)."""
    off = p.vertex_offsets
    return np.array([np.hypot(*(wv[off[b]:off[b + 1]] - wv[v]).T).min() < margin
                     for b, v in zip(cand[:, 2], cand[:, 1])], dtype=bool)


def run(scale, cut, strong):
    corner = []

    def rows(p, s, cand, wv, margin, _cut):
        point_b, normal_b, L = AS_MADE(p, s, cand, wv, margin, cut)
        corner.extend(corner_to_corner(p, cand, wv, margin))
        return point_b, normal_b, L * scale

    det._new_rows, det._touched_material = rows, (_strongest if strong else TOUCHED)
    try:
        p = scene.LongtanParams(edge_length=0.008, relax_iterations=10, seed=1,
                                flaw_tensile_strength=4.81e6)
        m = build_model(scene.scene(p, stages=[]), threads=1, damping=0.0, kinetic_damping=1,
                        step_estimate="eigen", divide_interfaces=False)
        out = []
        for g in (40.0, 120.0):
            m.set_gravity(g)
            m.cycle(8000)
            c, n = m.contacts, m.contacts.n
            new = c.broken[:n] == UNBONDED
            loaded = new & (c.sn[:n] > 0)
            out.append(dict(g=g, A_mm=1e3 * m.point_motion("A")[0], ratio=m.unbalanced_ratio(),
                            made=len(corner), corner=int(sum(corner)), loaded=int(loaded.sum()),
                            slipping=int((loaded & (c.slipping[:n] > 0)).sum())))
        return out
    finally:
        det._new_rows, det._touched_material = AS_MADE, TOUCHED


def main():
    for name, scale, cut, strong in WAYS:
        t0 = time.perf_counter()
        for r in run(scale, cut, strong):
            print(f"{name:16s} {r['g']:5.0f} g: A {r['A_mm']:.4f} mm (ratio {r['ratio']:.1e}); "
                  f"made {r['made']}, corner to corner {r['corner']}, loaded {r['loaded']}, "
                  f"slipping {r['slipping']}", flush=True)
        print(f"  ({time.perf_counter() - t0:.0f} s)", flush=True)


if __name__ == "__main__":
    main()
