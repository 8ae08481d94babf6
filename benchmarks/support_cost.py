"""What support costs per step: a benched pit wall with 200 grouted cables, and a liner.

    .venv/bin/python benchmarks/support_cost.py            # 20 benches, 200 cables (~3 min)
    .venv/bin/python benchmarks/support_cost.py --quick    # 6 benches, 60 cables (~15 s)

Issue 23: "a slope with 200 cables costs less than 10 % more per step than without".

The scene (``pit_wall``): a pit wall of ``n`` benches (15 m faces at 70 deg, 8 m berms; 20
benches: 300 m high, overall 49 deg) in rock of 2,600 kg/m^3, E = 30 GPa. A zone 14 m deep
along the faces and berms (``near_face_regions``) is a Voronoi tessellation (the thesis's flaws:
intact rock contacts that can break; edge 0.6 m: 10,526 blocks in all, and 1.0 m: 4,795, in
the default run; quick: 6 benches, 0.8 m); the rest is the blocks the joints cut.
Two non-persistent joint sets cut both: one dipping 30 deg out of the face (6 m apart, 10 m
traces, persistence 0.7), one 75 deg into the slope (8 m, 8 m traces, 0.6). Base fixed, sides
on rollers. The model starts from a geostatic stress (k = 0.5 below its own surface) and is
settled under gravity for ``settle`` steps (mass scaling, local damping 0.8).

Support, installed on the settled model (``Model.install``): 10 rows of cables on each bench
face (every 1.6 m along the face; 20 benches: 200 cables), 8, 10 and 12 m long in turn,
drilled 10 deg below horizontal into the slope, 2.5 m apart out of plane, segments of about the
median block size (sqrt of the median Voronoi block area); steel and grout of the thesis's
Checkerboard Creek cables: area 625 mm^2, E 98 GPa, yield 0.548 MN, grout 6 GN/m/m and
0.32 MN/m. The liner: 0.15 m of shotcrete (E 25 GPa, 3 / 35 MPa tensile / compressive yield,
bond 5 / 2 GPa/m, 0.5 / 1 MPa) on every exposed face of the Voronoi zone (faces and berms, crest
to toe: one chain), the same segment length.

Timing: four copies of the settled model (``Model.snapshot`` / ``restore``): plain, cables,
liner, cables + liner, each warmed up, then ``--reps`` rounds in which each variant in turn is
restored to its own snapshot and runs ``--steps`` steps of ``Model.cycle`` (one thread, no
history records), so every round of a variant does the same work; the minimum per variant is
kept (the machine is shared: alternating spreads the load of other jobs over all variants; the
order rotates by one each round). Also the median over rounds of the ratio to the plain run of
the same round (robust to the load drifting between rounds), and the estimate 1 + (the support
kernels' time, looped) / (the plain step).
Reported: time per step and its ratio to the plain model, the automatic time step of each
(grout and bond springs add to their blocks' frequency bound), hence also the cost per second
of model time, and the support's node, segment and bond counts. A profile of the cable kernel's
parts (``components/cables.py``: the segments' axial forces, the grout on the blocks; and
``step/nodes.py``: moving the nodes), each looped inside numba on a copy of the model, says
where the extra time goes.
Writes results/benchmarks/support_cost.json and .png (``--reference``: benchmarks/results/).
"""
from __future__ import annotations

import argparse
import math
import time

import numpy as np
from numba import njit

import scenes
from dem_core.components.cables import _axial, _grout
from dem_core.components.liner import add_liners
from dem_core.step.nodes import move_nodes

BENCH_H, FACE_DIP, BERM, DEPTH = 15.0, 70.0, 8.0, 14.0         # m, deg, m, m
ROWS, ROW_SPACING = 10, 1.6                                     # rows per bench face, m
LENGTHS, DRILL_DIP, SPACING = (8.0, 10.0, 12.0), 10.0, 2.5      # m, deg below horizontal, m
DENSITY, K0 = 2600.0, 0.5
CABLE = dict(area=625e-6, E=98e9, yield_tension=0.548e6, grout_stiffness=6e9,
             grout_strength=0.32e6, spacing=SPACING)
