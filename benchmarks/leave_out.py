"""What an unused component costs, and the saving from flaws only where they are needed.

    .venv/bin/python benchmarks/leave_out.py [--quick | --full]

Part 1, unused components. One bonded Voronoi specimen (``throughput.specimen``, 50 g, a fixed
base) is stepped with each optional part of the time step absent, present but idle, and (for
reference) active. An absent component is an empty bundle whose kernel loops over nothing
(``dem_core/components``: gravity, applied loads, water, servo; the contact-search check is an
infinite margin), so an absent part and a zero part should cost the same.
Timings alternate between the variants (``--reps`` rounds, the minimum per variant is kept) so
the load of the shared machine affects all alike.

Part 2, flaws only in the zone of interest. A cantilever (0.3 x 0.03 m, the scene of
``tests/test_mech_specimens.py``) is loaded by raising gravity until it breaks. The bending
moment at the root, q L^2 / 2, does not depend on the beam's stiffness (statically determinate),
so the failure g-level depends only on the flaws near the root. Two scenes: Voronoi flaws
everywhere, and Voronoi flaws only in a hinge zone (the first ``zone`` m from the support; the
rest of the beam one rigid block, glued to the zone). Compared: failure g, blocks, contacts and
run time. Closed form for reference: sigma_max = 6 M / H^2 = T at n = T H / (3 rho g L^2).
Writes results/benchmarks/leave_out.json and .png (``--reference``: benchmarks/results/).
"""
from __future__ import annotations

import time

import numpy as np

import scenes
import throughput


# ------------------------------------------------------------------ part 1
def _model(bs, unbreakable=None):
    from dem_core.contact.materials import Material
    from dem_core.model import Model

    flaw = Material(kn=40e9, ks=20e9, tensile_strength=1.1e6, cohesion=1.2e6, friction=37)
    m = Model(bs, {"flaw:*": flaw, "boundary:*": flaw}, density=1700, history_every=10**9,
              unbreakable=unbreakable)
    m.fix("base")
    m.set_gravity(50.0)
    m.cycle(20)                     # warm-up: compile or load the cache
    return m


