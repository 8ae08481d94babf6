"""Does the Longtan slope's drift with block size come from its corner-to-corner contacts?
(issues 51 and 52)

    .venv/bin/python benchmarks/trials/longtan_corner_points.py --edges 0.004 0.003 [--G 1200]

The failure g of ``benchmarks/centrifuge_resolution.py --case longtan --edge-elements`` (the
full variant's ramp, T = 4.81 MPa, seed 1), run here with the contacts the search makes
between a corner of A and a corner of B (A's vertex within the search margin of a vertex of
B, where the two blocks share no edge) given 1 % of the length they are made with: as near a
point as the contact law allows. Every other contact the search makes keeps its length as
made. A diagnostic: ``detection._new_rows`` is replaced in this process only. One row per
edge, as centrifuge_resolution's, to results/benchmarks/<--name>.json.
"""
from __future__ import annotations

import argparse
import json
import platform
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks"))

import dem_core.contact.detection as det  # noqa: E402
import centrifuge_resolution as cr  # noqa: E402
sys.path.insert(0, str(ROOT / "benchmarks" / "trials"))
from new_contact_lengths import corner_to_corner  # noqa: E402
import outdir  # noqa: E402

AS_MADE = det._new_rows
POINT = 0.01          # a corner-to-corner contact's length, as a fraction of its made length


def corner_points(p, s, cand, wv, margin, cut):
    """``_new_rows`` with the corner-to-corner contacts' lengths scaled by ``POINT``."""
    point_b, normal_b, L = AS_MADE(p, s, cand, wv, margin, cut)
    return point_b, normal_b, np.where(corner_to_corner(p, cand, wv, margin), L * POINT, L)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--edges", type=float, nargs="+", default=[0.004, 0.003])
    ap.add_argument("--G", type=float, default=0.0, help="G_I of the zone's flaws (0: brittle)")
    ap.add_argument("--name", default="longtan_corner_points")
    a = ap.parse_args()
    det._new_rows = corner_points
    rows = []
    for edge in a.edges:
        m = cr.member(edge, 1, None, True, "longtan", 0.0, a.G, "zone*")
        r = cr.row(m, cr.run_member(m))
        r["corner_contacts"] = f"points ({POINT:g} of the length as made)"
        print(json.dumps({k: v for k, v in r.items() if k not in ("g", "verdicts")}), flush=True)
        rows.append(r)
    out = outdir.results_dir(False)
    (out / f"{a.name}.json").write_text(json.dumps(
        {"machine": f"{platform.machine()} {platform.platform()}", "rows": rows}, indent=2))


if __name__ == "__main__":
    main()