LINER = dict(thickness=0.15, E=25e9, tensile_yield=3e6, compressive_yield=35e6, bond_kn=5e9,
             bond_ks=2e9, bond_tension=0.5e6, bond_shear=1e6)


# ------------------------------------------------------------------ the scene
def pit_wall(n_benches, edge, seed=0):
    """The pit wall's Scene (module docstring)."""
    from dem_core.geometry import GeometrySpec, JointSet, Voronoi
    from dem_core.geometry.profiles import bench_profile, near_face_regions
    from dem_core.contact.materials import Material
    from dem_core.workflow.scene import Boundary, Scene

    rock = bench_profile(BENCH_H, n_benches, FACE_DIP, BERM, crest_length=30.0,
                         toe_length=30.0, base_thickness=20.0)
    zone, rest = near_face_regions(rock, DEPTH)
    sets = [JointSet("bedding", 30.0, 6.0, persistence=0.7, trace_length=10.0,
                     dip_direction="right", offset=1.3, seed=seed + 1),
            JointSet("cross", 75.0, 8.0, persistence=0.6, trace_length=8.0,
                     dip_direction="left", offset=2.1, seed=seed + 2)]
    geo = GeometrySpec([zone, rest], joint_sets=sets,
                       voronoi={"face_zone": Voronoi(edge_length=edge, relax_iterations=10,
                                                     seed=seed)})
    intact = Material(kn=50e9, ks=20e9, tensile_strength=4e6, cohesion=10e6, friction=45.0,
                      residual_friction=35.0)
    joint = Material(kn=5e9, ks=2.5e9, cohesion=50e3, friction=35.0)
    groups = {"bottom": {"touching": "bottom"}, "left": {"touching": "left"},
              "right": {"touching": "right"}, "sides": {"union": ["left", "right"]}}
    return Scene(geo, {"flaw:*": intact, "boundary:*": intact, "joint:*": joint},
                 density=DENSITY, block_E=30e9, block_nu=0.25, groups=groups,
                 boundaries=[Boundary("bottom"), Boundary("sides", x=True, y=False,
                                                          rotation=False)],
                 solver={"mass_scaling": True, "damping": 0.8, "history_every": 10**9})


def settled_model(n_benches, edge, settle, log):
    """The pit wall built, given its geostatic stress, and stepped ``settle`` times under
    gravity; (model, facts)."""
    from dem_core.workflow.insitu import InSitu
    from dem_core.workflow.scene import build_model

    t0 = time.perf_counter()
    sc = pit_wall(n_benches, edge)
    m = build_model(sc)
    t_build = time.perf_counter() - t0
    m.set_gravity(1.0)
    InSitu.geostatic(DENSITY, K0).run(m)
    t0 = time.perf_counter()
    m.cycle(settle)
    zone = m.group("face_zone")
    facts = {"benches": n_benches, "height_m": n_benches * BENCH_H, "voronoi_edge_m": edge,
             "blocks": m.n_blocks, "voronoi_blocks": int(zone.size),
             "contacts": int(m.contacts.n), "build_seconds": t_build,
             "settle_steps": settle, "settle_seconds": time.perf_counter() - t0,
             "unbalanced_ratio_after_settling": m.unbalanced_ratio(),
             "largest_settlement_m": float(np.hypot(*m.displacement().T).max()),
             "cracks_while_settling": int(m.cracks.count[0]),
             "median_block_size_m": float(np.sqrt(np.median(m.blocks.area[zone])))}
    log(f"  {facts['blocks']} blocks ({facts['voronoi_blocks']} Voronoi), "
        f"{facts['contacts']} contacts; built in {t_build:.1f} s, settled {settle} steps in "
        f"{facts['settle_seconds']:.1f} s (ratio {facts['unbalanced_ratio_after_settling']:.2g})")
    return m, facts


