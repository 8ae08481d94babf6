"""Stability map: the largest stable fixed time step of the DEM against the automatic one, and
Newton iterations / failures of the continuum for hard Hoek-Brown and Mohr-Coulomb cases.

    .venv/bin/python benchmarks/stability_map.py [--quick | --full] [--only dem|continuum]
                                                 [--softening]

DEM. The specimen of ``tests/test_mech_stability.py`` (a bonded Voronoi block on a fixed base,
released under gravity, undamped) for kn 1e8..1e15 Pa/m, kn/ks 0.1..100, g-level 1 and 150 and
two or three block sets (relaxed tessellation; sliver control off, which leaves the smallest
blocks the geometry makes). For each case ``auto_dt`` is ``Model(...).dt`` (safety 0.5) and the
largest stable step is found by bisection (in log dt, to 2 %) on a fixed ``Model(dt=...)``:
stable = the run of ``steps`` steps finishes without ``ModelUnstable``, with finite positions
and total energy (kinetic + spring + gravity, which starts at 0) never above 5 % of the largest
spring energy seen. ``stable_over_eigen`` = largest stable dt / the critical step from the
largest eigenvalue (``Model(step_estimate="eigen").critical_dt``, ``dem_core.step.critical_step``):
1 when that estimate is exact and the energy criterion measures stability (it measures the
energy error, i.e. accuracy, where that error passes 5 % below the limit: docs/mechanics.md).
``margin = largest stable dt / auto_dt``; > 1 means the automatic step is
safe. A bisection only brackets the stability limit of that run length: growth slower than
``steps`` steps is not seen (``--full`` doubles the steps).

Continuum. A smooth rigid strip footing (half model, B = 1 m) on rock with weight (gravity
first, then a prescribed settlement of 2 B sigma_cm / E, sigma_cm the rock-mass strength, so
every case is loaded to the same multiple of its strength): generalized Hoek-Brown for GSI 10..100, mi, D; Mohr-Coulomb with friction
near 0 and near 60 degrees. Each case is run twice: without step cutting
(``min_step`` = the step) and with the default cutting (halve on failure down to 1e-3).
Records convergence, load reached, steps, Newton iterations (converged steps) and run time.
Writes results/benchmarks/stability_map.json and .png (``--only dem``: stability_map_dem.*;
``--reference``: benchmarks/results/).
"""
from __future__ import annotations

import math
import time

import numpy as np

import scenes


# ------------------------------------------------------------------ DEM
# --softening: the flaws soften (``dem_core.contact.softening``) with fracture energies 20
# times their snap-back limits, T^2 / 2kn and c^2 / 2ks, and the second g-level is 3000, where
# most flaws of the specimen pass their peak (tests/test_mech_stability.py)
SOFTENING = {"on": False}


def _materials(kn, ks):
    from dem_core.contact.materials import Material

    T, c = 1e5, 2e5
    soft = (dict(fracture_energy_I=20 * T * T / (2 * kn), fracture_energy_II=20 * c * c / (2 * ks))
            if SOFTENING["on"] else {})
    return {"flaw:*": Material(kn=kn, ks=ks, tensile_strength=T, cohesion=c, friction=35,
                               **soft),
            "boundary:*": Material(kn=kn, ks=ks, friction=35)}