def variants(bs):
    """name -> (builder, what it shows)."""
    none = np.array([], dtype=np.int64)

    def base():
        return _model(bs)

    def zero_load():
        m = _model(bs)
        m.apply_load("rock", 0.0, 0.0, 0.0)      # present but zero: an empty bundle
        return m

    def active_load():
        m = _model(bs)
        m.apply_load("rock", 0.0, -1e-12, 0.0)   # non-zero (negligible): the loads kernel runs
        return m

    def idle_servo():
        m = _model(bs)
        m.servo(none, 0.0)                       # a servo group with no blocks: one group, no work
        return m

    def history_points():
        m = _model(bs)
        m.history.every = 100
        for k in range(5):
            m.add_history_point(f"p{k}", tuple(bs.centroid[k * (bs.n_blocks // 5)]))
        return m

    def no_search_check():
        m = _model(bs)
        m.enable_search(False)
        return m

    def no_gravity():
        m = _model(bs)
        m.set_gravity(0.0)
        return m

    def conventional():
        return _model(bs, unbreakable="flaw:*")

    def water(on):
        def build():
            from dem_core.workflow.water import WaterTable
            m = _model(bs)
            y = bs.vertices[:, 1]
            m.set_water(WaterTable(float(0.5 * (y.min() + y.max())), on=on))
            return m
        return build

    return {"baseline (gravity, search check)": (base, "reference"),
            "apply_load present but zero": (zero_load, "unused: must cost nothing"),
            "servo present but idle (empty group)": (idle_servo, "unused: must cost nothing"),
            "history points (5, every 100 steps)": (history_points, "monitor cost"),
            "applied load active (1e-12 N)": (active_load, "cost of the loads pass when used"),
            "contact-search check off": (no_search_check, "cost of the movement check"),
            "gravity off": (no_gravity, "cost of the gravity pass"),
            "conventional contacts (unbreakable flaws)": (conventional,
                                                          "glued vs damage law"),
            "water table at mid-height, joints (flaws dry)": (water("joints"),
                                                               "cost of water, flaws skipped"),
            "water table at mid-height, all contacts": (water("all"),
                                                        "cost of water on every contact")}


def unused_costs(n_blocks, steps, reps, log):
    bs = throughput.specimen(n_blocks)
    vs = variants(bs)
    models = {name: build() for name, (build, _) in vs.items()}
    times = {name: [] for name in vs}
    for _ in range(reps):
        for name, m in models.items():
            t0 = time.perf_counter()
            m.cycle(steps)
            times[name].append((time.perf_counter() - t0) / steps)
    base = min(times["baseline (gravity, search check)"])
    noise = float(np.std(times["baseline (gravity, search check)"])
                  / np.mean(times["baseline (gravity, search check)"]))
    rows = []
    for name, (_, what) in vs.items():
        best = min(times[name])
        rows.append({"variant": name, "what": what, "ms_per_step_min": 1e3 * best,
                     "ms_per_step_median": 1e3 * float(np.median(times[name])),
                     "relative_to_baseline": best / base,
                     "contacts": int(models[name].contacts.n)})
        log(f"  {name:44s} {1e3 * best:7.3f} ms/step  x{best / base:.3f}")
    return {"blocks": bs.n_blocks, "steps_per_rep": steps, "reps": reps,
            "baseline_rep_to_rep_spread": noise, "rows": rows}


# ------------------------------------------------------------------ part 2
def cantilever_ramp(zone, edge, g_levels, seed=3):
    """Failure g of a cantilever with Voronoi flaws in [0, zone] (zone=None: everywhere)."""
    from dem_core.geometry import GeometrySpec, Voronoi, build_block_system, rectangle
    from dem_core.workflow.gravity_ramp import raise_gravity
    from dem_core.contact.materials import Material
    from dem_core.model import Model

    L, H, p = 0.3, 0.03, 2 * edge
    regions = [rectangle("rock", 0, 0, L if zone is None else zone, H),
               rectangle("left", -p, 0, 0, H)]
    if zone is not None:
        regions.append(rectangle("beam", zone, 0, L, H))
    t0 = time.perf_counter()
    bs = build_block_system(GeometrySpec(regions=regions, voronoi={
        "rock": Voronoi(edge_length=edge, seed=seed, relax_iterations=100)}))
    flaw = Material(kn=scenes.KN, ks=scenes.KN, tensile_strength=scenes.T,
                    cohesion=3 * scenes.T, friction=35)
    glue = Material(kn=scenes.KN, ks=scenes.KN, breakable=False)
    m = Model(bs, {"flaw:*": flaw, "boundary:*": glue}, density=2500, damping=0.8)
    m.fix("left")
    t_build = time.perf_counter() - t0
    rec = raise_gravity(m, g_levels, ratio=1e-4, max_steps=20_000, failure_displacement=0.005)
    return {"zone_m": zone, "blocks": bs.n_blocks, "contacts": int(m.contacts.n),
            "failure_g": rec.failure_g, "last_stable_g": rec.last_stable_g,
            "steps": int(sum(rec.steps)), "seconds": time.perf_counter() - t0,
            "build_seconds": t_build, "verdicts": list(rec.verdict), "g": list(rec.g)}


def plot(out, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (a1, a2) = plt.subplots(1, 2, figsize=(13, 4.8))
    rows = out["unused"]["rows"]
    y = np.arange(len(rows))
    a1.barh(y, [r["relative_to_baseline"] for r in rows],
            color=["C2" if "unused" in r["what"] else "C0" for r in rows])
    a1.axvline(1.0, color="k", lw=1)
    spread = out["unused"]["baseline_rep_to_rep_spread"]
    a1.axvspan(1 - 2 * spread, 1 + 2 * spread, color="0.85", label="baseline +-2 sd (noise)")
    a1.set_yticks(y)
    a1.set_yticklabels([r["variant"] for r in rows], fontsize=7)
    a1.set_xlabel("time per step / baseline (min over rounds)")
    a1.set_title(f"{out['unused']['blocks']} blocks: cost of optional parts (green: unused)")
    a1.legend(fontsize=7)
    z = out["zone"]["runs"]
    for r in z:
        lab = "flaws everywhere" if r["zone_m"] is None else f"flaws in {r['zone_m']} m hinge"
        a2.plot(r["seconds"], r["failure_g"] or np.nan, "o", ms=9, label=f"{lab}, {r['blocks']} blocks")
    a2.axhline(out["zone"]["closed_form_g"], color="k", ls="--", lw=1,
               label="beam theory, T at the root")
    a2.set_xlabel("run time (s)")
    a2.set_ylabel("failure g-level")
    a2.set_title("cantilever under rising gravity")
    a2.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def main(argv=None):
    ap = scenes.quick_or_full_parser(__doc__.splitlines()[0])
    ap.add_argument("--reps", type=int, default=None)
    a = ap.parse_args(argv)
    out = {"machine": scenes.machine(), "mode": "full" if a.full else "quick"}
    t0 = time.perf_counter()
    print("unused components:")
    out["unused"] = unused_costs(10_000 if a.full else 3000, 300 if a.full else 200,
                                 a.reps or (7 if a.full else 5), print)
    print("flaws only in the hinge zone:")
    L, H, T, rho = 0.3, 0.03, scenes.T, 2500.0
    g_levels = [2, 3, 4, 5, 6, 7, 8, 10, 12] if not a.full else list(np.arange(2, 12.01, 0.5))
    edge = 0.005
    runs = []
    for zone in (None, 0.06):
        r = cantilever_ramp(zone, edge, g_levels)
        runs.append(r)
        print(f"  zone {zone}: {r['blocks']} blocks, failure g {r['failure_g']}, "
              f"{r['seconds']:.1f} s")
    out["zone"] = {"edge_m": edge, "g_levels": [float(x) for x in g_levels], "runs": runs,
                   "closed_form_g": T * H / (3 * rho * scenes.G * L ** 2),
                   "time_saving": runs[0]["seconds"] / runs[1]["seconds"]}
    out["wall_seconds"] = time.perf_counter() - t0
    path = scenes.write_json("leave_out", out, a.reference)
    plot(out, scenes.results_dir(a.reference) / "leave_out.png")
    print(f"wrote {path} ({out['wall_seconds']:.0f} s)")


if __name__ == "__main__":
    main()