def bench_faces(n_benches):
    """(toe, crest) points of each bench face, top bench first (``bench_profile``'s layout)."""
    run = BENCH_H / math.tan(math.radians(FACE_DIP))
    top = 20.0 + n_benches * BENCH_H
    faces, x = [], 30.0
    for k in range(n_benches):
        y = top - k * BENCH_H
        faces.append(((x + run, y - BENCH_H), (x, y)))
        x += run + BERM
    return faces


def cables(n_benches, segment_length):
    """The ``Cable`` records: ROWS per bench face (module docstring)."""
    from dem_core.components.support import Cable

    d = np.array([-math.cos(math.radians(DRILL_DIP)), -math.sin(math.radians(DRILL_DIP))])
    out = []
    for toe, crest in bench_faces(n_benches):
        toe, crest = np.asarray(toe), np.asarray(crest)
        along = (crest - toe) / np.hypot(*(crest - toe))
        for r in range(ROWS):
            collar = toe + (0.5 + r) * ROW_SPACING * along + 0.05 * d   # just inside the rock
            end = collar + LENGTHS[len(out) % len(LENGTHS)] * d
            out.append(Cable(collar=tuple(collar), end=tuple(end),
                             segment_length=segment_length, **CABLE))
    return out


def liner(segment_length):
    from dem_core.components.support import Liner
    return Liner("face_zone", segment_length=segment_length, **LINER)


# ------------------------------------------------------------------ timing
def variants(m, items, log):
    """name -> snapshot of the settled model with that support installed and warmed up."""
    base = m.snapshot()
    out, facts = {}, {}
    for name, support in items.items():
        m.restore(base)
        t0 = time.perf_counter()
        m.install(list(support))          # one search of the blocks for all
        t_install = time.perf_counter() - t0
        m.cycle(20)                       # warm-up: compile or load the caches
        cb, ln = m.cables, m.liners
        facts[name] = {"dt_s": m.dt, "install_seconds": t_install,
                       "cables": len([s for s in support if type(s).__name__ == "Cable"]),
                       "cable_nodes": int(cb.node_pos.shape[0]),
                       "cable_segments": int(cb.seg_a.shape[0]),
                       "liner_nodes": int(ln.node_pos.shape[0]),
                       "liner_elements": int(ln.el_a.shape[0]),
                       "liner_bonds": int(ln.bond_node.shape[0])}
        out[name] = m.snapshot()
        log(f"  {name}: {facts[name]['cable_nodes']} cable nodes, "
            f"{facts[name]['liner_nodes']} liner nodes, dt {m.dt:.3g} s "
            f"(installed in {t_install:.1f} s)")
    m.restore(base)
    return out, facts


