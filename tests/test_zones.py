"""Deformable zones (dem_core.deformable.zones: the zones on their own), against closed forms:

- the explicit forces are -K u of the assembled stiffness, and a translation strains nothing;
- patch test: on an irregular mesh of a pentagon, a linear displacement imposed on the boundary
  gridpoints gives, statically and by the damped explicit steps, the same linear field inside
  and the same stress D e in every zone;
- a cantilever (L/h = 10, tip shear) converges to Timoshenko's deflection at second order;
- without damping the explicit step conserves energy, is stable at the critical step and
  blows up at three times it;
- bad input is refused naming the value.
"""
import math

import numpy as np
import pytest
from scipy.sparse.linalg import spsolve

from dem_core.deformable import zones as Z

E, NU, RHO = 1e9, 0.25, 2500.0
PENTAGON = [(0.0, 0.0), (1.0, 0.0), (1.2, 0.8), (0.3, 1.1), (-0.2, 0.5)]


def _on_boundary(pts, polygon):
    poly = np.asarray(polygon)
    d = np.full(len(pts), np.inf)
    for a, b in zip(poly, np.roll(poly, -1, axis=0)):
        t = np.clip(((pts - a) @ (b - a)) / ((b - a) @ (b - a)), 0, 1)
        d = np.minimum(d, np.linalg.norm(pts - (a + t[:, None] * (b - a)), axis=1))
    return d < 1e-9


def _static(z, fixed_dofs, u_fixed, load=None):
    """Solve K u = load with u given on ``fixed_dofs``."""
    K = Z.stiffness_matrix(z)
    n = K.shape[0]
    free = np.setdiff1d(np.arange(n), fixed_dofs)
    u = np.zeros(n)
    u[fixed_dofs] = u_fixed
    rhs = (np.zeros(n) if load is None else load) - K @ u
    u[free] = spsolve(K[free][:, free].tocsc(), rhs[free])
    return u


def test_explicit_forces_are_minus_k_u_and_translation_is_free():
    pts, tri = Z.mesh_polygon(PENTAGON, 0.3)
    z = Z.zones_from_mesh(pts, tri, E, NU, RHO)
    rng = np.random.default_rng(3)
    u = 1e-7 * rng.standard_normal(z.x.shape)        # small: co-rotation adds O(u^2)
    z.x[:] = z.x0 + u
    Z.add_zone_forces(z)
    f = Z.stiffness_matrix(z) @ u.ravel()
    assert np.allclose(z.f.ravel(), -f, rtol=0, atol=1e-5 * np.abs(f).max())
    z.f[:] = 0.0
    z.x[:] = z.x0 + np.array([0.37, -1.2])
    Z.add_zone_forces(z)
    assert np.abs(z.f).max() < 1e-6 and np.abs(z.stress).max() < 1e-3


def test_patch_test_linear_field_is_exact():
    pts, tri = Z.mesh_polygon(PENTAGON, 0.25)
    z = Z.zones_from_mesh(pts, tri, E, NU, RHO)
    grad = np.array([[1e-4, 2e-4], [2e-4, 0.5e-4]])       # u = grad x + c, no rotation
    exact = pts @ grad.T + np.array([1e-3, -2e-3])
    edge = _on_boundary(pts, PENTAGON)
    assert 0 < edge.sum() < len(pts)
    dofs = np.flatnonzero(np.repeat(edge, 2))
    u = _static(z, dofs, exact.ravel()[dofs]).reshape(-1, 2)
    assert np.abs(u - exact).max() < 1e-12
    # every zone carries D e of the imposed gradient
    exx, eyy, gxy = grad[0, 0], grad[1, 1], grad[0, 1] + grad[1, 0]
    lam, mu = E * NU / ((1 + NU) * (1 - 2 * NU)), E / (2 * (1 + NU))
    z.x[:] = z.x0 + u
    Z.add_zone_forces(z)
    want = [(lam + 2 * mu) * exx + lam * eyy, lam * exx + (lam + 2 * mu) * eyy, mu * gxy]
    assert np.allclose(z.stress, want, rtol=1e-9)
    # the damped explicit steps reach the same field from rest
    z2 = Z.zones_from_mesh(pts, tri, E, NU, RHO)
    z2.x[edge] += exact[edge]
    z2.fixity[edge] = Z.FIX_X | Z.FIX_Y
    Z.run_zone_steps(z2, 6000, Z.critical_dt(z2), 0.8, 0.0, 0.0)
    assert np.abs((z2.x - z2.x0) - exact).max() < 1e-6 * np.abs(exact).max()


