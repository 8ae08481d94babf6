"""Continuum column of the ``lajtai`` case: UCS and direct-shear envelope of an intact plaster
specimen in ``continuum_ref`` (plane strain, P2, Mohr-Coulomb with a tension cut-off).

Material: plaster of Paris as a Mohr-Coulomb solid with the lab values of thesis 3.5:
friction 37, cohesion from UCS 4.1 MPa (c = UCS (1 - sin phi) / (2 cos phi) = 1.02 MPa),
tension cut-off 1.1 MPa, E 4.5 GPa (the thesis's block modulus), nu 0.25, associated flow
(the non-associated return is the weak point of ``continuum_ref``, docs/continuum.md).

- UCS: the 2:1 specimen of the DEM scene, bottom fixed (glued platen), top pushed down
  uniformly; UCS = peak of the top reaction / width.
- Direct shear: the DEM shear specimen (150 x 75 mm) with a stiff elastic plate on top whose
  weight gives the normal stress (gravity is stepped separately from the prescribed
  displacements, so the normal stress stays constant while shearing); the lower box is the
  bottom face and the lower part of the left face moved in +x, the upper box the upper part of
  the right face held in x. Peak shear = peak x reaction of the held face / length.

**Written by hand, not from the scenes** (``comparisons.scenes.lajtai``: ``ucs_scene``,
``shear_scene``) through ``continuum_ref.scene_run.run_scene``: both tests are loading paths,
a prescribed platen displacement with the top reaction read at each increment (UCS) and a
normal load held constant while the lower box is displaced (shear). The scenes' paths are
``load`` and ``servo`` stages on the platens and boxes (``comparisons.lab``), which
``run_scene`` refuses (they act on blocks), and it has no stage that prescribes a displacement
or reads a reaction; the shear scene's fixed group (the lower box, a region) is not made of box
sides, which the continuum's boundaries need. The meshes here are the specimens' own
rectangles (and the loading plate of the shear test).

Units SI; reported in MPa.
"""
from __future__ import annotations

import math
import time

import numpy as np

from comparisons.scenes import lajtai as scene
from continuum_ref.materials import Elastic, MohrCoulomb
from continuum_ref.mesh import PolygonRegion, build_mesh
from continuum_ref.model import ContinuumModel
from dem_core.units import STANDARD_GRAVITY

MPA = 1e6
E_PLASTER, NU_PLASTER = scene.THESIS_BLOCK_E, 0.25


def plaster() -> MohrCoulomb:
    phi = scene.THESIS_FRICTION
    p = math.radians(phi)
    c = scene.THESIS_UCS * (1 - math.sin(p)) / (2 * math.cos(p))
    return MohrCoulomb(E=E_PLASTER, nu=NU_PLASTER, cohesion=c, friction=phi,
                       tensile_strength=scene.THESIS_TENSILE)


def _rect(x0, y0, x1, y1):
    return [(x0, y0), (x1, y0), (x1, y1), (x0, y1)]


def ucs(h=0.01, width=scene.UCS_WIDTH, height=scene.UCS_HEIGHT, strain=0.004, steps=20):
    """Peak axial stress (Pa) of the continuum specimen and its stress-strain record."""
    md = build_mesh([PolygonRegion("rock", _rect(0, 0, width, height))], h=h)
    model = ContinuumModel(md, plaster(), 0.0)
    model.fix(lambda x: np.isclose(x[1], 0.0), (0, 1))
    top = lambda x: np.isclose(x[1], height)  # noqa: E731
    model.fix(top, (1,), value=(-strain * height,))
    rec = []
    for k in range(1, steps + 1):
        r = model.solve_load(k / steps)
        if not r.converged:
            break
        rec.append((k / steps * strain, -model.reaction(top, 1) / width))
    rec = np.array(rec)
    return float(rec[:, 1].max()), rec


def shear_peak(sn, h=0.006, length=scene.SHEAR_LENGTH, height=scene.SHEAR_HEIGHT,
               max_disp=0.0015, steps=15, plate=0.005):
    """Peak shear stress (Pa) at normal stress ``sn`` (Pa)."""
    yc, gap = 0.5 * height, height / 6.0
    md = build_mesh([PolygonRegion("rock", _rect(0, 0, length, height)),
                     PolygonRegion("plate", _rect(0, height, length, height + plate))], h=h)
    rho_plate = sn / (STANDARD_GRAVITY * plate)
    model = ContinuumModel(md, {"rock": plaster(), "plate": Elastic(E=100 * E_PLASTER,
                                                                     nu=0.25)},
                           {"rock": 0.0, "plate": rho_plate})
    bottom = lambda x: np.isclose(x[1], 0.0)  # noqa: E731
    low_left = lambda x: np.isclose(x[0], 0.0) & (x[1] <= yc - gap + 1e-9)  # noqa: E731
    up_right = lambda x: np.isclose(x[0], length) & (x[1] >= yc + gap - 1e-9)  # noqa: E731
    model.fix(bottom, (1,))
    model.fix(up_right, (0,))
    if not model.solve_gravity(1.0).converged:
        raise RuntimeError(f"continuum shear box: the normal load {sn:.3g} Pa did not converge")
    model.fix(bottom, (0,), value=(max_disp,))
    model.fix(low_left, (0,), value=(max_disp,))
    taus = []
    for k in range(1, steps + 1):
        r = model.solve_load(k / steps)
        if not r.converged:
            break
        taus.append(-model.reaction(up_right, 0) / length)
    return float(max(taus)) if taus else float("nan")


def run(normal_stresses, h=0.01, progress=None) -> dict:
    """The continuum column: UCS and the envelope at the given normal stresses (Pa); the
    summary reports MPa."""
    t0 = time.perf_counter()
    u, rec = ucs(h=h)
    if progress:
        progress(f"continuum UCS {u / MPA:.3g} MPa")
    env = []
    for sn in normal_stresses:
        env.append([sn / MPA, shear_peak(sn, h=h) / MPA])
        if progress:
            progress(f"continuum shear sn {sn / MPA:g} MPa -> {env[-1][1]:.3g} MPa")
    mat = plaster()
    return {"ucs_mpa": u / MPA, "envelope": env, "h_m": h,
            "material": {"E_gpa": mat.E / 1e9, "nu": mat.nu, "cohesion_mpa": mat.cohesion / MPA,
                         "friction_deg": mat.friction,
                         "tensile_mpa": mat.tensile_strength / MPA, "flow": "associated"},
            "ucs_curve": rec.tolist(), "runtime_s": time.perf_counter() - t0}