def time_rounds(m, snaps, steps, reps, log):
    """Seconds per step of each variant over ``reps`` rounds; each round runs every variant
    once, starting one further along the list than the round before (so no variant always
    runs first after the machine's load changed)."""
    names = list(snaps)
    times = {name: [] for name in names}
    for r in range(reps):
        for name in names[r % len(names):] + names[:r % len(names)]:
            m.restore(snaps[name])
            t0 = time.perf_counter()
            m.cycle(steps)
            times[name].append((time.perf_counter() - t0) / steps)
        if (r + 1) % max(1, reps // 5) == 0 or r + 1 == reps:
            log(f"  round {r + 1}/{reps}: " + ", ".join(f"{1e3 * t[-1]:.3f}"
                                                          for t in times.values()) + " ms/step")
    return times


# ------------------------------------------------------------------ where the cable time goes
@njit
def _loop_axial(cb, n):
    for _ in range(n):
        cb.node_force[:] = 0.0
        cb.node_tangent[:] = 0.0
        _axial(cb, 0.0)


@njit
def _loop_grout(cb, s, p, n):
    for _ in range(n):
        _grout(cb, s, p, 0.0)


@njit
def _loop_move(cb, alpha, n):
    for _ in range(n):
        move_nodes(cb.node_pos, cb.node_vel, cb.node_force, cb.node_inv_mass, 0.0, 0.0, alpha)


@njit
def _loop_liner(ln, s, p, gravity, n):
    for _ in range(n):
        add_liners(ln, s, p, 0.0, gravity)


def kernel_profile(m, snap, n=2000):
    """Seconds per call of the cable kernel's parts and the node move (and the whole liner
    force kernel), each looped ``n`` times inside numba on the variant's snapshot (the model is
    restored afterwards; dt = 0 in the node move so the nodes stay put)."""
    from dem_core.components import gravity_bundle

    parts = {}

    def timed(name, fn):
        m.restore(snap)
        fn(1)                                       # compile
        best = math.inf
        for _ in range(3):
            t0 = time.perf_counter()
            fn(n)
            best = min(best, (time.perf_counter() - t0) / n)
        parts[name] = best

    if m.cables.node_pos.shape[0] == 0 and m.liners.node_pos.shape[0] == 0:
        return parts
    m.restore(snap)
    if m.cables.node_pos.shape[0]:
        timed("cables: segments' axial forces (_axial)", lambda k: _loop_axial(m.cables, k))
        timed("cables: grout on the blocks (_grout)",
              lambda k: (_loop_axial(m.cables, 1), _loop_grout(m.cables, m.state, m.props, k)))
        timed("cables: moving the nodes (move_nodes)",
              lambda k: _loop_move(m.cables, m.damping, k))
    if m.liners.node_pos.shape[0]:
        timed("liner: whole kernel (add_liners)",
              lambda k: _loop_liner(m.liners, m.state, m.props, gravity_bundle(m.gravity), k))
    m.restore(snap)
    return parts


# ------------------------------------------------------------------ figure
def plot(out, path, m, snap):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.collections import LineCollection, PolyCollection

    fig = plt.figure(figsize=(17, 6.8))
    gs = fig.add_gridspec(1, 3, width_ratios=[1.2, 0.95, 0.85])
    a1, a2, a3 = (fig.add_subplot(g) for g in gs)
    _ratios(a1, out)
    _profile(a2, out["runs"][0])
    m.restore(snap)
    _draw(a3, m, out["runs"][0], LineCollection, PolyCollection)
    mach = out["machine"]
    fig.suptitle(f"Support cost per step, issue 23 ({out['mode']} run): {mach['cpu']}, "
                 f"{mach['cores']} cores shared with other jobs, 1 thread, {mach['date']}",
                 fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _ratios(ax, out):
    """Time per step / plain for every supported variant of every run."""
    rows = [(run, r) for run in out["runs"] for r in run["rows"][1:]]
    y = np.arange(len(rows))[::-1]
    ratio = np.array([r["time_per_step_ratio"] for _, r in rows])
    ax.barh(y, ratio - 1.0, left=1.0, color=["C2" if v < 1.10 else "C3" for v in ratio],
            label="ratio of the fastest rounds (min per variant)")
    med = np.array([r["same_round_ratio_median"] for _, r in rows])
    q = np.array([r["same_round_ratio_quartiles"] for _, r in rows])
    ax.errorbar(med, y, xerr=[med - q[:, 0], q[:, 1] - med], fmt="o", color="k", ms=4,
                capsize=3, label="ratio within a round: median, quartiles")
    ax.plot([r["kernel_estimate_ratio"] for _, r in rows], y, "D", color="C1", ms=6,
            label="1 + support kernels looped in numba / plain step")
    spread = out["runs"][0]["plain_rep_to_rep_spread"]
    ax.axvspan(1 - 2 * spread, 1 + 2 * spread, color="0.9", zorder=0,
               label=f"plain model, +-2 sd of its rounds ({100 * spread:.1f} %)")
    ax.axvline(1.0, color="k", lw=1)
    ax.axvline(1.10, color="C3", ls="--", lw=2, label="issue 23 target: +10 % (200 cables)")
    hi = max(1.3, ratio.max() + 0.16, q[:, 1].max() + 0.16)
    for yi, (run, r) in zip(y, rows):
        ax.text(max(r["time_per_step_ratio"], r["same_round_ratio_quartiles"][1],
                    r["kernel_estimate_ratio"]) + 0.015, yi,
                f"x{r['time_per_step_ratio']:.3f}\n{r['ms_per_step_min']:.3f} vs "
                f"{run['rows'][0]['ms_per_step_min']:.3f} ms", va="center", fontsize=7)
    for k in range(1, len(out["runs"])):
        ax.axhline(y[3 * k] + 0.5, color="0.5", lw=0.8)
    ax.set_yticks(y)
    ax.set_yticklabels([f"{r['variant']}\n{_counts(r)}\n{run['scene']['blocks']:,} blocks, "
                        f"{run['scene']['contacts']:,} contacts" for run, r in rows], fontsize=7)
    ax.set_xlim(0.85, hi)
    ax.set_xlabel("time per step / the same model without support")
    ax.set_title("cost of support per step", fontsize=10)
    ax.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.4, -0.1), ncol=2)


