"""Mohr-Coulomb zones with a tension cut-off (``dem_core/deformable/zone_plasticity.py``, used by
``zones.add_zone_forces`` and so by the deformable blocks): closed-form checks.

- Elastic zones (no strength, or c = +inf) are the code before plasticity to the bit (stored
  run, ``tests/data/zones_elastic_reference.npz``: the standalone zones from 6456e68, before
  plasticity; the deformable column, a regression guard, stored again when its mesh (gmsh)
  and contacts (split edges) changed).
- A returned stress is admissible and on the surface, its change is -D d eps_p, and every
  kind of return (shear, tension, corner, biaxial tension) is met.
- A patch of zones under plane-strain uniaxial compression between smooth platens
  (strain-controlled, quasi-static) peaks at UCS = 2 c cos phi / (1 - sin phi) and stays there;
  under uniaxial tension it plateaus at T; under a confining stress p it yields at
  N_phi p + UCS.
- The plastic strain's dilatancy ratio d eps_v / d gamma_max is sin psi (0 for psi = 0,
  sin phi when associated).
- Through the Model: a deformable column with a low cohesion yields under its weight, a strong
  one is the elastic model to the bit; save / load resumes to the bit; bad input is refused.
"""
import json
import math
import sys
from pathlib import Path

import numpy as np
import pytest

from dem_core.contact.materials import Material
from dem_core.model import Model
from dem_core.deformable.zone_plasticity import SHEAR, TENSION, mohr_coulomb, strength_table
from dem_core.deformable.zones import (critical_dt, mesh_polygon, mesh_rectangle, run_zone_steps,
                            zones_from_mesh)

sys.path.insert(0, str(Path(__file__).parent))
from test_deformable import column  # noqa: E402

REFERENCE = Path(__file__).parent / "data" / "zones_elastic_reference.npz"
E, NU, C, PHI = 1e9, 0.25, 1e6, 30.0
SIN = math.sin(math.radians(PHI))
UCS = 2 * C * math.cos(math.radians(PHI)) / (1 - SIN)      # 3.464 MPa
N_PHI = (1 + SIN) / (1 - SIN)                               # 3


def reference_zones(strength):
    """The stored run's zones: an irregular pentagon, bottom held, a point load, gravity."""
    pts, tri = mesh_polygon(np.array([[0, 0], [2, 0], [2.5, 1.2], [1, 2], [-0.4, 1.1]]), 0.4)
    z = zones_from_mesh(pts, tri, 1e9, 0.3, 2500.0, strength=strength)
    z.fixity[z.x0[:, 1] < 1e-9] = 3
    z.load[np.argmax(z.x0[:, 1])] = (2e6, -5e6)
    run_zone_steps(z, 400, critical_dt(z), 0.2, 3.0, -9.81)
    return z


@pytest.mark.parametrize("strength", [None, dict(cohesion=np.inf, friction=30.0)])
def test_elastic_zones_are_the_old_code_to_the_bit(strength):
    ref = np.load(REFERENCE)
    z = reference_zones(strength)
    assert np.abs(ref["zone_stress"]).max() > 1e7          # a loaded run, not a trivial one
    for name in ("x", "f", "stress"):
        assert np.array_equal(getattr(z, name), ref[f"zone_{name}"])
    assert not z.plastic.any() and not z.yielded.any()
    m = column(size=0.25)
    m.cycle(300)
    assert np.array_equal(m.zone_state.x, ref["block_x"])
    assert np.array_equal(m.zone_state.stress, ref["block_stress"])
    assert np.array_equal(m.state.pos, ref["block_pos"])


def test_the_return_lands_on_the_surface_by_minus_d_times_the_plastic_strain():
    lam, mu = E * NU / ((1 + NU) * (1 - 2 * NU)), E / (2 * (1 + NU))
    c, phi, psi, T = 1e6, 30.0, 10.0, 0.5e6
    rng = np.random.default_rng(4)
    kinds = set()
    for sxx, syy, sxy in rng.uniform(-8e6, 4e6, (2000, 3)) * [1, 1, 0.5]:
        out = mohr_coulomb(sxx, syy, sxy, lam, mu, c, phi, psi, T)
        nxx, nyy, nxy, dxx, dyy, dxy, mode = out
        m, r = 0.5 * (nxx + nyy), math.hypot(0.5 * (nxx - nyy), nxy)
        fs = N_PHI * (m + r) - (m - r) - 2 * c * math.sqrt(N_PHI)
        ft = m + r - T
        assert fs < 1e-8 * UCS and ft < 1e-8 * T
        if mode == 0:
            assert (nxx, nyy, nxy) == (sxx, syy, sxy)
            continue
        assert max(fs, ft) > -1e-8 * T                       # on the surface
        assert nxx == pytest.approx(sxx - (lam + 2 * mu) * dxx - lam * dyy, abs=1e-3)
        assert nyy == pytest.approx(syy - lam * dxx - (lam + 2 * mu) * dyy, abs=1e-3)
        assert nxy == pytest.approx(sxy - mu * dxy, abs=1e-3)
        two_way = abs(m + r - T) < 1e-6 and r < 1e-6
        kinds.add("two-way" if two_way else mode)
    assert kinds == {SHEAR, TENSION, SHEAR | TENSION, "two-way"}


