"""The coal footwall layer's thrust line with another basal friction (issue 54).

The case (``comparisons.coal_buckling``) reads the layer's thrust line after every stage of its
quick member (``run_member``: gravity at table 5.4's strengths, T lowered to 0, then the
cohesion to 0; ``thrust``). This runs the same member with the basal plane's friction changed,
which changes the thrust the layer hands to its toe (the free slab's, ``free_slab_thrust``):
does more thrust buckle it? Prints the thrust at the toe against the free slab's, the largest
|e| / t on the exposed layer and the verdicts; writes
results/benchmarks/thrust_line_coal_buckling[_phibF].json and .png (``--reference``:
benchmarks/results/).

    python benchmarks/trials/thrust_line.py [--basal-friction 0] [--edge 0.7] [--reference]
"""
from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))

from benchmarks import outdir  # noqa: E402
from comparisons import coal_buckling  # noqa: E402
from comparisons.scenes import coal_buckling as scene  # noqa: E402


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--edge", type=float, default=0.7, help="Voronoi cell edge (m)")
    ap.add_argument("--basal-friction", type=float, default=None,
                    help="the basal plane's friction (deg; default table 5.4's 20)")
    outdir.add_reference_flag(ap)
    a = ap.parse_args(argv)
    out = outdir.results_dir(a.reference)
    v = dict(coal_buckling.VARIANTS["quick"], edge_length=a.edge)
    member = coal_buckling.members(v, 1)[0]
    if a.basal_friction is not None:
        member["params"]["basal_friction"] = a.basal_friction
    p = scene.CoalBucklingParams(**member["params"])
    run = coal_buckling.run_member(member)
    name = "thrust_line_coal_buckling" + (
        "" if a.basal_friction is None else f"_phib{a.basal_friction:g}")
    toe_n, slab_n, e_max = coal_buckling.thrust_at_toe(run["thrust"])
    result = {"edge_m": a.edge, "basal_friction_deg": p.basal_friction,
              "toe_thrust_MN_per_m": toe_n / 1e6, "free_slab_MN_per_m": slab_n / 1e6,
              "largest_e_over_t_exposed": e_max,
              "verdicts": [st["verdict"] for st in run["stages"]], "cracks": run["cracks"],
              "seconds": run["runtime_s"], "thrust": run["thrust"]}
    (out / f"{name}.json").write_text(json.dumps(result, indent=1))
    fig = coal_buckling.thrust_figure(run, p)
    fig.savefig(out / f"{name}.png", dpi=120)
    s = np.asarray(run["thrust"]["stations_m"])
    n_grav = np.interp(0.0, s, run["thrust"]["after_gravity"]["N"])
    print(f"basal friction {p.basal_friction:g} deg: toe thrust {n_grav / 1e6:.2f} MN/m after "
          f"gravity, {toe_n / 1e6:.2f} at the end (free slab {slab_n / 1e6:.2f}); largest "
          f"|e|/t on the exposed layer {e_max:.3f}; verdicts {result['verdicts']}; "
          f"{run['runtime_s']:.0f} s; {out / name}.png")


if __name__ == "__main__":
    main()