def _is_stable(bs, kn, ks, g_level, dt, steps):
    from dem_core.model import Model, ModelUnstable

    m = Model(bs, _materials(kn, ks), density=2500, damping=0.0, dt=dt)
    m.fix("base")
    m.set_gravity(g_level)
    se_max, worst = 0.0, -np.inf
    try:
        for _ in range(steps // 100):
            m.cycle(100)
            se = m.strain_energy()
            se_max = max(se_max, se)
            worst = max(worst, m.kinetic_energy() + se + m.gravity_energy())
    except ModelUnstable:
        return False
    return bool(np.isfinite(m.state.pos).all() and np.isfinite(worst)
                and worst <= 0.05 * se_max)


def auto_dt(bs, kn, ks, step_estimate="bound"):
    """(automatic dt, search margin, critical dt) of the specimen, the critical step
    bounded (``step_estimate="bound"``) or from the largest eigenvalue ("eigen")."""
    from dem_core.model import Model

    m = Model(bs, _materials(kn, ks), density=2500, damping=0.0, step_estimate=step_estimate)
    m.fix("base")
    return m.dt, m.search_margin, m.critical_dt


def largest_stable_dt(bs, kn, ks, g_level, steps, rel_tol=0.02):
    """Bisection in log dt; returns (largest stable dt, auto dt, evaluations, stable at auto)."""
    dt0 = auto_dt(bs, kn, ks)[0]
    evals = 1
    stable_auto = _is_stable(bs, kn, ks, g_level, dt0, steps)
    if not stable_auto:
        lo, hi = dt0 / 64, dt0
        while not _is_stable(bs, kn, ks, g_level, lo, steps) and lo > dt0 / 4096:
            hi, lo = lo, lo / 4
            evals += 1
    else:
        lo, hi = dt0, 2 * dt0
        while _is_stable(bs, kn, ks, g_level, hi, steps):
            evals += 1
            lo, hi = hi, 2 * hi
            if hi > 256 * dt0:
                break
        evals += 1
    while hi / lo > 1 + rel_tol:
        mid = math.sqrt(lo * hi)
        evals += 1
        if _is_stable(bs, kn, ks, g_level, mid, steps):
            lo = mid
        else:
            hi = mid
    return lo, dt0, evals, stable_auto


def dem_map(full, log):
    kns = [1e8, 1e10, 1e12, 1e15] if not full else [1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15]
    ratios = [0.1, 1.0, 10.0, 100.0] if not full else [0.1, 0.3, 1.0, 3.0, 10.0, 30.0, 100.0]
    g_levels = [1.0, 3000.0 if SOFTENING["on"] else 150.0]
    steps = 2000 if not full else 4000
    block_sets = {"10 mm, relaxed": scenes.stability_specimen(),
                  "10 mm, sliver control off": scenes.stability_specimen(min_fraction=0.0,
                                                                         seed=4, relax=0)}
    rows = []
    for name, bs in block_sets.items():
        small = float(bs.area.min() / np.median(bs.area))
        for kn in kns:
            for r in ratios:
                for g in g_levels:
                    t0 = time.perf_counter()
                    dt_max, dt_auto, evals, ok = largest_stable_dt(bs, kn, kn / r, g, steps)
                    # static overlap at the base (rho g n H / kn) against the search margin:
                    # above 1 the blocks interpenetrate further than the contact search sees
                    margin = auto_dt(bs, kn, kn / r)[1]
                    eigen = auto_dt(bs, kn, kn / r, "eigen")[2]
                    overlap = 2500 * 9.81 * g * 0.05 / kn
                    row = {"blocks": name, "n_blocks": bs.n_blocks,
                           "smallest_area_over_median": small, "kn": kn, "kn_over_ks": r,
                           "g_level": g, "auto_dt": dt_auto, "largest_stable_dt": dt_max,
                           "margin": dt_max / dt_auto, "auto_dt_stable": ok,
                           # the critical step from the largest eigenvalue: 1 if it is exact
                           "eigen_critical_dt": eigen, "stable_over_eigen": dt_max / eigen,
                           "overlap_over_search_margin": overlap / margin,
                           "evaluations": evals, "seconds": time.perf_counter() - t0}
                    rows.append(row)
                    log(f"  {name:26s} kn {kn:.0e} kn/ks {r:5g} g {g:5g}: auto {dt_auto:.3e} s, "
                        f"largest stable {dt_max:.3e} s, margin {row['margin']:.2f}, "
                        f"over the eigen critical {row['stable_over_eigen']:.3f}"
                        f"{'' if ok else '  AUTO UNSTABLE'}")
    valid = [r for r in rows if r["overlap_over_search_margin"] < 1.0]
    return {"steps_per_run": steps, "rel_tol": 0.02, "rows": rows,
            "min_margin_valid_scenes": min(r["margin"] for r in valid),
            "stable_over_eigen_valid_scenes": [min(r["stable_over_eigen"] for r in valid),
                                               max(r["stable_over_eigen"] for r in valid)],
            "auto_unstable": [(r["blocks"], r["kn"], r["kn_over_ks"], r["g_level"],
                               r["overlap_over_search_margin"]) for r in rows
                              if not r["auto_dt_stable"]],
            "min_margin": min(r["margin"] for r in rows),
            "max_margin": max(r["margin"] for r in rows),
            "all_auto_stable": all(r["auto_dt_stable"] for r in rows)}


# ------------------------------------------------------------------ continuum
def footing_case(material, cutting, strength, h_min=0.1, h_max=0.3, steps=10, density=2500.0):
    """Strip footing on rock with weight: gravity first (one step, elastic-plastic), then a
    prescribed settlement of 2 B sigma_cm / E (B = 1 m, sigma_cm the rock-mass strength), so
    every case is loaded to the same multiple of its own strength."""
    from continuum_ref.mesh import PolygonRegion, build_mesh, refine_near
    from continuum_ref.model import ContinuumModel

    half = 0.5
    t0 = time.perf_counter()
    md = build_mesh([PolygonRegion("rock", [(0, -2), (3, -2), (3, 0), (half, 0), (0, 0)])],
                    h_max, size_field=refine_near([(half, 0.0)], h_min, h_max, 0.05, 1.0))
    model = ContinuumModel(md, material, density)
    model.fix(lambda x: np.isclose(x[0], 0.0) | np.isclose(x[0], 3.0), (0,))
    model.fix(lambda x: np.isclose(x[1], -2.0), (0, 1))
    under = lambda x: np.isclose(x[1], 0.0) & (x[0] <= half + 1e-9)  # noqa: E731
    settlement = 2.0 * 1.0 * strength / material.E
    step = 1.0 / steps
    no_cut = (lambda st: st * 0.999) if not cutting else (lambda st: None)
    try:
        rg = model.solve_gravity(1.0, first_step=1.0, min_step=no_cut(1.0))
        model.fix(under, (1,), value=(-settlement,))
        r = model.solve_load(1.0, first_step=step, min_step=no_cut(step)) if rg.converged else rg
    except Exception as exc:       # noqa: BLE001 - a solver crash is a result here (reported)
        return {"converged": False, "load_reached": float("nan"), "steps": -1,
                "newton_iterations": -1, "iterations_per_step": float("nan"),
                "pressure_over_strength": float("nan"), "seconds": time.perf_counter() - t0,
                "settlement_m": settlement,
                "error": f"{type(exc).__name__}: {str(exc).splitlines()[0]}"}
    q = -model.reaction(under, 1) / half
    return {"converged": bool(rg.converged and r.converged),
            "gravity_converged": bool(rg.converged),
            "load_reached": float(r.load_reached) if rg.converged else 0.0,
            "steps": int(r.steps), "newton_iterations": int(r.newton_iterations),
            "iterations_per_step": r.newton_iterations / max(r.steps, 1),
            "pressure_over_strength": float(q / strength), "settlement_m": settlement,
            "seconds": time.perf_counter() - t0,
            "dofs": int(model.V.dofmap.index_map.size_global * 2)}


VARIANTS = {"10 steps, no cutting": (10, False), "10 steps, cutting": (10, True),
            "2 steps, no cutting": (2, False), "2 steps, cutting": (2, True)}


def continuum_map(full, log):
    from continuum_ref import hoek_brown as hb
    from continuum_ref.materials import HoekBrown, MohrCoulomb

    sci = 50e6
    gsis = [10, 40, 100] if not full else [10, 25, 40, 55, 70, 85, 100]
    mis = [5, 25] if not full else [5, 15, 25, 35]
    Ds = [0.0, 1.0]
    cases = []
    for gsi in gsis:
        for mi in mis:
            for D in Ds:
                mat = HoekBrown.from_gsi(gsi, mi, sci, D=D, nu=0.3)
                scm = hb.global_strength(sci, mat.mb, mat.s, mat.a)
                cases.append((f"HB GSI {gsi} mi {mi} D {D:g}",
                              dict(law="HB", gsi=gsi, mi=mi, D=D), mat, scm))
    for phi in ([0.0, 1.0, 59.0, 60.0] if not full else [0.0, 0.5, 1.0, 2.0, 58.0, 59.0, 60.0]):
        for psi in (0.0, phi):
            c = 1e6
            ucs = 2 * c * math.cos(math.radians(phi)) / (1 - math.sin(math.radians(phi)))
            cases.append((f"MC phi {phi:g} psi {psi:g}", dict(law="MC", friction=phi, dilation=psi),
                          MohrCoulomb(E=1e9, nu=0.3, cohesion=c, friction=phi, dilation=psi),
                          ucs))
    rows = []
    for name, params, mat, strength in cases:
        row = {"case": name, **params, "E": mat.E}
        line = f"  {name:24s}"
        for key, (steps, cutting) in VARIANTS.items():
            r = footing_case(mat, cutting, strength, steps=steps)
            row[key] = r
            line += (f" | {key}: {'ok ' if r['converged'] else 'FAIL'} "
                     f"{r['load_reached']:.2f} {r['newton_iterations']:4d} it")
            if "error" in r:
                log(f"  {name}: {key}: solver raised {r['error']}")
        rows.append(row)
        log(line)
    return {"problem": "smooth strip footing B = 1 m on rock of 2500 kg/m3 (gravity first), "
                       "settlement 2 B sigma_cm / E in 10 load steps, P2, h_min 0.1 m",
            "sci_Pa": sci, "rows": rows,
            "failed": {k: [r["case"] for r in rows if not r[k]["converged"]] for k in VARIANTS},
            "rescued_by_cutting": {
                n: [r["case"] for r in rows if not r[f"{n} steps, no cutting"]["converged"]
                    and r[f"{n} steps, cutting"]["converged"]] for n in (10, 2)},
            "solver_raised": [(r["case"], k, r[k]["error"]) for r in rows
                              for k in VARIANTS if "error" in r[k]]}


def plot(out, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    panels = []
    if "dem" in out:
        panels += ["dem"]
    if "continuum" in out:
        panels += ["continuum"]
    fig, axes = plt.subplots(1, len(panels) + ("dem" in out), figsize=(6.5 * (len(panels) + 1), 5),
                             squeeze=False)
    axes = list(axes.flat)
    if "dem" in out:
        rows = out["dem"]["rows"]
        ax = axes.pop(0)
        for name, mk in zip(dict.fromkeys(r["blocks"] for r in rows), "os^"):
            for g, col in ((1.0, "C0"), (150.0, "C3")):
                for valid in (True, False):
                    sel = [r for r in rows if r["blocks"] == name and r["g_level"] == g
                           and (r["overlap_over_search_margin"] < 1.0) == valid]
                    if not sel:
                        continue
                    ax.scatter([r["kn"] * (1 + 0.15 * np.log10(r["kn_over_ks"])) for r in sel],
                               [r["margin"] for r in sel], marker=mk, alpha=0.7,
                               c=col if valid else "none", edgecolors=col,
                               label=f"{name}, {g:g} g" + ("" if valid else
                                                          " (overlap > search margin)"))
        ax.set_xscale("log")
        ax.axhline(1.0, color="k", lw=1)
        ax.set_xlabel("kn (Pa/m)  (points spread by kn/ks 0.1..100 left to right)")
        ax.set_ylabel("largest stable dt / automatic dt")
        ax.set_title("DEM: margin of the automatic time step")
        ax.legend(fontsize=7)
        ax = axes.pop(0)
        ratios = sorted(set(r["kn_over_ks"] for r in rows))
        for name, mk in zip(dict.fromkeys(r["blocks"] for r in rows), "os^"):
            sel = [r for r in rows if r["blocks"] == name and r["overlap_over_search_margin"] < 1]
            m = [min(x["margin"] for x in sel if x["kn_over_ks"] == q) for q in ratios]
            ax.semilogx(ratios, m, mk + "-", label=f"{name}: min over kn, g (overlap < margin)")
        ax.axhline(1.0, color="k", lw=1)
        ax.set_xlabel("kn / ks")
        ax.set_ylabel("min margin")
        ax.set_title("DEM: margin against kn/ks")
        ax.legend(fontsize=7)
    if "continuum" in out:
        rows = out["continuum"]["rows"]
        ax = axes.pop(0)
        x = np.arange(len(rows))
        for k, key in enumerate(VARIANTS):
            its = [max(r[key]["newton_iterations"], 0) for r in rows]
            ok = [r[key]["converged"] for r in rows]
            ax.bar(x - 0.3 + 0.2 * k, its, 0.2, color=[f"C{k}" if o else "0.75" for o in ok],
                   edgecolor=["k" if o else "r" for o in ok], label=key)
        ax.set_xticks(x)
        ax.set_xticklabels([r["case"] for r in rows], rotation=90, fontsize=6)
        ax.set_ylabel("Newton iterations (grey/red edge = failed)")
        ax.set_title("continuum: footing on HB / MC rock (grey, red edge: failed)")
        ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def main(argv=None):
    ap = scenes.quick_or_full_parser(__doc__.splitlines()[0])
    ap.add_argument("--only", choices=["dem", "continuum"])
    ap.add_argument("--softening", action="store_true",
                    help="DEM flaws that soften (fracture energies 20x the snap-back limit), "
                         "at 1 g and 3000 g; writes stability_map_softening.*")
    a = ap.parse_args(argv)
    SOFTENING["on"] = a.softening
    out = {"machine": scenes.machine(), "mode": "full" if a.full else "quick"}
    t0 = time.perf_counter()
    if a.only != "continuum":
        out["dem"] = dem_map(a.full, print)
        print(f"DEM margin {out['dem']['min_margin']:.2f} .. {out['dem']['max_margin']:.2f}; "
              f"valid scenes (overlap < search margin) from "
              f"{out['dem']['min_margin_valid_scenes']:.2f}")
    if a.only != "dem":
        out["continuum"] = continuum_map(a.full, print)
    out["wall_seconds"] = time.perf_counter() - t0
    name = "stability_map" if a.only is None else f"stability_map_{a.only}"
    name = "stability_map_softening" if a.softening else name
    path = scenes.write_json(name, out, a.reference)
    plot(out, scenes.results_dir(a.reference) / f"{name}.png")
    print(f"wrote {path} ({out['wall_seconds']:.0f} s)")


if __name__ == "__main__":
    main()
