"""The critical step from the largest eigenvalue (``Model(step_estimate="eigen")``,
``dem_core.step.critical_step``): the closed form of a bonded block, and the stability limit."""
import math

import numpy as np
import pytest

from dem_core.contact.materials import Material
from dem_core.model import Model, ModelUnstable
from dem_core.geometry.simple_blocks import brick_grid, from_polygons


def block_on_base(kn, ks, **kw):
    """A unit square bonded on a fixed unit square below it (shared edge y = 1)."""
    bs = from_polygons([[(0, 0), (1, 0), (1, 1), (0, 1)], [(0, 1), (1, 1), (1, 2), (0, 2)]],
                       edge_material="flaw:rock", groups={"base": [0], "top": [1]})
    m = Model(bs, {"flaw:*": Material(kn=kn, ks=ks, breakable=False)}, density=2000,
              damping=0.0, **kw)
    m.fix("base")
    return m


@pytest.mark.parametrize("kn, ks", [(2e9, 5e8), (1e9, 1e10)])
def test_eigen_step_of_a_bonded_block_is_the_closed_form(kn, ks):
    # The edge's two contacts, each of length L = a/2 at the edge ends (-a/2, -a/2) and
    # (a/2, -a/2) from the centroid: K_vv = 2 kn L, and sliding u and rocking w couple,
    # K_uu = 2 ks L, K_uw = 2 ks L a/2, K_ww = 2 (kn + ks) L a^2/4; M = diag(m, m, m a^2/6).
    a, m_ = 1.0, 2000.0
    L, inertia = a / 2, m_ * a * a / 6
    k_uw = np.array([[2 * ks * L, ks * L * a], [ks * L * a, (kn + ks) * L * a * a / 2]])
    d = np.diag([1 / math.sqrt(m_), 1 / math.sqrt(inertia)])
    w2 = max(2 * kn * L / m_, np.linalg.eigvalsh(d @ k_uw @ d)[-1])
    m = block_on_base(kn, ks, step_estimate="eigen", safety=0.5)
    assert m.critical_dt == pytest.approx(2 / math.sqrt(w2), rel=1e-3)
    assert m.dt == pytest.approx(0.5 * m.critical_dt, rel=1e-12)
    bound = block_on_base(kn, ks)
    assert bound.critical_dt < m.critical_dt       # the Gershgorin bound is the safe side


def bonded_wall(kn_over_ks, safety):
    """A wall of bonded bricks (brick bond, half bricks at the ends) on its fixed bottom row,
    undamped, with the step set from the eigenvalue and a small random velocity in every
    free dof. End springs: the eigenvalue is of their lumped stiffness, the exact limit there
    (edge elements are softer in the Loewner order, so for them it is a bound)."""
    bs = brick_grid(4, 4, 0.2, 0.1, stagger=True, edge_material="flaw:rock")
    base = bs.groups["bottom"]
    m = Model(bs, {"flaw:*": Material(kn=1e10, ks=1e10 / kn_over_ks, breakable=False)},
              density=2600, damping=0.0, safety=safety, step_estimate="eigen",
              edge_elements=False)
    m.fix("bottom")
    rng = np.random.default_rng(3)
    free = np.setdiff1d(np.arange(bs.n_blocks), base)
    m.state.vel[free] = 1e-6 * rng.standard_normal((free.size, 2))
    m.state.omega[free] = 1e-5 * rng.standard_normal(free.size)
    return m


@pytest.mark.parametrize("kn_over_ks", [0.1, 1.0, 100.0])
def test_eigen_step_is_the_stability_limit(kn_over_ks):
    # Central differences: stable below 2 / omega_max, the highest mode growing above it.
    below = bonded_wall(kn_over_ks, 0.97)
    e0 = below.kinetic_energy()
    below.cycle(3000)
    assert below.kinetic_energy() + below.strain_energy() < 2 * e0
    above = bonded_wall(kn_over_ks, 1.0)
    above.set_options(dt=1.05 * above.critical_dt)
    with pytest.raises(ModelUnstable):
        above.cycle(3000)


def test_eigen_step_is_a_function_of_the_state():
    # a fixed Lanczos start: the same model gives the same step to the bit, built twice or
    # recomputed (a resumed run steps as one that had not stopped)
    a, b = bonded_wall(1.0, 0.5), bonded_wall(1.0, 0.5)
    assert a.critical_dt == b.critical_dt
    a.update_timestep()
    assert a.critical_dt == b.critical_dt


def test_eigen_step_survives_save_and_load(tmp_path):
    m = block_on_base(1e9, 1e9, step_estimate="eigen")
    m.save(tmp_path / "m.npz")
    back = Model.load(tmp_path / "m.npz")
    assert back.step_estimate == "eigen" and back.dt == m.dt


