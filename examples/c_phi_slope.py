"""A homogeneous c-phi slope's strength-reduction factor of safety in the continuum against
Bishop's simplified method on the same section.

The slope: H = 10 m, 45 deg face, 3 m of foundation on a rigid base, c = 20 kPa, phi = 30 deg,
gamma = 20 kN/m3, E = 100 MPa, nu = 0.3, associated flow, fixed base and rollers on the sides,
P2 elements refined to h along the ground near the face (3 h elsewhere). Bishop (critical
circle, ``continuum_ref.limit_equilibrium``): F = 1.600; the continuum gives 1.641 / 1.622 /
1.607 at h = 1 / 0.5 / 0.25 m (docs/continuum.md; ``benchmarks/ssr_mesh.py`` times them).
Asserted: F within 5 % of Bishop at h = 1 m (quick) or 0.5 m. ``slope_model`` is the section
that tests/test_continuum_ssr.py and the benchmark use.
"""
import math

import numpy as np

H, D, BETA, X_CREST, LENGTH = 10.0, 3.0, 45.0, 10.0, 35.0
X_TOE = X_CREST + H / math.tan(math.radians(BETA))
GROUND = [(0.0, D + H), (X_CREST, D + H), (X_TOE, D), (LENGTH, D)]
WATER = [(0.0, D + H / 2), (X_CREST + H / 2, D + H / 2), (X_TOE, D), (LENGTH, D)]
C, PHI, GAMMA = 20e3, 30.0, 20e3


def slope_model(h, material, water=None):
    """The slope meshed at h near the face (3 h elsewhere), at equilibrium at 1 g; ``water``:
    a ``dem_core.workflow.water.WaterTable`` (effective stress)."""
    from continuum_ref.mesh import PolygonRegion, build_mesh, refine_near
    from continuum_ref.model import ContinuumModel

    poly = [(0, 0), (LENGTH, 0)] + GROUND[::-1]
    near = np.concatenate([np.linspace((X_CREST - 6, D + H), (X_CREST, D + H), 13),
                           np.linspace((X_CREST, D + H), (X_TOE, D), 29),
                           np.linspace((X_TOE, D), (X_TOE + 4, D), 9)])
    md = build_mesh([PolygonRegion("soil", poly)], 3 * h,
                    size_field=refine_near(near, h, 3 * h, 6.0, 10.0))
    model = ContinuumModel(md, material, GAMMA / 9.81)
    model.fix(lambda x: np.isclose(x[1], 0.0), (0, 1))
    model.fix(lambda x: np.isclose(x[0], 0.0) | np.isclose(x[0], LENGTH), (0,))
    if water is not None:
        model.set_pore_pressure(water.pressure)
    if not model.solve_gravity(1.0).converged:
        raise RuntimeError(f"the slope at h = {h} m did not come to equilibrium under gravity")
    return model


def main(quick=True):
    from continuum_ref import limit_equilibrium as le
    from continuum_ref import ssr
    from continuum_ref.materials import MohrCoulomb

    bishop = le.critical_circle(GROUND, C, PHI, GAMMA, bottom=0.0).factor
    rock = MohrCoulomb(E=1e8, nu=0.3, cohesion=C, friction=PHI, dilation=PHI)
    h = 1.0 if quick else 0.5
    fos = ssr.factor_of_safety(slope_model(h, rock), [rock], f_max=3.0)
    print(f"h = {h} m: F = {fos.value:.3f} (mechanism {fos.mechanism}), Bishop {bishop:.3f}, "
          f"{fos.run_time:.1f} s")
    assert fos.found and abs(fos.value / bishop - 1) < 0.05
    return fos.value


if __name__ == "__main__":
    main(quick=False)
