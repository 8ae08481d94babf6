"""Error against run time of the centrifuge cases (Adhikary, Longtan): failure g by block size.

One damage-model g-ramp (the base flaw T: adhikary 1.1 MPa, longtan 4.81 MPa) per block edge
length with the case's full variant's solver (adhikary: 10 g levels, the failed level bisected
and the ramp closed in 1 g steps, the thesis's loading; longtan: 20 g levels bisected to 2 g;
kinetic damping; a step limit per level that grows as the blocks get smaller), run through the
case's own ``run_member``, the block sizes spread over ``--workers`` processes. The error is
taken against the experiment (adhikary 80-85 g, zero inside the range; longtan 130 g) and the
thesis's damage model (70 g; 134 g).

    python benchmarks/centrifuge_resolution.py [--case adhikary] [--edges 0.008 0.006 0.004]
                                               [--seeds 1] [--tensile 1.1] [--workers 2]
                                               [--edge-elements | --end-springs]
                                               [--judge response]
                                               [--solver '{"step_estimate": "eigen"}']

Every edge is run with every tessellation seed of ``--seeds`` (the scatter of one block size)
and every flaw tensile strength of ``--tensile`` (MPa; whether a T trend outlasts that scatter).
``--edge-elements`` runs the blocks' shared edges as linear elements (``Model(edge_elements=True)``:
the bending strength of a bonded edge no longer depends on the block size, issue 24 item 1),
``--end-springs`` as the two point contacts of UDEC (without either, the scene's: adhikary edge
elements on the eigen step since 2026-11-30, longtan end springs);
``--deformable H`` makes every block deformable with zones of H m (UDEC-DM's blocks, issue 24
item 2; the contacts then act on the zones' boundary segments). ``--judge`` is the levels'
verdict (default the full variant's, "response"; "budget": the stands-at-the-budget verdict of
the runs before 2026-11-30) and ``--solver`` further ``Model`` options as JSON (e.g. the eigen
step).

Writes results/benchmarks/centrifuge_resolution.json and .png (``--name`` renames them;
``--reference``: benchmarks/results/); ``--summary NAME ...`` draws the rows of earlier result
files in one figure (``--name``.png).
"""
from __future__ import annotations

import argparse
import json
import platform
from pathlib import Path

import numpy as np

from comparisons import adhikary, longtan
from comparisons.results import metric_error
from comparisons.sweep import run_sweep

import outdir

# G_II / G_I of the softening flaws a --fracture-energy run gives (shear fracture energies of
# rock are several to ten times the opening one; a stated choice, not a measured one)
MODE_II_RATIO = 10.0

# per case: its module, the full variant's settings, steps per level by block edge (m; finer
# blocks settle more slowly: more blocks along a column, more steps per period of its lowest
# mode; the case's own edge keeps its own setting), the base T (MPa) and the references
CASES = {
    "adhikary": dict(module=adhikary, params=adhikary.scene.AdhikaryParams,
                     max_steps={0.008: 30_000, 0.006: 40_000, 0.004: 60_000, 0.003: 80_000},
                     tensile=1.1, experiment=adhikary.REFERENCE["experiment_failure_g"],
                     thesis=adhikary.REFERENCE["thesis_dem_failure_g_T1.1"]),
    "longtan": dict(module=longtan, params=longtan.scene.LongtanParams,
                    max_steps={0.008: 30_000, 0.005: 60_000, 0.004: 70_000, 0.003: 90_000},
                    tensile=4.81, experiment=longtan.REFERENCE["experiment_failure_g"],
                    thesis=longtan.REFERENCE["thesis_dem_failure_g"]),
}