def _profile(ax, run):
    """The plain step, the measured extra time of the cables, and the kernels' parts."""
    prof = run["kernel_profile_us_per_step"]
    rows = run["rows"]
    plain_us = 1e3 * rows[0]["ms_per_step_min"]
    extra_us = 1e3 * (rows[1]["ms_per_step_min"] - rows[0]["ms_per_step_min"])
    labels = ["plain step (whole)", f"{rows[1]['variant']} - plain (whole steps)"] + list(prof)
    vals = [plain_us, max(extra_us, 1e-3)] + list(prof.values())
    yy = np.arange(len(vals))[::-1]
    ax.barh(yy, vals, color=["0.6", "C0"] + ["C1"] * len(prof))
    for yi, v, lb in zip(yy, vals, labels):
        ax.text(v, yi, f" {v:.0f} us" + (" (noise)" if "whole steps" in lb and extra_us <= 0
                                         else ""), va="center", fontsize=8)
    ax.axvline(0.10 * plain_us, color="C3", ls="--", lw=1.5, label="10 % of the plain step")
    ax.set_xscale("log")
    ax.set_xlim(1.0, 4 * plain_us)
    ax.set_yticks(yy)
    ax.set_yticklabels([textwrap(lb) for lb in labels], fontsize=7)
    ax.set_xlabel("microseconds per step")
    ax.set_title(f"where the time goes, {run['scene']['blocks']:,} blocks "
                 f"({rows[1]['cable_nodes']} cable nodes: {run['cable_ns_per_node']:.0f} ns "
                 f"each;\n{run['plain_ns_per_contact']:.0f} ns per contact in the plain step)",
                 fontsize=9)
    ax.legend(fontsize=7, loc="lower right")


def textwrap(s, width=34):
    import textwrap as tw
    return "\n".join(tw.wrap(s, width))


def _counts(r):
    nodes = [f"{r['cable_nodes']:,} cable" if r["cable_nodes"] else "",
             f"{r['liner_nodes']:,} liner" if r["liner_nodes"] else ""]
    return " + ".join(n for n in nodes if n) + " nodes"


