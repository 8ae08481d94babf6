"""Which fracture energies can the thesis's cases resolve at the thesis's flaw sizes? (issue 54)

Issue 54 asks for every case rerun with softening flaws, G_I swept over a plausible range (the
thesis gives none; for rock, G_I = K_Ic^2 / E of 10-100 J/m^2 is the usual range). Two bounds
of the flaw law (``dem_core.contact.softening``) decide where such a sweep means anything:

- no snap-back at a contact (linear softening): G_I > T^2 / (2 kn), below which the material
  is refused before any step;
- a resolved softening zone: Hillerborg's l_ch = E' G_I / T^2 spans at least
  ``RESOLVED_SPACINGS`` blocks, i.e. G_I >= RESOLVED_SPACINGS d T^2 / E' (below it the model
  warns, and the answer depends on block size again, docs/verification.md),

with kn, ks the flaw's stiffness in series with two half-blocks of the scene's block modulus
(``elastic.series_stiffness``, h = d / 2 each side) and E' the plane modulus of that lattice
(``elastic.lattice_moduli``), d the centroid spacing, taken here as the case's flaw edge: an
estimate at the median contact (the model's own check refuses a G that snaps back at its
softest contact, and reports the l_ch of a built scene, ``softening.characteristic_lengths``). For each case, at
its scene's default (the thesis's) flaw size and stiffness and at the T values its results
turn on, this prints both bounds and the largest flaw size at which 10 / 30 / 100 J/m^2 are
resolved. No model is run; writes results/benchmarks/field_softening_bounds.json
(``--reference``: benchmarks/results/).

    python benchmarks/trials/field_softening_bounds.py [--reference]
"""
from __future__ import annotations

import argparse
import importlib
import json
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
sys.path.insert(0, str(Path(__file__).resolve().parents[2]))

import outdir  # noqa: E402
from dem_core.contact.elastic import lattice_moduli, series_stiffness  # noqa: E402
from dem_core.contact.softening import RESOLVED_SPACINGS  # noqa: E402

PLAUSIBLE_G = (10.0, 30.0, 100.0)      # J/m^2

# case: (params class, the flaw material's name in ``materials(params)``, the T values (Pa)
# the case's results turn on: the thesis's start and its T at failure)
CASES = {
    "adhikary": ("AdhikaryParams", "flaw:rock", (1.4e6, 1.1e6, 0.8e6)),
    "longtan": ("LongtanParams", "flaw:*", (4.81e6, 2.5e6)),
    "underdip": ("UnderdipParams", "flaw:zone", (60e3, 10e3)),
    "common_toppling": ("ToppleParams", "*", (7e6, 1e6)),
    "coal_buckling": ("CoalBucklingParams", "flaw:layer", (30e3, 10e3)),
    "highwood": ("HighwoodParams", "*:q*", (1.15e6, 0.2e6)),
    "lornex": ("LornexParams", None, (1e6, 0.1e6)),          # None: the first "flaw:" one
    "checkerboard": ("CheckerboardParams", "flaw:weathered_gneiss", (0.65e6, 0.025e6)),
}


def bounds(kn: float, ks: float, d: float, t: float) -> dict:
    """G_I (J/m^2) below which a linear softening snaps back (``G_snap``) and below which
    its l_ch spans fewer than RESOLVED_SPACINGS blocks of spacing d (``G_resolved``); the
    largest d (m) at which each plausible G is resolved."""
    e2 = lattice_moduli(kn, ks, d)["E_2d"]
    # refining the flaws at a fixed modulus E_2d (kn scaled as E / d, the thesis's eq. 3.7),
    # G_resolved falls in proportion to d: the largest d that resolves G is G E_2d / (R T^2)
    return {"T_MPa": t / 1e6, "E2d_GPa": e2 / 1e9,
            "G_snap": t * t / (2.0 * kn),
            "G_resolved": RESOLVED_SPACINGS * d * t * t / e2,
            "largest_d_m": {f"{g:g}": g * e2 / (RESOLVED_SPACINGS * t * t) for g in PLAUSIBLE_G}}


def case_rows(name: str) -> dict:
    params_cls, material, ts = CASES[name]
    mod = importlib.import_module(f"comparisons.scenes.{name}")
    p = getattr(mod, params_cls)()
    mats = mod.materials(p)
    key = material or next(k for k in mats if k.startswith("flaw:"))
    m = mats[key]
    d = float(p.edge_length)
    E, nu = float(p.block_E), float(getattr(p, "block_nu", getattr(mod, "NU", 0.25)))
    kn, ks = (float(x) for x in series_stiffness(m.kn, m.ks, d / 2, d / 2, E, nu, E, nu))
    return {"material": key, "kn_table": m.kn, "kn": kn, "ks": ks, "flaw_edge_m": d,
            "block_E": E, "rows": [bounds(kn, ks, d, t) for t in ts]}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    outdir.add_reference_flag(ap)
    a = ap.parse_args(argv)
    out = {"resolved_spacings": RESOLVED_SPACINGS, "plausible_G": PLAUSIBLE_G,
           "cases": {name: case_rows(name) for name in CASES}}
    path = outdir.results_dir(a.reference) / "field_softening_bounds.json"
    path.write_text(json.dumps(out, indent=1))
    print("case | flaw edge (m) | T (MPa) | G snap-back | G resolved | largest edge for "
          "10 / 30 / 100 J/m^2 (m)")
    for name, c in out["cases"].items():
        for r in c["rows"]:
            ds = " / ".join(f"{v:.3g}" for v in r["largest_d_m"].values())
            print(f"{name} | {c['flaw_edge_m']:g} | {r['T_MPa']:g} | {r['G_snap']:.3g} | "
                  f"{r['G_resolved']:.3g} | {ds}")
    print(path)


if __name__ == "__main__":
    main()
