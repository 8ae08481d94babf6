"""Checkerboard Creek: does the cut stand at its weathered strengths (T = c) before any T is
lowered? The scene's base stages only (gravity at 10 x strength, the real strengths, the
water table, each solved), for one extent, flaw size, cut height and UCS.

    python benchmarks/trials/checkerboard_base.py --extent section --edge 6      # whole section
    python benchmarks/trials/checkerboard_base.py --extent window --edge 1.3     # quick window
    python benchmarks/trials/checkerboard_base.py --extent section --edge 1.3 --cut 50
    python benchmarks/trials/checkerboard_base.py --extent section --edge 1.3 --edge-elements
    python benchmarks/trials/checkerboard_base.py --extent section --edge 1.3 --insitu 0.37
    python benchmarks/trials/checkerboard_base.py --extent window --edge 1.3 --demand
    python benchmarks/trials/checkerboard_base.py --extent window --edge 1.3 --demand --joints-through
    python benchmarks/trials/checkerboard_base.py --extent window --edge 1.3 --demand --deformable 1.3 \
        --deformable-within 10 [--local-damping 0.8 --steps 50000]

``--demand``: after the gravity stage, the flaws' stress against their real strength (per
material: contacts above T in tension and above c + sn tan(phi) in shear, the largest ratios,
and where the contacts above their strength are), then the real strengths and the cracks after
50, 200, 1,000, 3,000 and 8,000 steps; the water stage is not run. ``--joints-through``: an
experiment, not the scene: the three joint sets cut every unit (the scene's joints stop at the
base of the weathered zone, and a joint's end is a stress concentration), with the weathered
joints' properties. ``--deformable H``: every block deformable, zones of size H m
(``Model(deformable={"*": H})``, the scene's block_E 3.6 GPa and block_nu 0.27; not with
``--edge-elements``, which the deformable blocks do not take yet). The window's far blocks
(up to 40 m) then carry most of the gridpoints (560,000 at H = 1.3 m); ``--deformable-within
D`` makes only the blocks whose centroid lies within D m of the flaw zone (the weathered rock
within ``zone_length`` behind the crest, ``scene.cut_zone``) deformable, the rest rigid.
``--local-damping A``: an experiment, not the scene: local damping A (``Model(damping=A)``)
instead of the scene's kinetic damping (``damping=0``, ``kinetic_damping=100``, whose
kinetic-energy test sees the blocks' motion only, not their zones'). With the scene's damping
the deformable window fails in its gravity stage at 10 x strength; with local damping 0.8 it
stands (docs/cases/checkerboard.md, "With deformable blocks").

Prints one line per solved stage (verdict, steps, cracks so far, the monitoring points'
displacement in m, seconds) and a JSON line at the end. The quick variant's model is
``--extent window --edge 6``; the full variant's ``--extent section --edge 1.3``
(docs/cases/checkerboard.md, "Full variant").
"""
from __future__ import annotations

