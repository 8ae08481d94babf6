"""What cables do for the jointed slope of ``field_slope.py``: its factor of safety with a row
of grouted cables, in the DEM and by limit equilibrium.

The slope (30 m, face 60 deg, bedding dipping 40 deg out of the face, c = 20 kPa, phi = 35 deg,
k = 1.5, three lifts, a water table) is cut and drained as in ``field_slope.py``; then five
cables are installed across the face, collared every 5 m of height, 20 m long, dipping 15 deg
into the slope, 4 m apart along the slope (the thesis's Checkerboard Creek cables, section 7.8,
Table 7.5: 625 mm^2 strand, E 98 GPa, yield 0.548 MN, grout 6 GN/m/m and 0.32 MN/m), and the
strength-reduction factor of safety of the joints is searched again (the cables keep their
strength, as UDEC's structural elements do under strength reduction).

Asserted: the DEM's factor of safety with the cables equals, within 5 %, the smallest
limit-equilibrium F of planar sliding on a daylighting bedding joint with each cable that
crosses the joint pulling the wedge at its yield force (Hoek & Bray 1981, ch. 7, with a bolt
force T along the cable's axis u)::

    F = (c L + (W cos psi - U - sum T u.n) tan phi) / (W sin psi + sum T u.t)

(n the joint's upward normal, t down its dip). ``python examples/bolted_slope.py`` prints both
factors of safety with and without the cables, and writes results/bolted_slope.png (the
failing mechanism with the cables' axial forces).

Measured (2026-11-25, Intel Xeon 2-core VM): see docs/mechanics.md ("Support").
"""
import math
import time

import numpy as np

import field_slope as fs
from dem_core.workflow.scene import build_model
from dem_core.workflow.stages import FactorOfSafety, run_stages
from dem_core.components.support import Cable

AREA, E_STEEL, YIELD = 625e-6, 98e9, 0.548e6             # m^2, Pa, N
GROUT_K, GROUT_S, SPACING = 6e9, 0.32e6, 4.0             # N/m/m, N/m, m
LENGTH, PLUNGE = 20.0, 15.0                              # m, deg below horizontal, into the slope
HEIGHTS = (3.0, 8.0, 13.0, 18.0, 23.0)                   # collars above the toe, m


def cables():
    """The row of cables: collars 0.2 m inside the face, pointing into the slope."""
    u = np.array([-math.cos(math.radians(PLUNGE)), -math.sin(math.radians(PLUNGE))])
    out = []
    for z in HEIGHTS:
        y = fs.BASE + z
        face = np.array([fs.CREST + (fs.TOP - y) / math.tan(math.radians(fs.FACE)), y])
        collar = face + 0.2 * u
        out.append(Cable(tuple(collar), tuple(collar + LENGTH * u), area=AREA, E=E_STEEL,
                         yield_tension=YIELD, grout_stiffness=GROUT_K, grout_strength=GROUT_S,
                         spacing=SPACING, segment_length=0.5))
    return out


def planar_sliding_bolted(model, bolts):
    """(F, joint offset): the smallest limit-equilibrium F of planar sliding with the cables
    that cross the joint under the wedge at their yield force (module docstring)."""
    from shapely.geometry import LineString, Point

    psi, tan_phi = math.radians(fs.BEDDING), math.tan(math.radians(fs.JOINT.friction))
    n = np.array([math.sin(psi), math.cos(psi)])
    t = np.array([math.cos(psi), -math.sin(psi)])
    best = (math.inf, None)
    for d, wedge, plane, w, u in fs.sliding_wedges(model):
        pull_n = pull_t = 0.0
        for b in bolts:
            if LineString([b.collar, b.end]).intersects(plane) and \
                    wedge.buffer(1e-6).contains(Point(b.collar)):
                axis = np.subtract(b.end, b.collar) / math.dist(b.collar, b.end)
                force = b.yield_tension / b.spacing
                pull_n += force * float(axis @ n)
                pull_t += force * float(axis @ t)
        f = ((fs.JOINT.cohesion * plane.length + (w * math.cos(psi) - u - pull_n) * tan_phi)
             / (w * math.sin(psi) + pull_t))
        best = min(best, (f, d), key=lambda b: b[0])
    return best


def main(quick=True):
    t0 = time.perf_counter()
    sc = fs.scene(spacing=5.0)
    model = build_model(sc)
    run_stages(model, sc.stages[:-1])                     # cut, drained: not yet reduced
    bolts = cables()
    model.install(bolts)
    search = FactorOfSafety(("*",), f_levels=(1.0, 1.2, 1.4, 1.6, 2.0, 2.5),
                            refine_to=0.05 if quick else 0.02, failure_displacement=0.5)
    fos = run_stages(model, [search])[0].detail
    seconds = time.perf_counter() - t0
    f_plain, _ = fs.planar_sliding(model)
    f_le, d = planar_sliding_bolted(model, bolts)
    print(f"DEM with {len(bolts)} cables: F = {fos['factor_of_safety']:.3f} (first failed "
          f"{fos['first_failed']:.3f}), {seconds:.1f} s; limit equilibrium on the joint at "
          f"{d:.2f} m with the cables at yield: F = {f_le:.3f} (no cables: {f_plain:.3f})")
    assert abs(fos["factor_of_safety"] / f_le - 1) < 0.05
    if not quick:
        picture(model, fos)
    return fos["factor_of_safety"]


def picture(model, fos, path="results/bolted_slope.png"):
    """The mechanism at the first F that failed, with the cables' axial forces."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from pathlib import Path

    from dem_core.output.plot import plot_model

    fig, ax = plt.subplots(figsize=(10, 6.5))
    plot_model(model, ax=ax)
    ax.set_title(f"DEM with cables at F = {fos['first_failed']:.2f} (first failed; "
                 f"F = {fos['factor_of_safety']:.2f} stood)")
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110, bbox_inches="tight")
    plt.close(fig)
    print(f"wrote {path}")


if __name__ == "__main__":
    main(quick=False)