def _draw(ax, m, run, LineCollection, PolyCollection):
    """The lowest two benches with their blocks, cables and liner."""
    from dem_core.contact.broad import world_vertices

    p, s = m.props, m.state
    wv = world_vertices(s.pos, s.rot, p.vertex_offsets, p.local_vertices)
    off = p.vertex_offsets
    faces = bench_faces(run["scene"]["benches"])
    (x1, y0), (x0, y1) = faces[-1][0], faces[-2][1]       # lowest toe, crest of the next
    box = (x0 - 14.0, x1 + 6.0, y0 - 10.0, y1 + 3.0)
    keep = [b for b in range(m.n_blocks)
            if box[0] - 5 < s.pos[b, 0] < box[1] + 5 and box[2] - 5 < s.pos[b, 1] < box[3] + 5]
    zone = set(m.group("face_zone").tolist())
    polys = [wv[off[b]:off[b + 1]] for b in keep]
    ax.add_collection(PolyCollection(polys, facecolors=["0.93" if b in zone else "0.8"
                                                         for b in keep],
                                     edgecolors="0.55", linewidths=0.3))
    mat = m.contacts.material[:m.contacts.n]
    names = m.table.names
    joints = [i for i, n in enumerate(names) if n.startswith("joint:")]
    c = m.contacts
    jt = np.isin(mat, joints)
    xy = c.position(s.pos, s.rot)[:c.n][jt]
    ax.plot(xy[:, 0], xy[:, 1], ",", color="C3")
    cb = m.cables
    segs = [cb.node_pos[[a, b]] for a, b in zip(cb.seg_a, cb.seg_b)]
    ax.add_collection(LineCollection(segs, colors="C0", linewidths=1.2, label="cables"))
    ax.plot(cb.node_pos[:, 0], cb.node_pos[:, 1], ".", color="C0", ms=2)
    ln = m.liners
    if ln.node_pos.shape[0]:
        ax.plot(ln.node_pos[:, 0], ln.node_pos[:, 1], "-", color="C1", lw=2, label="liner")
    ax.plot([], [], ",", color="C3", label="joint contacts")
    ax.set_xlim(box[0], box[1])
    ax.set_ylim(box[2], box[3])
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_title(f"lowest two of {run['scene']['benches']} benches (light: Voronoi zone)",
                 fontsize=10)
    ax.legend(fontsize=7, loc="lower left")