import argparse
import dataclasses
import json
import time
import warnings


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--extent", choices=["section", "window"], default="section")
    ap.add_argument("--edge", type=float, default=1.3, help="flaw edge near the cut, m")
    ap.add_argument("--cut", type=float, default=70.0, help="cut height, m")
    ap.add_argument("--ucs", type=float, default=60.0, help="MPa")
    ap.add_argument("--steps", type=int, default=150_000, help="step limit of each solve")
    ap.add_argument("--insitu", type=float, default=None, metavar="K",
                    help="start from the geostatic field sv = rho g depth, sh = K sv "
                         "(dem_core.workflow.insitu.InSitu) before the gravity stage")
    ap.add_argument("--edge-elements", action="store_true",
                    help="each shared edge one linear element (Model(edge_elements=True))")
    ap.add_argument("--demand", action="store_true",
                    help="the flaws' demand against their real strength after gravity")
    ap.add_argument("--joints-through", action="store_true",
                    help="experiment: the joint sets cut the fresh rock too")
    ap.add_argument("--deformable", type=float, default=None, metavar="H",
                    help="every block deformable with zones of H m (Model(deformable=...))")
    ap.add_argument("--deformable-within", type=float, default=None, metavar="D",
                    help="with --deformable: only the blocks within D m of the flaw zone")
    ap.add_argument("--local-damping", type=float, default=None, metavar="A",
                    help="experiment: local damping A instead of the scene's kinetic damping")
    a = ap.parse_args()
    warnings.simplefilter("ignore")        # (the scene's own notes)
    from comparisons import checkerboard as cbk
    from comparisons.scenes import checkerboard as scene
    from dem_core.workflow.scene import build_model
    from dem_core.workflow.stages import run_stages

    common = dict(cbk._COMMON) if a.extent == "window" else {}
    p = scene.CheckerboardParams(**dict(common, edge_length=a.edge, cut_height=a.cut,
                                        ucs=a.ucs * 1e6))
    if a.joints_through:
        _joints_through(scene)
    stages = scene.base_stages(p, a.steps)
    if a.insitu is not None:
        from dem_core.workflow.insitu import InSitu
        stages = [InSitu.geostatic(scene.DENSITY, a.insitu)] + stages
    sc = scene.scene(p, stages)
    if a.edge_elements:
        sc = dataclasses.replace(sc, solver=dict(sc.solver, edge_elements=True))
    if a.local_damping is not None:
        sc = dataclasses.replace(sc, solver=dict(sc.solver, damping=a.local_damping,
                                                 kinetic_damping=0))
    if a.deformable is not None:
        which = "*"
        if a.deformable_within is not None:
            near = scene.cut_zone(p).buffer(a.deformable_within, join_style="mitre")
            ring = [[float(x), float(y)] for x, y in list(near.exterior.coords)[:-1]]
            sc = dataclasses.replace(sc, groups=dict(sc.groups, deformable={"inside": ring}))
            which = "deformable"
        sc = dataclasses.replace(sc, solver=dict(sc.solver, deformable={which: a.deformable}))
    t_build = time.time()
    m = build_model(sc)
    zs = m.zone_state
    print(f"{a.extent}, {a.edge} m flaws, cut {a.cut} m, UCS {a.ucs} MPa, edge elements "
          f"{a.edge_elements}, in-situ k {a.insitu}, joints through {a.joints_through}, "
          f"deformable {a.deformable} within {a.deformable_within}: {m.n_blocks} blocks "
          f"({int(m.deformable_blocks.sum())} deformable), {m.contacts.n} contacts, "
          f"{zs.x0.shape[0]} gridpoints, dt {m.dt:.3g} s, built in "
          f"{time.time() - t_build:.0f} s", flush=True)
    t0 = time.time()
    if a.demand:
        return demand(m, sc.stages, scene.materials(p), t0,
                      dict(extent=a.extent, edge=a.edge, ucs=a.ucs, joints_through=
                           a.joints_through, deformable=a.deformable,
                           deformable_within=a.deformable_within,
                           local_damping=a.local_damping, blocks=int(m.n_blocks),
                           deformable_blocks=int(m.deformable_blocks.sum()),
                           gridpoints=int(zs.x0.shape[0]), dt0=float(m.dt)))
    out = []
    for r in run_stages(m, sc.stages, progress=lambda *x, **k: None):
        if r.steps:
            pts = {k: [round(x, 2) for x in v] for k, v in r.points.items()}
            print(f"  {r.kind}: {r.verdict}, {r.steps} steps, cracks {r.cracks}, {pts}, "
                  f"{r.seconds:.0f} s", flush=True)
            out.append(dict(kind=r.kind, verdict=r.verdict, steps=r.steps, cracks=r.cracks,
                            points=pts))
    print(json.dumps(dict(extent=a.extent, edge=a.edge, cut=a.cut, ucs=a.ucs,
                          edge_elements=a.edge_elements, insitu_k=a.insitu,
                          blocks=int(m.n_blocks), stages=out,
                          seconds=round(time.time() - t0)), default=str))