def specimen(strength, confining=0.0):
    """A 1 m square of 4 zones between smooth platens (y held at the bottom and top rows, one
    corner held in x), with a confining stress ``confining`` (Pa, compression) on its sides
    as point loads p H / 2 at their corners."""
    pts, tri = mesh_rectangle(0, 0, 1, 1, 1, 1)
    z = zones_from_mesh(pts, tri, E, NU, 2500.0, strength=strength)
    bottom, top = z.x0[:, 1] < 1e-9, z.x0[:, 1] > 1 - 1e-9
    z.fixity[bottom | top] = 2
    z.fixity[np.flatnonzero(bottom & (z.x0[:, 0] < 1e-9))] = 3
    z.load[z.x0[:, 0] < 1e-9, 0] = 0.5 * confining
    z.load[z.x0[:, 0] > 1 - 1e-9, 0] = -0.5 * confining
    return z, top


def strain_path(z, top, strain, n=1000, every=4):
    """Move the top platen by ``strain`` (m/m, + stretches) in n increments, ``every`` damped
    steps after each: the mean axial stress syy (Pa) after each increment."""
    dt = critical_dt(z)
    run_zone_steps(z, 2000, dt, 0.8, 0.0, 0.0)               # the confining load first
    out = []
    for _ in range(n):
        z.x[top, 1] += strain / n
        run_zone_steps(z, every, dt, 0.8, 0.0, 0.0)
        out.append(z.stress[:, 1].mean())
    return np.array(out)


def test_uniaxial_compression_peaks_at_the_plane_strain_ucs_and_stays():
    z, top = specimen(dict(cohesion=C, friction=PHI))
    syy = -strain_path(z, top, -0.01)             # yield strain UCS (1 - nu^2) / E = 0.32 %
    assert syy.max() == pytest.approx(UCS, rel=0.01)
    assert syy[499] == pytest.approx(UCS, rel=0.01)     # at 0.5 % strain
    assert syy[-1] == pytest.approx(UCS, rel=0.01)      # at 1 %: perfectly plastic
    assert syy[200] < 0.7 * UCS                          # elastic at 0.2 %
    assert (z.yielded > 0).all()
    elastic, top = specimen(None)
    assert -strain_path(elastic, top, -0.01, n=100, every=20)[-1] > 2.5 * UCS


def test_uniaxial_tension_plateaus_at_the_tensile_strength():
    T = 0.5e6
    z, top = specimen(dict(cohesion=C, friction=PHI, tensile_strength=T))
    syy = strain_path(z, top, 0.002)               # yield strain 0.05 %
    assert syy.max() == pytest.approx(T, rel=0.01)
    assert syy[-1] == pytest.approx(T, rel=0.01)
    assert z.yielded.max() & TENSION or z.yielded.max() & (TENSION << 2)
    assert strength_table(dict(cohesion=C, friction=PHI), 1)[0, 3] == \
        pytest.approx(C / math.tan(math.radians(PHI)))     # T defaults to the apex


def test_confined_compression_yields_at_n_phi_p_plus_ucs():
    p = 2e6
    z, top = specimen(dict(cohesion=C, friction=PHI), confining=p)
    syy = -strain_path(z, top, -0.015)             # yields at about 0.85 %
    assert syy.max() == pytest.approx(N_PHI * p + UCS, rel=0.01)     # 9.46 MPa
    assert syy[-1] == pytest.approx(N_PHI * p + UCS, rel=0.01)
    assert z.stress[:, 0].mean() == pytest.approx(-p, rel=0.01)


@pytest.mark.parametrize("psi", [0.0, PHI])
def test_dilatancy_of_the_plastic_strain_is_sin_psi(psi):
    """d eps_v / d gamma_max = (N_psi - 1) / (N_psi + 1) = sin psi (eps_v = exx + eyy, gamma_max
    = e1 - e3) of each zone's plastic strain (the principal axes stay near x, y: 1e-4)."""
    z, top = specimen(dict(cohesion=C, friction=PHI, dilation=psi))
    strain_path(z, top, -0.01)
    e = z.plastic
    gamma = np.hypot(e[:, 0] - e[:, 1], e[:, 2])
    assert gamma.min() > 1e-4
    assert (e[:, 0] + e[:, 1]) / gamma == pytest.approx(math.sin(math.radians(psi)), abs=1e-4)
    assert not z.plastic[:, 3].any()


