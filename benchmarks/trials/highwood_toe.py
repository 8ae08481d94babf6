"""Highwood: why the surface beds stand at T = 0, and how much that hangs on the assumed toe
(issue 54, outcome (b) for "T at failure rising with k").

Two parts.

1. **The energy barrier of a bed leaning on the limestone** (closed form, Rayleigh-Ritz). A
   bed of thickness t dipping psi rests on the limestone behind it; per metre of width its
   weight gives the axial load q = gamma t sin(psi) (N/m per m along the bed) and presses it
   on the wall with q_n = gamma t cos(psi). Take the bed as a cantilever of length L fixed at
   its foot and an outward deflection w(x) = a phi(x), phi = 1 - cos(pi x / 2L) (x up the
   bed; one-sided, so the wall does not forbid it). The change of potential energy is

       dPi(a) = a q_n I0 - a^2 / 2 (q I1 - EI I2),
       I0 = int phi = L (1 - 2/pi),  I1 = int (L - x) phi'^2 = (pi^2/4)(1/4 + 1/pi^2),
       I2 = int phi''^2 = pi^4 / (32 L^3),

   linear in a for the pressing weight, quadratic for the axial load against the bending
   stiffness. When q I1 > EI I2 (the bed is longer than Euler's self-weight length
   L_cr = (7.837 EI / q)^(1/3), Greenhill 1881) the straight bed is still stable against small
   deflections: it must be pushed out by a* = q_n I0 / (q I1 - EI I2) before it can buckle,
   over an energy barrier q_n^2 I0^2 / (2 (q I1 - EI I2)). A bed with no bending stiffness
   left (EI -> 0, cracked through at T = 0) keeps the same barrier to within EI's share. This is
   the pipeline's upheaval buckling (Hobbs 1984): a straight bar held down by its own weight
   needs an imperfection to buckle, however large its axial load.

2. **Sensitivity of the quick case to the assumed toe** (``comparisons.highwood`` quick, k =
   0.5 and 3, the case's solver and judge, no continuum): depth of rock under the toe level
   (``base``: 10 m assumed; 30 and 60), toe bench (``toe_length``: 10 m assumed; 2 and 40),
   and the dip (``face_dip``: 84 (the thesis) and 88 degrees, a quarter of the pressing
   weight's cos(psi)).

References: A. G. Greenhill (1881), "Determination of the greatest height consistent with
stability that a vertical pole or mast can be made", Proc. Cambridge Philos. Soc. 4, 65-73;
R. E. Hobbs (1984), "In-service buckling of heated pipelines", J. Transp. Eng. (ASCE) 110(2),
175-189; the Rayleigh-Ritz energy of a self-weight cantilever as in S. P. Timoshenko and J. M.
Gere (1961), Theory of Elastic Stability, sec. 2.13.

Writes results/benchmarks/highwood_toe.json and .png (``--reference``: benchmarks/results/).

    python benchmarks/trials/highwood_toe.py [--skip-runs] [--reference]
"""
from __future__ import annotations

import argparse
import json
import math
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
sys.path.insert(0, str(Path(__file__).resolve().parents[2]))

import outdir  # noqa: E402
from scenes import machine  # noqa: E402

GAMMA = 25e3          # N/m3 (table 5.5)
E = 20e9              # Pa (table 5.5)
# the quick's parameters (comparisons.highwood.VARIANTS["quick"]["params"])
QUICK = dict(edge_length=0.5, quartzite_beds=(0.4, 0.8, 1.2), limestone_cross=1.2,
             limestone_depth=3.0, relax_iterations=10)
CHANGES = [dict(), dict(base=30.0), dict(base=60.0), dict(toe_length=2.0),
           dict(toe_length=40.0), dict(face_dip=88.0)]


def _terms(t: float, dip_deg: float, length: float, ei_factor: float) -> tuple:
    """(q, q_n I0, q I1 - EI I2): the axial load (N/m per m), the pressing weight's linear
    coefficient and the quadratic one of dPi (module docstring)."""
    psi = math.radians(dip_deg)
    q, qn = GAMMA * t * math.sin(psi), GAMMA * t * math.cos(psi)
    ei = ei_factor * E * t ** 3 / 12.0
    i0 = length * (1.0 - 2.0 / math.pi)
    i1 = math.pi ** 2 / 4.0 * (0.25 + 1.0 / math.pi ** 2)
    i2 = math.pi ** 4 / (32.0 * length ** 3)
    return q, qn * i0, q * i1 - ei * i2