def _joints_through(scene):
    """Replace the scene's joint sets by the same three sets cutting every unit."""
    from dem_core.geometry import JointSet

    def joint_sets(p, names):
        gneiss = [n for n in names if "gneiss" in scene.unit_of(n)]
        return [JointSet("vertical", 85.0, p.vertical_spacing, dip_direction="left",
                         origin=scene.TOE, regions=list(names)),
                JointSet("cross_shears", 65.0, p.shear_spacing, dip_direction="right",
                         origin=scene.TOE, offset=0.5 * p.vertical_spacing, regions=list(names)),
                JointSet("gneiss_shears", 70.0, p.shear_spacing, dip_direction="left",
                         origin=scene.TOE, offset=0.25 * p.shear_spacing, regions=gneiss)]
    scene.joint_sets = joint_sets


def strength_ratios(m, real):
    """Per breakable material: (rows, tension ratio -sn / T, shear ratio |ts| / (c + sn tan
    phi)) of its intact contacts against the ``real`` strengths (sn compression +)."""
    import numpy as np

    c, n = m.contacts, m.contacts.n
    names = list(m.blocks.material_names)
    out = {}
    for name, mat in real.items():
        if name not in names or not mat.tensile_strength > 0:
            continue
        rows = np.flatnonzero((c.material[:n] == names.index(name)) & (c.broken[:n] == 0))
        sn, ts = c.sn[rows], np.abs(c.ts[rows])
        rt = np.where(sn < 0, -sn / mat.tensile_strength, 0.0)
        rs = ts / (mat.cohesion + np.maximum(sn, 0.0) * np.tan(np.radians(mat.friction)))
        out[name] = (rows, rt, rs)
    return out


def demand(m, stages, real, t0, head):
    """The --demand run (module docstring); ``head`` goes into the JSON line."""
    import numpy as np

    from dem_core.workflow.stages import ChangeMaterial

    i = 0
    while True:                             # up to and with the gravity stage's solve
        steps, verdict, _ = stages[i].run(m)
        i += 1
        if steps:
            break
    moved0 = {k: [round(float(x), 2) for x in m.point_motion(k)[:2]] for k in m.points}
    t_gravity = time.time() - t0
    n0 = int(m.cracks.count[0])
    print(f"  gravity at high strength: {verdict}, {steps} steps, {n0} cracks, {moved0}, "
          f"{t_gravity:.0f} s "
          f"({1e3 * t_gravity / max(steps, 1):.2f} ms a step), dt {m.dt:.3g} s", flush=True)
    rows = {}
    for name, (r, rt, rs) in strength_ratios(m, real).items():
        c = m.contacts
        xy = 0.5 * (m.state.pos[c.block_a[r]] + m.state.pos[c.block_b[r]])
        over = np.flatnonzero(np.maximum(rt, rs) > 1.0)
        rows[name] = dict(contacts=int(r.size), above_T=int((rt > 1).sum()),
                          above_shear=int((rs > 1).sum()), above_half=int(
                              (np.maximum(rt, rs) > 0.5).sum()),
                          max_tension_ratio=round(float(rt.max()), 2),
                          max_shear_ratio=round(float(rs.max()), 2),
                          where_above=[[round(float(x), 1) for x in xy[j]] +
                                       [round(float(max(rt[j], rs[j])), 2)] for j in over])
        print(f"  {name}: {json.dumps(rows[name])}", flush=True)
    while isinstance(stages[i], ChangeMaterial):
        stages[i].run(m)
        i += 1
    after = []
    for k in (50, 150, 800, 2000, 5000):
        t1 = time.time()
        m.cycle(k)
        t1 = time.time() - t1
        modes = m.cracks.rows[n0:int(m.cracks.count[0]), 3]
        moved = {k: [round(float(x), 2) for x in m.point_motion(k)[:2]] for k in m.points}
        after.append(dict(steps=int(m.step), tension=int((modes == 1).sum()),
                          shear=int((modes == 2).sum()), points=moved,
                          ms_per_step=round(1e3 * t1 / k, 2)))
        print(f"  real strengths, step {m.step}: {json.dumps(after[-1])}", flush=True)
    print(json.dumps(dict(head, gravity=dict(verdict=str(verdict), steps=int(steps), cracks=n0,
                                             points=moved0, seconds=round(t_gravity)),
                          demand=rows, after_real_strengths=after,
                          seconds=round(time.time() - t0))), flush=True)


if __name__ == "__main__":
    main()
