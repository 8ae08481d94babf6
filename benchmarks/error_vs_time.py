"""Error against run time for the closed-form checks, DEM and continuum.

    .venv/bin/python benchmarks/error_vs_time.py [--quick | --full] [--only dem|continuum]

For each check one control at a time is varied around the default setting (resolution: block
or mesh size; solver controls: time-step safety factor, mass scaling, local damping, the
equilibrium ratio, the loading rate / number of load steps). Every run gives a pair
(|relative error|, seconds). The best front is the set of runs no other run beats in both error
and time (Pareto front); for the default setting the JSON records whether it is on the front
and, if not, how much cheaper a front run of no larger error is (``default_vs_front``).
Writes results/benchmarks/error_vs_time.json and .png (``--reference``: benchmarks/results/).
"""
from __future__ import annotations

import time

import numpy as np

import scenes

# check -> (function, default kwargs, {control: values}) ; quick uses the first list, full the second
DEM_CHECKS = {
    "sliding block (a)": (
        scenes.sliding_block, dict(safety=0.5, damping=0.0, steps=6000),
        {"safety": ([0.1, 0.25, 0.5, 0.9, 1.0], [0.05, 0.1, 0.25, 0.5, 0.75, 0.9, 1.0]),
         "damping": ([0.0, 0.1, 0.8], [0.0, 0.05, 0.1, 0.3, 0.8]),
         "steps": ([500, 2000, 6000], [250, 500, 1000, 2000, 6000, 20000])}),
    "oscillation (period)": (
        scenes.oscillation_period, dict(safety=0.5, periods=20),
        {"safety": ([0.05, 0.1, 0.25, 0.5, 0.75, 0.9, 1.0],
                    [0.02, 0.05, 0.1, 0.25, 0.5, 0.75, 0.9, 1.0]),
         "periods": ([3, 20], [2, 5, 20, 50])}),
    "brick bar in tension (peak/T)": (
        scenes.brick_bar_tension, dict(cell=0.01, velocity=2e-3, safety=0.5, damping=0.8,
                                       mass_scaling=False),
        {"cell": ([0.02, 0.01], [0.025, 0.02, 0.01, 0.005]),
         "velocity": ([8e-3, 2e-3, 5e-4], [1.6e-2, 8e-3, 4e-3, 2e-3, 1e-3, 5e-4]),
         "damping": ([0.5, 0.8, 0.9], [0.3, 0.5, 0.7, 0.8, 0.9]),
         "safety": ([0.25, 0.5, 0.9], [0.25, 0.5, 0.75, 0.9]),
         "mass_scaling": ([False, True], [False, True])}),
    "Voronoi cantilever (tip deflection)": (
        scenes.cantilever, dict(edge=0.005, ratio=1e-5, damping=0.8, safety=0.5,
                                mass_scaling=False),
        {"edge": ([0.01, 0.0075, 0.005], [0.01, 0.0075, 0.005, 0.004, 0.003]),
         "ratio": ([1e-3, 1e-4, 1e-5], [1e-3, 1e-4, 1e-5, 1e-6]),
         "damping": ([0.5, 0.8, 0.9], [0.3, 0.5, 0.7, 0.8, 0.9]),
         "safety": ([0.25, 0.5, 0.9], [0.25, 0.5, 0.75, 0.9]),
         "mass_scaling": ([False, True], [False, True])}),
}

CONTINUUM_CHECKS = {
    "gravity column (settlement)": (
        scenes.gravity_column, dict(h=1.0, degree=2),
        {"h": ([2.0, 1.0, 0.5], [2.0, 1.0, 0.5, 0.25]),
         "degree": ([1, 2], [1, 2]),
         "h (P1)": ([2.0, 1.0, 0.5, 0.25], [2.0, 1.0, 0.5, 0.25, 0.125])}),
    "gravity column (sigma_yy)": (
        scenes.gravity_column_stress, dict(h=1.0, degree=2),
        {"h": ([2.0, 1.0, 0.5], [2.0, 1.0, 0.5, 0.25]),
         "degree": ([1, 2], [1, 2]),
         "h (P1)": ([2.0, 1.0, 0.5, 0.25], [2.0, 1.0, 0.5, 0.25, 0.125])}),
    "strip footing (q/c)": (
        scenes.strip_footing, dict(h_min=0.03, load_steps=10, degree=2),
        {"h_min": ([0.1, 0.05, 0.03], [0.1, 0.05, 0.03, 0.015, 0.008]),
         "load_steps": ([5, 10, 20], [5, 10, 20, 40]),
         "degree": ([1, 2], [1, 2])}),
}


