"""Hard Hoek-Brown cases do not break the Newton loop: step cutting rescues them.

A strip footing on very poor, disturbed rock mass (GSI 10, D = 0 or 1) pushed to twice its
rock-mass strength in two load steps. Before the fixes these raised from the linear solver
(MUMPS error 76 on a singular tangent) or from the local return mapping (singular Jacobian at
a corner) instead of cutting the step.
"""
import numpy as np
import pytest

from continuum_ref import hoek_brown as hb
from continuum_ref.materials import HoekBrown


def _footing(material, steps=2, half=0.5):
    from continuum_ref.mesh import PolygonRegion, build_mesh, refine_near
    from continuum_ref.model import ContinuumModel

    md = build_mesh([PolygonRegion("rock", [(0, -2), (3, -2), (3, 0), (half, 0), (0, 0)])], 0.3,
                    size_field=refine_near([(half, 0.0)], 0.1, 0.3, 0.05, 1.0))
    model = ContinuumModel(md, material, 2500.0)
    model.fix(lambda x: np.isclose(x[0], 0.0) | np.isclose(x[0], 3.0), (0,))
    model.fix(lambda x: np.isclose(x[1], -2.0), (0, 1))
    assert model.solve_gravity(1.0, first_step=1.0).converged
    strength = hb.global_strength(material.sci, material.mb, material.s, material.a)
    model.fix(lambda x: np.isclose(x[1], 0.0) & (x[0] <= half + 1e-9), (1,),
              value=(-2.0 * strength / material.E,))
    return model.solve_load(1.0, first_step=1.0 / steps)


@pytest.mark.parametrize("disturbance", [0.0, 1.0])
def test_step_cutting_carries_poor_rock_mass_to_the_full_load(disturbance):
    result = _footing(HoekBrown.from_gsi(10, 5, 50e6, D=disturbance, nu=0.3))
    assert result.converged and result.load_reached == pytest.approx(1.0)
    assert result.steps > 2            # the two steps were cut: the rescue happened
