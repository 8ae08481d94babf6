"""The reference numbers of the regression guard (tests/test_regression_guard.py).

    .venv/bin/python benchmarks/regression_numbers.py            # print the current numbers
    .venv/bin/python benchmarks/regression_numbers.py --write    # store them as the reference

Each number is a cheap closed-form check of ``scenes`` (DEM and continuum). ``--write`` keeps
the tolerances and reasons already in tests/regression_reference.json and replaces the values
(do it only for a change that is meant to alter the physics, and say so in the commit).

How tolerances are chosen (``TOLERANCES``): every scene is deterministic (fixed seeds, serial
kernels, direct solvers), so a rerun on the same software gives the same number to round-off
(<1e-12 relative). A tolerance must (a) stay above what a different CPU, BLAS or numba version
can move (reassociation of sums: ~1e-10 relative for the DEM numbers, Newton's rtol 1e-8 for the
continuum ones, so at least 1e-7 of the value) and (b) stay below the smallest change that a
real physics or solver change makes. Measured: a 10 % change of the time-step safety
(0.5 -> 0.45 / 0.55) moves the sliding error by 1.2e-4 / 1.8e-3 (2026-12-01, edge elements,
the block settled before it is tilted), the period error by 5e-4, the
energy drift by 1e-5 / 7.5e-5 and the brick-bar peak error by 2.7e-3 / 7.0e-3; kn x 1.1 moves the
sliding error by 8.2e-4; damping 0.8 -> 0.75 moves the brick-bar error by 4.2e-4; the next footing
mesh (h_min 0.05) moves q/c by 0.08. Each absolute tolerance in ``TOLERANCES`` is at least 10x
below the smallest of these for its number and at least 1e4x above round-off.
"""
from __future__ import annotations

import json
import sys
from pathlib import Path

import scenes

REFERENCE = scenes.ROOT / "tests" / "regression_reference.json"

# name -> (absolute tolerance on the number, what it is / why that tolerance)
TOLERANCES = {
    "dem.sliding_block.rel_error": (1e-6, "acceleration error, 30 deg / 20 deg, safety 0.5, "
                                    "undamped, settled first; safety 0.9 moves it by 9.3e-4"),
    "dem.oscillation.rel_error": (1e-5, "period error, safety 0.5; safety 0.75 moves it by 3e-3"),
    "dem.oscillation.energy_drift": (1e-7, "energy drift over 20 periods (1.2e-4)"),
    "dem.brick_bar.rel_error": (1e-5, "peak stress / T - 1, 10 mm bricks, 2 mm/s; damping 0.75 "
                                "moves it by 4.2e-4"),
    "dem.cantilever_10mm.deflection_um": (1e-3, "tip deflection (micrometres) of the 10 mm "
                                          "Voronoi cantilever solved to ratio 1e-4 (tol 1e-5 "
                                          "relative to ~16 um)"),
    "dem.auto_dt_kn1e12.ns": (1e-3, "automatic time step (ns) of the stability specimen, "
                              "kn 1e12, ks 5e11 (a change of the step rule or of the geometry)"),
    "continuum.gravity_column_P2.rel_error": (1e-10, "settlement error, P2: exact to round-off"),
    "continuum.gravity_column_P1_h0.5.stress_rel_error": (1e-7, "sigma_yy error of P1 at h 0.5 "
                                                          "(6.9e-3; h 0.25 halves it)"),
    "continuum.footing_h0.1.q_over_c": (1e-4, "collapse pressure / c, h_min 0.1 m (5.367); "
                                        "h_min 0.05 gives 5.286"),
}


def measure() -> dict:
    from dem_core.contact.materials import Material
    from dem_core.model import Model

    out = {}
    out["dem.sliding_block.rel_error"] = scenes.sliding_block()["rel_error"]
    osc = scenes.oscillation_period()
    out["dem.oscillation.rel_error"] = osc["rel_error"]
    out["dem.oscillation.energy_drift"] = osc["energy_drift"]
    out["dem.brick_bar.rel_error"] = scenes.brick_bar_tension()["rel_error"]
    # cantilever without the E measurement: the deflection itself
    from dem_core.model import Model as _M  # noqa: F401
    bs = scenes.voronoi_bar(0.3, 0.03, edge=0.01, seed=3)
    m = Model(bs, scenes.spec_materials(1.0), density=2500.0, damping=0.8)
    m.remove("right")
    m.fix("left")
    m.set_gravity(1.0)
    m.add_history_point("tip", (0.3, 0.015))
    m.solve(ratio=1e-4, max_steps=100_000)
    out["dem.cantilever_10mm.deflection_um"] = -1e6 * m.point_motion("tip")[1]
    mats = {"flaw:*": Material(kn=1e12, ks=5e11, tensile_strength=1e5, cohesion=2e5,
                               friction=35),
            "boundary:*": Material(kn=1e12, ks=5e11, friction=35)}
    m = Model(scenes.stability_specimen(), mats, density=2500, damping=0.0)
    m.fix("base")
    out["dem.auto_dt_kn1e12.ns"] = 1e9 * m.dt
    try:
        import dolfinx  # noqa: F401
    except ImportError:
        return out
    out["continuum.gravity_column_P2.rel_error"] = scenes.gravity_column(h=1.0)["rel_error"]
    out["continuum.gravity_column_P1_h0.5.stress_rel_error"] = scenes.gravity_column(
        h=0.5, degree=1)["stress_rel_error"]
    out["continuum.footing_h0.1.q_over_c"] = scenes.strip_footing(h_min=0.1)["measured"]
    return out


def main():
    values = measure()
    for k, v in values.items():
        print(f"{k:52s} {v:+.10e}")
    if "--write" in sys.argv:
        ref = {"machine": scenes.machine(), "how_tolerances_were_chosen":
               __doc__.split("How tolerances are chosen")[1].strip(), "numbers": {}}
        for k, v in values.items():
            tol, why = TOLERANCES[k]
            ref["numbers"][k] = {"value": v, "abs_tolerance": tol, "what": why}
        REFERENCE.write_text(json.dumps(ref, indent=1))
        print(f"wrote {REFERENCE}")


if __name__ == "__main__":
    main()