def pareto(points):
    """Indices of the runs not beaten in both |error| and seconds by another run."""
    idx = []
    for i, (e, s) in enumerate(points):
        if not any((e2 <= e and s2 <= s) and (e2 < e or s2 < s)
                   for j, (e2, s2) in enumerate(points) if j != i):
            idx.append(i)
    return sorted(idx, key=lambda i: points[i][1])


def run_check(name, fn, default, controls, full, log):
    runs = []

    def one(kw, control):
        r = fn(**kw)
        r.update({"control": control, "settings": {k: kw[k] for k in kw}})
        runs.append(r)
        log(f"  {name:38s} {control:14s} {str(kw.get(control.split()[0], '')):>8s} "
            f"err {r['rel_error']:+.3e}  {r['seconds']:.2f} s")

    one(dict(default), "default")
    for control, (quick_vals, full_vals) in controls.items():
        key = control.split()[0]
        for v in (full_vals if full else quick_vals):
            kw = dict(default)
            if control == "h (P1)":
                kw["degree"] = 1
            if kw.get(key) == v and control != "h (P1)":
                continue                      # the default run already covers it
            kw[key] = v
            one(kw, control)
    pts = [(abs(r["rel_error"]), r["seconds"]) for r in runs]
    front = pareto(pts)
    d_err, d_sec = pts[0]
    cheaper = [i for i in front if pts[i][0] <= d_err]
    best_time = min((pts[i][1] for i in cheaper), default=d_sec)
    better = [i for i in front if pts[i][1] <= d_sec]
    best_err = min((pts[i][0] for i in better), default=d_err)
    return {"default": {k: default[k] for k in default}, "runs": runs, "front": front,
            "default_on_front": 0 in front,
            "default_vs_front": {"abs_error": d_err, "seconds": d_sec,
                                 "front_seconds_at_no_larger_error": best_time,
                                 "front_error_at_no_more_time": best_err,
                                 "time_ratio_default_over_front": d_sec / best_time}}


def plot(results, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    names = list(results)
    ncol = 3
    nrow = -(-len(names) // ncol)
    fig, axes = plt.subplots(nrow, ncol, figsize=(5.2 * ncol, 4.0 * nrow), squeeze=False)
    markers = "osD^vPX*<>"
    for ax, name in zip(axes.flat, names):
        res = results[name]
        runs = res["runs"]
        floor = 1e-16
        controls = list(dict.fromkeys(r["control"] for r in runs))
        for k, c in enumerate(controls):
            sel = [r for r in runs if r["control"] == c]
            ax.loglog([r["seconds"] for r in sel],
                      [max(abs(r["rel_error"]), floor) for r in sel],
                      markers[k % len(markers)], ms=6, alpha=0.75, label=c)
        f = res["front"]
        ax.loglog([runs[i]["seconds"] for i in f],
                  [max(abs(runs[i]["rel_error"]), floor) for i in f], "k-", lw=1,
                  label="best front")
        d = runs[0]
        ax.loglog(d["seconds"], max(abs(d["rel_error"]), floor), "r*", ms=16, mfc="none",
                  mew=2, label="default")
        ax.set_title(name, fontsize=10)
        ax.set_xlabel("run time (s)")
        ax.set_ylabel("|relative error|")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
    for ax in list(axes.flat)[len(names):]:
        ax.axis("off")
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def main(argv=None):
    ap = scenes.quick_or_full_parser(__doc__.splitlines()[0])
    ap.add_argument("--only", choices=["dem", "continuum"])
    a = ap.parse_args(argv)
    info = scenes.machine()
    checks = {}
    if a.only != "continuum":
        checks.update(DEM_CHECKS)
    if a.only != "dem":
        checks.update(CONTINUUM_CHECKS)
    # warm the JIT caches so no check pays a compile (not counted)
    scenes.oscillation_period(periods=1)
    if a.only != "dem":
        scenes.gravity_column(h=2.0, degree=1)
        scenes.gravity_column(h=2.0, degree=2)
    t0 = time.perf_counter()
    results = {}
    for name, (fn, default, controls) in checks.items():
        results[name] = run_check(name, fn, default, controls, a.full, print)
    out = {"machine": info, "mode": "full" if a.full else "quick",
           "wall_seconds": time.perf_counter() - t0, "checks": results,
           "cantilever_reference_E": {str(k): {"E_2d": v[0], "seconds": v[1]}
                                      for k, v in scenes._E_CACHE.items()}}
    path = scenes.write_json("error_vs_time", out, a.reference)
    plot(results, scenes.results_dir(a.reference) / "error_vs_time.png")
    print(f"wrote {path} ({out['wall_seconds']:.0f} s)")


if __name__ == "__main__":
    main()
