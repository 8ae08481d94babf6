"""Virtual-lab helpers of the lajtai case (comparisons.lab, comparisons.lajtai.lajtai_envelope).

Closed forms used:
- Lajtai's tensile branch tau = sqrt(T (T + s)) is the stress state (s_yy = s, s_xx = 0,
  t_xy = tau) whose minor principal stress is -T (thesis eq. 3.6).
- The regular rigid-hexagon lattice (dem_core.contact.elastic.lattice_moduli) inverted for kn, ks.
"""
import math

import numpy as np
import pytest

from comparisons import lab
from comparisons.lajtai import lajtai_envelope, mc_cohesion_from_ucs, ucs_member
from comparisons.scenes import lajtai as scene
from dem_core.contact.elastic import lattice_moduli, series_stiffness

MPA = 1e6


def test_tensile_branch_is_the_state_with_minor_principal_stress_minus_T():
    T, s = 1.0e6, np.linspace(0, 3e6, 7)
    tau = lajtai_envelope(s, T, cohesion=5e6, friction=30)       # c large: tensile branch
    s3 = 0.5 * s - np.sqrt(0.25 * s ** 2 + tau ** 2)             # compression positive
    assert np.allclose(s3, -T, rtol=1e-12)


def test_envelope_branches_persistence_and_open_joints():
    s = np.linspace(0.1e6, 3e6, 30)
    tan30 = math.tan(math.radians(30))
    # k = 1: only friction remains
    assert np.allclose(lajtai_envelope(s, 1e6, 1.2e6, 30, persistence=1.0), s * tan30)
    # c < T: the Coulomb line is the lower bridge limit at low stress, the tensile branch
    # (slope T / (2 sqrt(T (T + s))) < tan(phi)) further up
    tau = lajtai_envelope(s, 1.1e6, 0.5e6, 37)
    assert tau[0] == pytest.approx(0.5e6 + s[0] * math.tan(math.radians(37)), rel=1e-12)
    mid = lajtai_envelope(2.2e6, 1.1e6, 0.5e6, 37)    # between 1.64 and 2.72 MPa
    assert mid == pytest.approx(math.sqrt(1.1e6 * 3.3e6), rel=1e-12)
    # and the ultimate friction line beyond
    assert tau[-1] == pytest.approx(s[-1] * math.tan(math.radians(37)), rel=1e-12)
    # strength falls with persistence and never below the friction line
    ks = [lajtai_envelope(s, 1e6, 1.2e6, 30, persistence=k) for k in (0, 0.25, 0.5, 0.7, 1)]
    assert all(np.all(a >= b - 1e-6) for a, b in zip(ks, ks[1:]))
    assert np.all(ks[-1] <= ks[2] + 1e-6)
    # open joints concentrate the normal stress on the bridges: never weaker than closed
    assert np.all(lajtai_envelope(s, 1e6, 1.2e6, 30, 0.5, "open")
                  >= lajtai_envelope(s, 1e6, 1.2e6, 30, 0.5, "closed") - 1e-6)
    # concave (non-linear) for the intact rock
    tau0 = lajtai_envelope(s, 1e6, 1.2e6, 30)
    assert np.all(np.diff(tau0, 2) < 0)


def test_mohr_coulomb_cohesion_from_ucs():
    c = mc_cohesion_from_ucs(4.1e6, 37)
    p = math.radians(37)
    assert 2 * c * math.cos(p) / (1 - math.sin(p)) == pytest.approx(4.1e6, rel=1e-12)


@pytest.mark.parametrize("E, nu, block_E", [(2e9, 0.2, None), (0.4e9, 0.1, 4.5e9)])
def test_stiffness_for_moduli_inverts_the_lattice(E, nu, block_E):
    area = 1e-4
    k = lab.stiffness_for_moduli(E, nu, area, block_E=block_E, block_nu=0.25)
    kn, ks = k["kn"], k["ks"]
    if block_E is not None:                 # the lattice sees the series stiffness
        kn, ks = series_stiffness(kn, ks, 0.5 * k["d"], 0.5 * k["d"], block_E, 0.25,
                                  block_E, 0.25)
    m = lattice_moduli(float(kn), float(ks), k["d"])
    assert m["E"] == pytest.approx(E, rel=1e-9)
    assert m["nu"] == pytest.approx(nu, rel=1e-9)