def member(edge: float, seed: int = 1, tensile_mpa: float | None = None,
           edge_elements: bool | None = None, case: str = "adhikary", zone: float = 0.0,
           fracture_energy: float = 0.0, softening_regions: str = "*", judge=None,
           solver=None) -> dict:
    """The sweep member of one block size (the case's base run at another edge, seed or T;
    ``fracture_energy`` G_I of softening flaws, J/m^2, with G_II = ``MODE_II_RATIO`` G_I;
    ``edge_elements`` None: the scene's contact model; ``judge`` the levels' verdict, default
    the full variant's; ``solver`` further Model options)."""
    spec = CASES[case]
    full = spec["module"].VARIANTS["full"]
    t = spec["tensile"] if tensile_mpa is None else tensile_mpa
    steps = spec["max_steps"]
    soft = ({"flaw_fracture_energy_I": fracture_energy,
             "flaw_fracture_energy_II": MODE_II_RATIO * fracture_energy}
            if fracture_energy else {})
    if fracture_energy and softening_regions != "*":      # (longtan: "zone*")
        soft["flaw_softening_regions"] = softening_regions
    return dict(label=f"{case} edge {edge} seed {seed} T {t} G {fracture_energy}", case=case,
                solver=dict(**({} if edge_elements is None else
                               {"edge_elements": edge_elements}),
                            # (deformable blocks take neither edge elements nor the eigen step)
                            **({"deformable": {"*": zone}, "edge_elements": False,
                                "step_estimate": "bound"} if zone > 0 else {}),
                            **(solver or {})),
                judge=judge or full.get("judge", "budget"),
                params=dict(edge_length=edge, seed=seed, flaw_tensile_strength=t * 1e6,
                            relax_iterations=full["relax_iterations"], **soft),
                g_levels=full["g_levels"],
                max_steps=steps.get(edge, steps[min(steps)]),   # (else the finest's)
                refine_to=full["refine_to"])


def _scene_edge_elements(case: str) -> bool:
    """Whether the case's scene runs its shared edges as linear elements by default: its
    solver's ``edge_elements``, else the library's default (``SolverOptions``: edge elements
    where every block is rigid; until 2026-12-02 a scene that named none was reported as end
    springs, e.g. Longtan since its scene left the choice to the default)."""
    spec = CASES[case]
    solver = spec["module"].scene.scene(spec["params"]()).solver
    value = solver.get("edge_elements")
    return not solver.get("deformable") if value is None else bool(value)


def run_member(m: dict) -> dict:
    """The case's own ``run_member`` (a sweep member: plain dict in and out)."""
    return CASES[m["case"]]["module"].run_member(m)


