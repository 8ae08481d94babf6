"""Prandtl's smooth rigid strip footing on weightless soil: the collapse pressure q = c N_c.

N_c = (N_q - 1) cot(phi), N_q = exp(pi tan(phi)) tan^2(45 deg + phi/2) (Prandtl 1921;
Reissner 1924), and N_c = 2 + pi for Tresca (phi = 0); the exact solution for associated flow
(e.g. Chen 1975, Limit Analysis and Soil Plasticity, ch. 4). Half model (B = 1 m, symmetry
plane x = 0 on rollers), the footing a prescribed settlement of the surface nodes under it
(smooth: their horizontal displacement is free), the pressure read from the reaction and
divided by the half width. P2, refined at the footing edge (the singular point).
"""
import math
from types import SimpleNamespace

import numpy as np
import pytest

pytest.importorskip("dolfinx")

from continuum_ref.materials import MohrCoulomb  # noqa: E402
from continuum_ref.mesh import PolygonRegion, build_mesh, refine_near  # noqa: E402
from continuum_ref.model import ContinuumModel  # noqa: E402

HALF, COHESION = 0.5, 1e4           # half width (m), c (Pa)


def prandtl_nc(phi):
    """Bearing capacity factor N_c of a weightless soil (phi in degrees)."""
    if phi == 0.0:
        return 2.0 + math.pi
    t = math.tan(math.radians(phi))
    nq = math.exp(math.pi * t) * math.tan(math.radians(45.0 + phi / 2.0)) ** 2
    return (nq - 1.0) / t


def footing(phi, width, depth, settlement, steps=10, h_min=0.03, h_max=0.3):
    """Push the footing down by `settlement` (m) in `steps` equal steps; q/c after each."""
    md = build_mesh([PolygonRegion("soil", [(0, -depth), (width, -depth), (width, 0),
                                             (HALF, 0), (0, 0)])], h_max,
                    size_field=refine_near([(HALF, 0.0)], h_min, h_max, 0.05, 1.0))
    mat = MohrCoulomb(E=1e7, nu=0.3, cohesion=COHESION, friction=phi)
    model = ContinuumModel(md, mat, 0.0)
    model.fix(lambda x: np.isclose(x[0], 0.0) | np.isclose(x[0], width), (0,))
    model.fix(lambda x: np.isclose(x[1], -depth), (0, 1))
    under = lambda x: np.isclose(x[1], 0.0) & (x[0] <= HALF + 1e-9)  # noqa: E731
    model.fix(under, (1,), value=(-settlement,))
    loads = []
    for k in range(1, steps + 1):
        assert model.solve_load(k / steps).converged
        loads.append(-model.reaction(under, 1) / HALF / COHESION)
    return SimpleNamespace(model=model, loads=np.array(loads), exact=prandtl_nc(phi))


def test_prandtl_factors_are_the_textbook_values():
    assert prandtl_nc(0.0) == pytest.approx(5.142, abs=5e-4)
    assert prandtl_nc(20.0) == pytest.approx(14.83, abs=5e-3)
    assert prandtl_nc(1e-6) == pytest.approx(2.0 + math.pi, rel=1e-5)     # continuous at 0


def test_tresca_footing_reaches_two_plus_pi():
    # The mechanism reaches about 1 m beyond the footing edge: a 3 x 2 m box holds it.
    run = footing(0.0, width=3.0, depth=2.0, settlement=0.02)
    assert run.loads[-1] == pytest.approx(run.exact, rel=0.03)       # measured +1.5 %
    assert abs(run.loads[-1] - run.loads[-2]) < 0.005 * run.exact    # a plateau
    assert run.loads[0] < 0.8 * run.exact                            # starts elastic


def test_mohr_coulomb_footing_reaches_prandtl_nc():
    # phi = 20 deg, associated: the log-spiral mechanism ends about 3 m from the axis at the
    # surface and 1.2 m deep, so the box is 5 x 3 m; more settlement than Tresca (dilation).
    run = footing(20.0, width=5.0, depth=3.0, settlement=0.05)
    assert run.loads[-1] == pytest.approx(run.exact, rel=0.05)       # measured +1.7 %
    assert abs(run.loads[-1] - run.loads[-2]) < 0.005 * run.exact
    assert run.loads[0] < 0.8 * run.exact