@pytest.mark.parametrize("kw, word", [({"step_estimate": "exact"}, "'exact'"),
                                      ({"step_estimate": "eigen", "deformable": {"*": 0.5}},
                                       "deformable=")])
def test_bad_step_estimate_is_named(kw, word):
    with pytest.raises(ValueError, match=word):
        block_on_base(1e9, 1e9, **kw)


def test_auto_takes_the_eigenvalue_on_rigid_blocks_rounded_or_not():
    for rounding in (0.0, 0.01):
        auto, eigen = (block_on_base(2e9, 5e8, step_estimate=e, rounding=rounding)
                       for e in ("auto", "eigen"))
        assert auto.critical_dt == eigen.critical_dt
        bound = block_on_base(2e9, 5e8, step_estimate="bound", rounding=rounding)
        assert bound.critical_dt < auto.critical_dt


def resting_stack(kn, ks, d, **kw):
    """A fixed base [-1.5, 1.5] x [-1, 0], a 2 x 0.5 block on it and a unit square on that,
    each 1 um clear of the one below, so every contact is a corner on a face made by the
    search (rounded with radius ``d``), not a shared edge."""
    g = 1e-6
    bs = from_polygons([[(-1.5, -1), (1.5, -1), (1.5, 0), (-1.5, 0)],
                        [(-1, g), (1, g), (1, 0.5 + g), (-1, 0.5 + g)],
                        [(-0.5, 0.5 + 2 * g), (0.5, 0.5 + 2 * g), (0.5, 1.5 + 2 * g),
                         (-0.5, 1.5 + 2 * g)]],
                       edge_material="joint:rock", groups={"base": [0], "middle": [1], "top": [2]})
    m = Model(bs, {"joint:*": Material(kn=kn, ks=ks, friction=89.0, breakable=False)},
              density=2000, damping=0.0, new_contact_material="joint:rock", rounding=d,
              edge_elements=False, **kw)
    m.fix("base")
    return m


@pytest.mark.parametrize("kn, ks", [(2e9, 5e8), (1e9, 1e10)])
def test_eigen_step_of_a_rounded_block_is_the_closed_form(kn, ks):
    # The top square alone on a fixed block (the middle block held too): its two corners
    # rest on the face below, rounded with radius d, so each contact pushes at its arc's
    # touch, (+-(a/2 - d), -a/2) from the centroid: K_vv = 2 kn L, K_uu = 2 ks L,
    # K_uw = 2 ks L a/2, K_ww = 2 kn L (a/2 - d)^2 + 2 ks L a^2/4; M = diag(m, m, m a^2/6).
    a, d, m_ = 1.0, 0.05, 2000.0
    m = resting_stack(kn, ks, d, step_estimate="eigen")
    m.fix("middle")
    c = m.contacts
    top = [k for k in range(c.n) if 2 in (c.block_a[k], c.block_b[k])]
    assert len(top) == 2 and all(c.face[k] == 0 for k in top)
    L = c.length[top[0]]
    assert c.length[top[1]] == pytest.approx(L, rel=1e-12)
    b, inertia = a / 2 - d, m_ * a * a / 6
    k_uw = np.array([[2 * ks * L, ks * L * a],
                     [ks * L * a, 2 * kn * L * b * b + ks * L * a * a / 2]])
    dm = np.diag([1 / math.sqrt(m_), 1 / math.sqrt(inertia)])
    w2 = max(2 * kn * L / m_, np.linalg.eigvalsh(dm @ k_uw @ dm)[-1])
    assert m.critical_dt == pytest.approx(2 / math.sqrt(w2), rel=1e-3)
    sharp = resting_stack(kn, ks, 0.0, step_estimate="eigen")
    sharp.fix("middle")
    assert sharp.critical_dt != pytest.approx(m.critical_dt, rel=1e-3)   # (d matters here)


@pytest.mark.parametrize("kn_over_ks", [0.1, 1.0, 10.0])
def test_eigen_step_is_the_stability_limit_on_rounded_corners(kn_over_ks):
    # the stack under gravity, undamped, on the step from the eigenvalue of its rounded
    # contacts: bounded at 0.97 of the critical step, the highest mode growing at 1.05 (until
    # the model blows up, or its contacts open, which caps it: kinetic energy 1e6 times)
    def run(factor, steps):
        m = resting_stack(1e9, 1e9 / kn_over_ks, 0.02, step_estimate="eigen", safety=1.0)
        m.set_gravity(1.0)
        rng = np.random.default_rng(5)
        m.state.vel[1:] = 1e-6 * rng.standard_normal((2, 2))
        m.set_options(dt=factor * m.critical_dt)
        try:
            m.cycle(steps)
        except ModelUnstable:
            return math.inf
        return m.kinetic_energy()
    below = run(0.97, 3000)
    assert below < 1.0                  # J/m: the drop onto the contacts' static overlap
    assert run(1.05, 3000) > 1e6 * below