def test_a_weak_deformable_column_yields_under_its_weight_a_strong_one_is_elastic():
    """1 m column, rho g H = 19.6 kPa at its base: c = 3 kPa (UCS 10.4 kPa) yields below;
    its top zones (< 2 kPa) do not; c = 1 MPa gives the elastic model's bits."""
    runs = {}
    for name, zs in (("elastic", None), ("strong", {"top": dict(cohesion=1e6, friction=30.0)}),
                     ("weak", {"*": dict(cohesion=3e3, friction=30.0)})):
        m = column(size=0.25, zone_strength=zs, mass_scaling=True)
        m.cycle(3000)
        runs[name] = m.zone_state
    assert not runs["elastic"].yielded.any() and not runs["strong"].yielded.any()
    assert np.array_equal(runs["strong"].x, runs["elastic"].x)
    weak = runs["weak"]
    yc = weak.x0[weak.nodes].mean(axis=1)[:, 1]            # block frame: centroid at 0
    assert (weak.yielded > 0).sum() > len(yc) / 3
    assert not weak.yielded[yc > 0.4].any()
    assert np.abs(weak.plastic).max() > 1e-4
    # it stands: the weak column is still in equilibrium, squeezed more than the elastic one
    u = lambda d: d.x[:, 1] - d.x0[:, 1]
    assert np.ptp(u(weak)) > 1.2 * np.ptp(u(runs["elastic"]))


def test_save_load_and_a_scene_keep_the_strength(tmp_path):
    from dem_core.geometry import GeometrySpec, rectangle
    from dem_core.workflow.scene import Boundary, Scene, build_model

    m = column(size=0.25, zone_strength={"top": dict(cohesion=3e3, friction=30.0)},
               mass_scaling=True)
    m.cycle(300)
    path = tmp_path / "m.npz"
    m.save(path)
    back = Model.load(path)
    assert back.zone_strength == {"top": dict(cohesion=3e3, friction=30.0)}
    m.cycle(500)
    back.cycle(500)
    assert m.zone_state.yielded.any()
    for name in ("x", "plastic", "yielded", "strength", "stress"):
        assert np.array_equal(getattr(back.zone_state, name), getattr(m.zone_state, name))
    # a file without the zones' new fields (written before them) loads as elastic zones
    with np.load(path) as f:
        old = {k: f[k] for k in f.files if k not in ("zone_state.strength",
                                                     "zone_state.plastic", "zone_state.yielded")}
    np.savez(tmp_path / "old.npz", **old)
    before = Model.load(tmp_path / "old.npz").zone_state
    assert np.isinf(before.strength[:, 0]).all() and before.strength.shape == (len(before.area), 4)
    assert not before.plastic.any() and before.yielded.dtype == np.int8
    geo = GeometrySpec([rectangle("base", 0, -0.02, 0.1, 0), rectangle("rock", 0, 0, 0.1, 0.2)])
    sc = Scene(geo, {"*": Material(kn=1e10, ks=5e9, friction=35)}, density=2500.0,
               block_E=1e9, boundaries=[Boundary("base")],
               solver={"deformable": {"rock": 0.05},
                       "zone_strength": {"rock": dict(cohesion=1e5, friction=35.0,
                                                      tensile_strength=1e4)}})
    built = build_model(Scene.from_dict(json.loads(json.dumps(sc.to_dict()))))
    assert np.array_equal(np.unique(built.zone_state.strength, axis=0),
                          [[1e5, 35.0, 0.0, 1e4]])


@pytest.mark.parametrize("zs, word", [
    ({"top": dict(cohesion=-1.0, friction=30.0)}, "cohesion.*-1.0"),
    ({"top": dict(cohesion=1e5, friction=90.0)}, "friction.*90.0"),
    ({"top": dict(cohesion=1e5, friction=30.0, dilation=40.0)}, "dilation.*40.0"),
    ({"top": dict(cohesion=1e5, friction=30.0, tensile_strength=-5.0)},
     "tensile_strength.*-5.0"),
    ({"top": dict(cohesion=1e5, friction=float("nan"))}, "friction.*nan"),
    ({"top": dict(cohesion=1e5)}, "missing.*friction"),
    ({"top": dict(cohesion=1e5, friction=30.0, phi=3)}, "unknown.*phi"),
    ({"nowhere": dict(cohesion=1e5, friction=30.0)}, "nowhere"),
    ({"top": (1e5, 30.0)}, "dict"),
    ({"top": dict(cohesion="1e5", friction=30.0)}, "'1e5'"),
])
def test_bad_zone_strength_is_refused_naming_it(zs, word):
    with pytest.raises(ValueError, match=word):
        column(zone_strength=zs)
    with pytest.raises(ValueError, match="deformable"):
        column(deformable=False, zone_strength={"top": dict(cohesion=1e5, friction=30.0)})