def row(m: dict, r: dict) -> dict:
    return {"case": m["case"], "edge_m": m["params"]["edge_length"],
            "seed": m["params"]["seed"],
            "flaw_tensile_mpa": m["params"]["flaw_tensile_strength"] / 1e6,
            "edge_elements": m["solver"].get("edge_elements", _scene_edge_elements(m["case"])),
            "fracture_energy_I": m["params"].get("flaw_fracture_energy_I", 0.0),
            "softening_regions": m["params"].get("flaw_softening_regions", "*"),
            "zone_m": m["solver"].get("deformable", {}).get("*", 0.0),
            "judge": m["judge"], "solver": m["solver"], "blocks": r["blocks"],
            "contacts": r["contacts"], "g_step": m["g_levels"][1] - m["g_levels"][0],
            "g_resolution": m["refine_to"], "max_steps_per_level": m["max_steps"],
            "failure_g": r["failure_g"], "last_stable_g": r["last_stable_g"],
            "levels": len(r["g"]), "steps": r["steps"], "seconds": r["runtime_s"],
            # the levels in the order run (bisection and the 1 g closing steps come last)
            "g_run": r["g"], "verdicts": r["verdict"],
            # the rupture surface of the failed state (adhikary's experiment: 12-20 degrees
            # above the joint normal)
            "rupture": None if r.get("rupture") is None else {
                k: r["rupture"][k] for k in ("angle_above_joint_normal_deg", "depth_m",
                                             "n_cracks")},
            "error_vs_experiment": metric_error(r["failure_g"], CASES[m["case"]]["experiment"]),
            "error_vs_thesis": metric_error(r["failure_g"], CASES[m["case"]]["thesis"])}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--edges", type=float, nargs="+", default=[0.008, 0.006, 0.004])
    ap.add_argument("--seeds", type=int, nargs="+", default=[1])
    ap.add_argument("--case", choices=sorted(CASES), default="adhikary")
    ap.add_argument("--tensile", type=float, nargs="+", default=[None],
                    help="flaw T (MPa; default the case's base: adhikary 1.1, longtan 4.81)")
    ap.add_argument("--workers", type=int, default=2)
    contacts = ap.add_mutually_exclusive_group()
    contacts.add_argument("--edge-elements", action="store_const", const=True, default=None,
                          help="shared edges as linear elements (Model(edge_elements=True))")
    contacts.add_argument("--end-springs", dest="edge_elements", action="store_const",
                          const=False, help="shared edges as two point contacts (UDEC's)")
    ap.add_argument("--deformable", type=float, default=0.0, metavar="H",
                    help="every block deformable, zones of H m (Model(deformable={'*': H}))")
    ap.add_argument("--fracture-energy", type=float, nargs="+", default=[0.0], metavar="G_I",
                    help="softening flaws with G_I (J/m^2) and G_II = 10 G_I; 0: brittle")
    ap.add_argument("--softening-regions", default="*", metavar="PATTERN",
                    help="longtan: the regions whose flaws soften (\"zone*\": the Voronoi "
                         "zone; the others' flaws stay brittle)")
    ap.add_argument("--judge", choices=("response", "budget"), default=None,
                    help="the levels' verdict (default the full variant's)")
    ap.add_argument("--solver", type=json.loads, default=None, metavar="JSON",
                    help='further Model options, e.g. \'{"step_estimate": "eigen"}\'')
    ap.add_argument("--name", default="centrifuge_resolution",
                    help="file name of the results (without .json / .png)")
    ap.add_argument("--summary", nargs="+", metavar="NAME",
                    help="run nothing: draw the rows of these result files (names as --name; "
                         "results/benchmarks/ first, then benchmarks/results/) in one figure, "
                         "<--name>.png")
    outdir.add_reference_flag(ap)
    a = ap.parse_args(argv)
    out = outdir.results_dir(a.reference)
    if a.summary:
        rows = [r for n in a.summary
                for r in json.loads(outdir.find(f"{n}.json").read_text())["rows"]]
        summary_figure(rows, out / f"{a.name}.png")
        return
    members = [member(edge, seed, t, a.edge_elements, a.case, a.deformable, g,
                      a.softening_regions, a.judge, a.solver)
               for edge in a.edges for seed in a.seeds for t in a.tensile
               for g in a.fracture_energy]
    rows = [row(m, r) for m, r in zip(members, run_sweep(run_member, members, a.workers))]
    for r in rows:
        print(json.dumps(r), flush=True)
    (out / f"{a.name}.json").write_text(json.dumps(
        {"machine": f"{platform.machine()} {platform.platform()}", "workers": a.workers,
         "rows": rows}, indent=2))
    summary_figure(rows, out / f"{a.name}.png")


def _model_label(r: dict) -> str:
    if r.get("zone_m"):
        return f"deformable blocks, {1e3 * r['zone_m']:g} mm zones"
    label = "edge elements" if r.get("edge_elements") else "end springs (default)"
    if (r.get("solver") or {}).get("divide_interfaces") is False:
        label += ", lengths as made"        # the default before 2026-12-02
    G = r.get("fracture_energy_I", 0.0)
    return f"{label}, G_I {G:g} J/m2" if G else label


def across_tensile(rows: list) -> bool:
    """Whether the rows are a T study (several flaw T at one block edge: failure g is drawn
    against T, one series per tessellation and contact model) rather than a block-size
    study (failure g against the block edge, one series per contact model)."""
    return (len({r["flaw_tensile_mpa"] for r in rows}) > 1
            and len({r["edge_m"] for r in rows}) == 1)