def test_a_rigid_rotation_strains_nothing_and_a_strained_zone_turns_its_stress():
    pts, tri = Z.mesh_polygon(PENTAGON, 0.3)
    z = Z.zones_from_mesh(pts, tri, E, NU, RHO)
    t = math.radians(30.0)
    R = np.array([[math.cos(t), -math.sin(t)], [math.sin(t), math.cos(t)]])
    z.x[:] = z.x0 @ R.T + np.array([2.0, -1.0])
    Z.add_zone_forces(z)
    scale = E * 1e-4 * z.area.sum()                          # forces of a 1e-4 strain
    assert np.abs(z.f).max() < 1e-8 * scale and np.abs(z.stress).max() < 1e-8 * E * 1e-4
    assert Z.strain_energy(z) < 1e-12 * E * 1e-8 * z.area.sum()
    # stretched 1e-4 along x, then turned 90 degrees: the stretch lies along y
    z.f[:] = 0.0
    z.x[:] = (z.x0 * [1.0 + 1e-4, 1.0]) @ np.array([[0.0, -1.0], [1.0, 0.0]]).T
    Z.add_zone_forces(z)
    lam, mu = E * NU / ((1 + NU) * (1 - 2 * NU)), E / (2 * (1 + NU))
    assert np.allclose(z.stress[:, 1], (lam + 2 * mu) * 1e-4, rtol=1e-6)
    assert np.allclose(z.stress[:, 0], lam * 1e-4, rtol=1e-6)


def _cantilever(nx, ny, L=10.0, h=1.0, P=1e5):
    pts, tri = Z.mesh_rectangle(0.0, -h / 2, L, h / 2, nx, ny)
    z = Z.zones_from_mesh(pts, tri, E, NU, RHO)
    clamp = np.flatnonzero(np.isclose(pts[:, 0], 0.0))
    tip = np.flatnonzero(np.isclose(pts[:, 0], L))
    load = np.zeros(2 * len(pts))
    # consistent nodal loads of a uniform shear P / h on the end (trapezoid rule)
    ys = np.sort(pts[tip, 1])
    w = np.zeros(len(ys))
    w[:-1] += 0.5 * np.diff(ys)
    w[1:] += 0.5 * np.diff(ys)
    order = tip[np.argsort(pts[tip, 1])]
    load[2 * order + 1] = -P / h * w
    dofs = np.concatenate([2 * clamp, 2 * clamp + 1])
    u = _static(z, dofs, np.zeros(len(dofs)), load).reshape(-1, 2)
    return -u[tip, 1].mean()


def test_cantilever_converges_to_timoshenko_at_second_order():
    L, h, P = 10.0, 1.0, 1e5
    Ep, G = E / (1 - NU ** 2), E / (2 * (1 + NU))            # plane strain
    exact = P * L ** 3 / (3 * Ep * h ** 3 / 12) + P * L / (5 / 6 * G * h)
    d = [_cantilever(10 * k, k) for k in (1, 2, 4, 8)]
    diffs = np.diff(d)
    assert all(x > 0 for x in diffs)                          # stiff from below, as a CST is
    assert diffs[-2] / diffs[-1] > 3.0                        # O(h^2): the ratio tends to 4
    assert d[-1] == pytest.approx(exact, rel=0.03)


def test_undamped_energy_is_conserved_and_the_step_bound_holds():
    pts, tri = Z.mesh_rectangle(0.0, -0.5, 5.0, 0.5, 10, 2)

    def released(dt_factor, steps):
        z = Z.zones_from_mesh(pts, tri, E, NU, RHO)
        clamp = np.isclose(pts[:, 0], 0.0)
        z.fixity[clamp] = Z.FIX_X | Z.FIX_Y
        z.x[:, 1] += -1e-3 * (pts[:, 0] / 5.0) ** 2             # bent, then let go
        dt = dt_factor * Z.critical_dt(z, safety=1.0)
        e0 = Z.strain_energy(z)
        energy = []
        for _ in range(steps // 50):
            Z.run_zone_steps(z, 49, dt, 0.0, 0.0, 0.0)
            strain, v_before = Z.strain_energy(z), z.v.copy()
            Z.run_zone_steps(z, 1, dt, 0.0, 0.0, 0.0)
            v = 0.5 * (v_before + z.v)                # leapfrog: v at the strain's time
            energy.append(strain + 0.5 * (z.mass * (v ** 2).sum(axis=1)).sum())
        return e0, np.array(energy)

    e0, energy = released(0.5, 4000)
    assert np.abs(energy / e0 - 1.0).max() < 0.02
    _, energy = released(1.0, 4000)                           # Gershgorin: still stable
    assert np.isfinite(energy).all() and energy.max() < 1.1 * e0
    with np.errstate(over="ignore", invalid="ignore"):        # (it blows up, as it should)
        _, energy = released(3.0, 1000)
    assert not (np.isfinite(energy).all() and energy.max() < 10 * e0)


@pytest.mark.parametrize("kw, word", [(dict(E=-1.0), "E"), (dict(nu=0.5), "nu"),
                                      (dict(density=math.nan), "density")])
def test_bad_input_is_refused_naming_it(kw, word):
    pts, tri = Z.mesh_rectangle(0, 0, 1, 1, 1, 1)
    args = dict(E=E, nu=NU, density=RHO) | kw
    with pytest.raises(ValueError, match=word):
        Z.zones_from_mesh(pts, tri, **args)
    with pytest.raises(ValueError, match="no area"):
        Z.zones_from_mesh(np.array([[0, 0], [1, 0], [2, 0.0]]), [[0, 1, 2]], E, NU, RHO)
    with pytest.raises(ValueError, match="size"):
        Z.mesh_polygon(PENTAGON, 0.0)