# ------------------------------------------------------------------ main
def measure(n_benches, edge, settle, steps, reps, log):
    """One pit wall: the four variants timed and the kernels profiled; (run, model, snapshot
    with cables and liner)."""
    log(f"pit wall, {n_benches} benches, Voronoi edge {edge} m:")
    m, scene = settled_model(n_benches, edge, settle, log)
    h = scene["median_block_size_m"]
    cab = cables(n_benches, h)
    name = f"{len(cab)} cables"
    items = {"plain": [], name: cab, "liner": [liner(h)], f"{name} + liner": cab + [liner(h)]}
    snaps, facts = variants(m, items, log)
    log(f"  timing, {reps} rounds of {steps} steps:")
    times = time_rounds(m, snaps, steps, reps, log)
    prof = kernel_profile(m, snaps[f"{name} + liner"])
    log("  kernel parts: " + ", ".join(f"{k} {1e6 * v:.1f} us" for k, v in prof.items()))
    pt = np.array(times["plain"])
    plain = pt.min()
    rows = []
    for v in snaps:
        best, f = min(times[v]), facts[v]
        paired = np.array(times[v]) / pt                 # same round: the load was alike
        parts = sum(t for k, t in prof.items() if (k.startswith("cables") and f["cable_nodes"])
                    or (k.startswith("liner") and f["liner_nodes"]))
        r = {"variant": v, **f, "ms_per_step_min": 1e3 * best,
             "ms_per_step_median": 1e3 * float(np.median(times[v])),
             "ms_per_step_rounds": [1e3 * t for t in times[v]],
             "time_per_step_ratio": best / plain,
             "same_round_ratio_median": float(np.median(paired)),
             "same_round_ratio_quartiles": [float(np.percentile(paired, 25)),
                                            float(np.percentile(paired, 75))],
             "kernel_estimate_ratio": 1.0 + parts / plain,
             "model_time_cost_ratio": (best / f["dt_s"]) / (plain / facts["plain"]["dt_s"])}
        rows.append(r)
        log(f"  {v:22s} {1e3 * best:7.3f} ms/step  x{r['time_per_step_ratio']:.3f} "
            f"(within a round x{r['same_round_ratio_median']:.3f}, kernels "
            f"x{r['kernel_estimate_ratio']:.3f}), dt {f['dt_s']:.3g} s, "
            f"x{r['model_time_cost_ratio']:.3f} per second of model time")
    run = {"scene": scene, "steps_per_round": steps, "rounds": reps,
           "support": {"cable": {**CABLE, "lengths_m": LENGTHS, "drill_dip_deg": DRILL_DIP,
                                 "rows_per_bench": ROWS, "row_spacing_m": ROW_SPACING,
                                 "segment_length_m": h},
                       "liner": {**LINER, "group": "face_zone", "segment_length_m": h}},
           "rows": rows, "plain_rep_to_rep_spread": float(np.std(pt) / np.mean(pt)),
           "kernel_profile_us_per_step": {k: 1e6 * v for k, v in prof.items()},
           "cable_ns_per_node": 1e9 * sum(v for k, v in prof.items() if k.startswith("cables"))
           / facts[name]["cable_nodes"],
           "plain_ns_per_contact": 1e9 * plain / scene["contacts"]}
    return run, m, snaps[f"{name} + liner"]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    g = ap.add_mutually_exclusive_group()
    g.add_argument("--quick", action="store_true", help="6 benches, 60 cables, 0.8 m blocks")
    g.add_argument("--full", action="store_true", help="the default: 20 benches, 200 cables")
    ap.add_argument("--edges", type=float, nargs="+", default=None,
                    help="Voronoi edge lengths, m (default 0.6 1.0; quick 0.8)")
    ap.add_argument("--steps", type=int, default=None, help="steps per round")
    ap.add_argument("--reps", type=int, default=None, help="alternating rounds")
    scenes.outdir.add_reference_flag(ap)
    a = ap.parse_args(argv)
    quick = a.quick
    n_benches = 6 if quick else 20
    edges = a.edges or ([0.8] if quick else [0.6, 1.0])
    steps = a.steps or (100 if quick else 200)
    reps = a.reps or (12 if quick else 24)
    out = {"machine": scenes.machine(), "mode": "quick" if quick else "default", "threads": 1,
           "runs": []}
    t0 = time.perf_counter()
    for k, edge in enumerate(edges):
        run, m, snap = measure(n_benches, edge, 500 if quick else 2000, steps, reps, print)
        out["runs"].append(run)
        if k == 0:
            drawn = (m, snap)
    r = out["runs"][0]["rows"][1]
    out["issue_23"] = {"blocks": out["runs"][0]["scene"]["blocks"], "cables": r["cables"],
                       "cable_nodes": r["cable_nodes"],
                       "time_per_step_ratio": r["time_per_step_ratio"],
                       "same_round_ratio_median": r["same_round_ratio_median"],
                       "kernel_estimate_ratio": r["kernel_estimate_ratio"],
                       "target": 1.10, "met": bool(r["time_per_step_ratio"] < 1.10)}
    out["wall_seconds"] = time.perf_counter() - t0
    path = scenes.write_json("support_cost", out, a.reference)
    plot(out, scenes.results_dir(a.reference) / "support_cost.png", *drawn)
    for run in out["runs"]:
        r = run["rows"][1]
        print(f"{r['cables']} cables ({r['cable_nodes']} nodes) in {run['scene']['blocks']} "
              f"blocks: x{r['time_per_step_ratio']:.3f} per step (within a round "
              f"x{r['same_round_ratio_median']:.3f}, kernels x{r['kernel_estimate_ratio']:.3f})")
    print(f"issue 23 (< 1.10): {'met' if out['issue_23']['met'] else 'NOT met'}")
    print(f"wrote {path} ({out['wall_seconds']:.0f} s)")


if __name__ == "__main__":
    main()