def test_stiffness_for_moduli_rejects_unreachable_targets():
    with pytest.raises(ValueError, match="softer"):
        lab.stiffness_for_moduli(5e9, 0.2, 1e-4, block_E=1e9)
    with pytest.raises(ValueError, match="nu_2d"):
        lab.stiffness_for_moduli(1e9, 0.3, 1e-4)          # nu_2d = 0.43 > 1/3


def test_calibrate_cohesion_on_a_monotone_and_a_floored_response():
    def ucs(c):                             # a smooth increasing response, Pa
        return 2.0e6 + 3.0 * c ** 0.9 * MPA ** 0.1
    cal = lab.calibrate_cohesion(ucs, 4.1e6, 1.2e6, rel_tol=0.01)
    assert cal["converged"] and abs(ucs(cal["cohesion"]) / 4.1e6 - 1) <= 0.01
    floor = lambda c: 8e6 + 1e-3 * c        # noqa: E731  out of reach: does not respond
    cal = lab.calibrate_cohesion(floor, 4.1e6, 1.2e6)
    assert not cal["converged"] and len(cal["history"]) <= 4


def test_calibration_reproduces_its_own_target_ucs_on_a_voronoi_specimen():
    """Target: the UCS the quick specimen gives at c = 0.6 MPa; start from c = 1.2 MPa.

    The UCS of these specimens responds weakly to c above 0.3 MPa (docs/comparisons.md
    ## lajtai: a wide band of c meets the target) and is neither smooth nor monotone below
    it. With the interfaces divided (the default since 2026-12-02): 4.63, 4.59, 5.21, 5.46,
    5.48 MPa at c = 0.2, 0.25, 0.3, 0.35, 0.4 MPa, so a target taken at 0.3 MPa sits on a
    jump's edge and six secant or regula-falsi runs do not reach it to 3 %. The target is
    taken on the continuous part of the curve."""
    base = dict(test="ucs", edge=0.007, tensile=scene.THESIS_TENSILE, friction=37.0,
                kn=scene.THESIS_KN, ks=scene.THESIS_KS, seed=1, rate=3e-7, max_strain=0.02)
    run = lambda c: ucs_member({**base, "cohesion": c})["peak"]  # noqa: E731
    target = run(0.6e6)
    cal = lab.calibrate_cohesion(run, target, 1.2e6, rel_tol=0.03, max_runs=6)
    assert cal["converged"], cal["history"]
    assert run(cal["cohesion"]) == pytest.approx(target, rel=0.05)     # rerun: reproducible


def test_compression_modulus_of_a_strong_specimen_is_near_the_lattice():
    p = scene.FlawParams(edge_length=0.01, block_E=None, relax_iterations=50)
    m = scene.ucs_model(p, 0.1, 0.2)
    for name in ("flaw:*",):
        m.set_material(name, tensile_strength=1e9, cohesion=1e9)
    cv = lab.compression_test(m, 0.1, 0.2, 3e-7, gauge=("left side", "right side"),
                              max_strain=0.002)
    E2 = lab.elastic_moduli(cv, 0.2, 0.9)["E_2d"]
    d = math.sqrt(2 * m.blocks.area[m.blocks.groups["rock"]].mean() / math.sqrt(3))
    pred = lattice_moduli(p.kn, p.ks, d)["E_2d"]
    # Voronoi assemblies measure 0.96-1.0 x the lattice (docs/mechanics.md); platens add a
    # compliant layer at each end
    assert E2 == pytest.approx(pred, rel=0.2)
    assert m.cracks.count[0] == 0


def test_calibrate_stiffness_corrects_a_biased_assembly():
    """A 'measured' assembly 40 % stiffer than the lattice with nu 0.03 lower (what the quick
    specimens show): the correction reaches the target E and nu."""
    d = 0.01

    def measure(kn, ks):
        m = lattice_moduli(kn, ks, d)
        return 1.4 * m["E"], m["nu"] - 0.03

    k0 = lab.stiffness_for_moduli(0.5e9, 0.1, math.sqrt(3) / 2 * d * d)
    cal = lab.calibrate_stiffness(measure, 0.5e9, 0.1, k0["kn"], k0["ks"], rel_tol=0.01,
                                  max_runs=8)
    assert cal["converged"], cal["history"]
    assert cal["E"] == pytest.approx(0.5e9, rel=0.01)
    assert cal["nu"] == pytest.approx(0.1, abs=0.02)