def barrier(t: float, dip_deg: float, length: float, ei_factor: float = 1.0) -> dict:
    """The Rayleigh-Ritz barrier (module docstring) of a bed t (m) thick, dipping dip_deg,
    length (m) from its fixed foot to its top; ei_factor scales E t^3 / 12 (0: cracked)."""
    q, lin, soft = _terms(t, dip_deg, length, ei_factor)
    l_cr = (7.837 * E * t ** 3 / 12.0 / q) ** (1.0 / 3.0)
    out = {"t_m": t, "dip_deg": dip_deg, "length_m": length, "ei_factor": ei_factor,
           "greenhill_length_m": round(l_cr, 2), "q_N_per_m": q,
           "qn_N_per_m": GAMMA * t * math.cos(math.radians(dip_deg))}
    if soft <= 0:
        return dict(out, unstable=False, a_star_m=None, barrier_J_per_m=None)
    a_star = lin / soft
    return dict(out, unstable=True, a_star_m=round(a_star, 3),
                barrier_J_per_m=round(0.5 * lin * a_star, 1))


def energy_curve(t, dip_deg, length, ei_factor, a):
    """dPi (J/m) at each outward deflection in ``a`` (m)."""
    _, lin, soft = _terms(t, dip_deg, length, ei_factor)
    return [x * lin - 0.5 * x * x * soft for x in a]


def sensitivity() -> list:
    from comparisons import highwood

    rows = []
    for change in CHANGES:
        v = dict(highwood.VARIANTS["quick"], params=dict(QUICK, **change), continuum=False)
        t0 = time.perf_counter()
        dem = highwood.run(v, seed=1).methods["dem"]
        rows.append({"change": change or "as assumed (base 10, toe 10, dip 84)",
                     "stress_ratio": dem["stress_ratio"], "failure_T_MPa": dem["failure_T_MPa"],
                     "last_stable_T_MPa": dem["last_stable_T_MPa"],
                     "onset_T_MPa": dem["onset_T_MPa"], "cracks": dem["cracks"],
                     "blocks": dem["blocks"], "seconds": round(time.perf_counter() - t0, 1)})
        print(json.dumps(rows[-1]), flush=True)
    return rows


def figure(path, length):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    a = [0.05 * i for i in range(0, 241)]
    fig, ax = plt.subplots(figsize=(7.5, 4.5))
    for dip, ls in ((84.0, "-"), (88.0, "--")):
        for ei, colour, what in ((1.0, "tab:blue", "intact"), (0.0, "tab:red", "cracked, EI = 0")):
            b = barrier(0.4, dip, length, ei)
            ax.plot(a, [e / 1e3 for e in energy_curve(0.4, dip, length, ei, a)], ls=ls,
                    color=colour, label=f"dip {dip:g} deg, {what}: a* = {b['a_star_m']:.2f} m")
    ax.axhline(0.0, color="0.5", lw=0.8)
    ax.set_xlabel("outward deflection of the bed's top, a (m)")
    ax.set_ylabel("change of potential energy (kJ per m of width)")
    ax.set_title(f"Outer quartzite bed (t = 0.4 m, L = {length:g} m) leaning on the limestone:\n"
                 "the straight bed is stable until pushed out by a* (Rayleigh-Ritz, cantilever mode)")
    ax.set_ylim(bottom=-50)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--skip-runs", action="store_true", help="the closed form only")
    outdir.add_reference_flag(ap)
    a = ap.parse_args()
    from comparisons.scenes import highwood as hs
    p = hs.HighwoodParams()
    length = p.base + p.slope_height          # the outer bed, from the fixed base to the crest
    closed = [barrier(t, dip, length, ei) for t in p.quartzite_beds for dip in (84.0, 88.0)
              for ei in (1.0, 0.0)]
    for row in closed:
        print(json.dumps(row))
    out = {"closed_form": closed, "sensitivity": [] if a.skip_runs else sensitivity(),
           "machine": machine()}
    folder = outdir.results_dir(a.reference)
    (folder / "highwood_toe.json").write_text(json.dumps(out, indent=1))
    figure(folder / "highwood_toe.png", length)
    print("wrote", folder / "highwood_toe.json")


if __name__ == "__main__":
    main()