def _series(rows: list, by_seed: bool) -> dict:
    """Series label -> its rows with a failure g (contact model, and the seed if asked)."""
    out = {}
    for r in rows:
        if r["failure_g"]:
            label = _model_label(r) + (f", seed {r['seed']}" if by_seed else "")
            out.setdefault(label, []).append(r)
    return out


def summary_figure(rows: list, path: Path) -> None:
    """Left: failure g (bar from the last stable level) against block edge, one series per
    contact model, or against the flaw T for a T study (``across_tensile``), one series per
    tessellation; each point labelled with its run time, the references as lines. Right:
    each run's failure g against its run time."""
    import matplotlib.pyplot as plt

    case = rows[0].get("case", "adhikary")
    spec = CASES[case]
    t_study = across_tensile(rows)
    x_of = (lambda r: r["flaw_tensile_mpa"]) if t_study else (lambda r: 1e3 * r["edge_m"])
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(10, 4.2))
    by_seed = t_study or len({r["seed"] for r in rows}) > 1
    for i, (label, sel) in enumerate(sorted(_series(rows, by_seed).items())):
        sel = sorted(sel, key=x_of)
        x = np.array([x_of(r) for r in sel])
        hi = np.array([r["failure_g"] for r in sel], float)
        lo = np.array([r["last_stable_g"] or 0.0 for r in sel], float)
        t = np.array([r["seconds"] for r in sel])
        colour = f"C{i}"
        ax.errorbar(x, hi, yerr=[hi - lo, 0 * hi], fmt="o-", color=colour, capsize=3,
                    label=label)
        for xi, y, s in zip(x, hi, t):
            ax.annotate(f"{s:.0f} s", (xi, y), textcoords="offset points", xytext=(4, 4),
                        fontsize=7, color=colour)
        bx.plot(t, hi, "o", color=colour, label=label)
        for xi, y, r in zip(t, hi, sel):
            tag = f"T {r['flaw_tensile_mpa']:g}" if t_study else f"{1e3 * r['edge_m']:g} mm"
            bx.annotate(tag, (xi, y), textcoords="offset points", xytext=(4, 4), fontsize=7,
                        color=colour)
    exp = np.atleast_1d(spec["experiment"])
    for axis in (ax, bx):
        axis.axhspan(exp.min() - 0.5, exp.max() + 0.5, color="0.85", label="experiment")
        axis.set_ylabel("failure g (bar: from the last stable level)")
        axis.set_ylim(0, None)
    if t_study:                # the thesis's UDEC-DM at its base T
        ax.plot([spec["tensile"]], [spec["thesis"]], "s", color="k",
                label=f"thesis UDEC-DM (T {spec['tensile']:g} MPa)")
        bx.axhline(spec["thesis"], color="k", ls="--", label="thesis UDEC-DM")
        ax.set_xlabel("flaw tensile strength T (MPa)")
        ax.set_title(f"{case.capitalize()} centrifuge, damage model, {1e3 * rows[0]['edge_m']:g}"
                     " mm blocks: failure g against T", fontsize=10)
    else:
        for axis in (ax, bx):
            axis.axhline(spec["thesis"], color="k", ls="--", label="thesis UDEC-DM")
        ax.set_xlabel("block edge (mm)")
        ax.invert_xaxis()
        T = rows[0]["flaw_tensile_mpa"]
        ax.set_title(f"{case.capitalize()} centrifuge, damage model, T = {T:g} MPa: block size",
                     fontsize=10)
    bx.set_xscale("log")
    from matplotlib.ticker import NullFormatter, ScalarFormatter
    bx.xaxis.set_major_formatter(ScalarFormatter())
    bx.xaxis.set_minor_formatter(NullFormatter())
    bx.set_xticks([t for t in (30, 100, 300, 1000, 3000, 10000)
                   if 0.5 * min(r["seconds"] for r in rows) <= t <= 2 * max(r["seconds"]
                                                                          for r in rows)])
    bx.set_xlabel("run time (s, one core)")
    ax.legend(fontsize=8, loc="lower left" if not t_study else "upper left")
    bx.set_title("failure g against run time", fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


if __name__ == "__main__":
    main()
