"""Staged excavation from an in-situ stress with k = sh / sv = 1.5 (examples/field_slope.py).

Two faults made such a sequence fail or drift (docs/continuum.md, "Staged excavation under a
high horizontal stress"):

- the Mohr-Coulomb return accepted a corner with a negative plastic multiplier for stiff rock
  (the multipliers were compared with a tolerance in Pa, but they are strains), so the return
  jumped between the two edges next to a point and Newton cycled: a 60 deg cut in stiff rock
  did not converge on its second lift at any release step;
- a released excavation kept its stress inside the soft void while its weight was gone, so the
  void moved by metres and, when the release took more than one step, its elastic stress was
  dropped between steps and the final stress depended on the step size.
"""
import math

import numpy as np
import pytest

from continuum_ref import return_mapping as rm
from continuum_ref.materials import Elastic, MohrCoulomb

STIFF_ROCK = MohrCoulomb(E=20e9, nu=0.25, cohesion=40e3, friction=54.0)   # associated


def _rectangle(x0, y0, w, h):
    return [(x0, y0), (x0 + w, y0), (x0 + w, y0 + h), (x0, y0 + h)]


def _fixed_box(model, length):
    model.fix(lambda x: np.isclose(x[1], 0.0), (0, 1))
    model.fix(lambda x: np.isclose(x[0], 0.0) | np.isclose(x[0], length), (0,))
    return model


def test_associated_return_is_nonexpansive_for_stiff_rock():
    # The closest-point return of associated plasticity is a projection in the energy norm,
    # hence nonexpansive: |sig(a) - sig(b)|_E <= |a - b|_E. The trial states are those of a
    # point just below the cut floor of the example (Pa, tension +, zz through the edge where
    # the out-of-plane stress changes from major to intermediate); before the fix the return
    # jumped there (ratio 1000).
    trial = np.zeros((2001, 4))
    trial[:, 0], trial[:, 1], trial[:, 2] = 0.95e6, 6.3e6, np.linspace(1.0e6, 2.0e6, 2001)
    sig, _, mode = rm.return_map(trial, STIFF_ROCK)
    c_inv = np.linalg.inv(rm.elastic_tangent(STIFF_ROCK.E, STIFF_ROCK.nu))

    def energy(d):
        return np.sqrt(np.einsum("ni,ij,nj->n", d, c_inv, d))
    ratio = energy(np.diff(sig, axis=0)) / energy(np.diff(trial, axis=0))
    assert np.all(mode > 0) and ratio.max() <= 1.0 + 1e-6


def test_stepped_release_of_stacked_lifts_equals_the_final_geometry_when_elastic():
    # Elasticity is path independent: two lifts, one under the other, released in four steps
    # each, leave the stress of the final geometry loaded directly (before the fix: 6 % of
    # rho g H off, and the void moved by 16 m in a 6 m model).
    from continuum_ref.mesh import PolygonRegion, build_mesh
    from continuum_ref.model import ContinuumModel

    md = build_mesh([PolygonRegion("rock", _rectangle(0, 0, 6, 4))], h=0.4,
                    groups={"upper": _rectangle(4, 3.25, 2, 0.75),
                            "lower": _rectangle(4, 2.5, 2, 0.75)})
    rock, void = Elastic(E=1e9, nu=0.3), Elastic(E=1e9 * 1e-6, nu=0.3)
    staged = _fixed_box(ContinuumModel(md, rock, 2600.0), 6.0)
    assert staged.solve_gravity(1.0).converged
    for name in ("upper", "lower"):
        result = staged.excavate(name, first_step=0.25)
        assert result.converged and result.steps == 4
    assert np.abs(staged.u.x.array).max() < 1e-3
    direct = _fixed_box(ContinuumModel(md, {"rock": rock, "upper": void, "lower": void},
                                       {"rock": 2600.0, "upper": 0.0, "lower": 0.0}), 6.0)
    assert direct.solve_gravity(1.0).converged
    removed = np.concatenate([md.cells("upper"), md.cells("lower")])
    keep = np.setdiff1d(np.arange(len(staged._cells)), removed)
    scale = 2600.0 * 9.81 * 4.0
    assert np.max(np.abs(staged.stress()[keep] - direct.stress()[keep])) < 1e-4 * scale


def test_cut_in_two_lifts_under_high_horizontal_stress_converges():
    # A 20 m cut (60 deg face) in two 10 m lifts from flat ground, geostatic k = 1.5, stiff
    # Mohr-Coulomb rock, then a water table: every stage converges, the floor heaves and
    # yields (the locked-in horizontal stress exceeds its strength), nothing runs away.
    from continuum_ref.mesh import PolygonRegion, build_mesh
    from continuum_ref.model import ContinuumModel

    length, height, crest = 60.0, 30.0, 20.0

    def lift(y0, y1):
        def x_face(y):
            return crest + (height - y) / math.tan(math.radians(60.0))
        return [(x_face(y0), y0), (length, y0), (length, y1), (x_face(y1), y1)]
    md = build_mesh([PolygonRegion("rock", _rectangle(0, 0, length, height))], 2.0,
                    groups={"lift1": lift(20.0, 30.0), "lift2": lift(10.0, 20.0)},
                    points={"crest": (crest - 0.5, height - 0.5), "floor": (45.0, 10.0)})
    model = _fixed_box(ContinuumModel(md, STIFF_ROCK, 2600.0), length)
    model.set_initial_stress(1.5, g_level=1.0)
    assert model.equilibrate().converged
    model.reset_displacement()
    for name in ("lift1", "lift2"):
        result = model.excavate(name)
        assert result.converged, name
    assert result.displacement["floor"][1] > 1e-4                  # heave of the floor, m
    floor_zone = (model._qp_xy[:, 0] > 40.0) & (model._qp_xy[:, 1] > 8.0) & \
        (model._point_material == 0)
    assert np.mean(model.mode[floor_zone] > 0) > 0.5               # the floor yields
    water = model.solve_pore_pressure(lambda x, y: 9810.0 * np.maximum(8.0 - y, 0.0))
    assert water.converged
    assert np.abs(model.u.x.array).max() < 5e-3                    # no runaway, m


if __name__ == "__main__":
    pytest.main([__file__, "-q"])
