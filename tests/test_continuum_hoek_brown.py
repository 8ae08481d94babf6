"""Hoek-Brown parameter formulas against thesis Tables 6.1 and 6.2 (section 6.4) and published
identities.

No DOLFINx: these run in milliseconds.
"""
import math
import subprocess
import sys

import numpy as np
import pytest

from continuum_ref import hoek_brown as hb

# Thesis Table 6.1 (RMR -> m, s) and Table 6.2 (RMR -> E, K, G in GPa), as printed.
TABLE_6_1 = {40: (0.39, 4.54e-5), 45: (0.55, 1.04e-4), 50: (0.79, 2.40e-4), 55: (1.13, 5.53e-4),
             60: (1.61, 1.27e-3), 65: (2.30, 2.93e-3), 70: (3.28, 6.74e-3), 75: (4.69, 1.55e-2),
             80: (6.71, 3.57e-2)}
TABLE_6_2 = {40: (5.6, 4.7, 2.2), 45: (7.5, 6.2, 2.9), 50: (10.0, 8.3, 3.8), 55: (13.3, 11.1, 5.1),
             60: (17.8, 14.8, 6.8), 65: (23.7, 19.8, 9.1), 70: (31.6, 26.4, 12.2),
             75: (42.2, 35.1, 16.2), 80: (56.2, 46.9, 21.6)}


def _round_sig(x, digits):
    return float(f"{x:.{digits - 1}e}")


@pytest.mark.parametrize("rmr", sorted(TABLE_6_1))
def test_table_6_1_m_and_s_from_1988_disturbed_formulas(rmr):
    m_printed, s_printed = TABLE_6_1[rmr]
    m, s, a = hb.parameters_rmr1988(rmr, mi=28.0, disturbed=True)
    assert round(m, 2) == pytest.approx(m_printed, abs=1e-12)
    assert _round_sig(s, 3) == pytest.approx(s_printed, rel=1e-12)
    assert a == 0.5


@pytest.mark.parametrize("rmr", sorted(TABLE_6_2))
def test_table_6_2_moduli(rmr):
    E_printed, K_printed, G_printed = TABLE_6_2[rmr]
    E = hb.modulus_rmr(rmr)
    K, G = hb.bulk_and_shear_modulus(E, 0.3)
    assert round(E / 1e9, 1) == pytest.approx(E_printed, abs=1e-12)
    assert round(K / 1e9, 1) == pytest.approx(K_printed, abs=1e-12)
    assert round(G / 1e9, 1) == pytest.approx(G_printed, abs=1e-12)


def test_undisturbed_1988_differs_from_disturbed():
    m_u, s_u, _ = hb.parameters_rmr1988(60, 28.0, disturbed=False)
    assert m_u == pytest.approx(28.0 * math.exp(-40.0 / 28.0))
    assert s_u == pytest.approx(math.exp(-40.0 / 9.0))


def test_parameters_2002_known_values_and_limits():
    # GSI 100, D 0 is intact rock: mb = mi, s = 1, a = 1/2 + (e^-20/3 - e^-20/3)/6 = 1/2.
    mb, s, a = hb.parameters(100.0, 10.0)
    assert (mb, s) == pytest.approx((10.0, 1.0))
    assert a == pytest.approx(0.5 + (math.exp(-100 / 15) - math.exp(-20 / 3)) / 6)
    # Hand value: GSI 50, mi 10, D 0.
    mb, s, a = hb.parameters(50.0, 10.0)
    assert mb == pytest.approx(10 * math.exp(-50 / 28), rel=1e-12)
    assert mb == pytest.approx(1.6767, abs=1e-4)
    assert s == pytest.approx(0.0038659, rel=1e-4)
    assert a == pytest.approx(0.50573, abs=1e-5)
    # Disturbance lowers mb and s.
    mb_d, s_d, _ = hb.parameters(50.0, 10.0, D=0.7)
    assert mb_d < mb and s_d < s


def test_strengths_are_consistent_with_the_criterion():
    sci = 50e6
    mb, s, a = hb.parameters(60.0, 15.0, D=0.2)
    sc = hb.uniaxial_compressive_strength(sci, s, a)
    st = hb.tensile_strength(sci, mb, s)
    # sigma1 at sigma3 = 0 is sc; at sigma3 = st the criterion reaches sigma1 = sigma3.
    assert hb.major_principal_stress(0.0, sci, mb, s, a) == pytest.approx(sc)
    assert hb.major_principal_stress(st, sci, mb, s, a) == pytest.approx(st, abs=1e-6 * sci)
    assert st < 0
    with pytest.raises(ValueError, match="sigma3"):
        hb.major_principal_stress(2 * st, sci, mb, s, a)


def test_global_strength_matches_its_definition_for_a_half():
    # For a = 1/2 (eq 18 of Hoek 2002) the global strength is the MC fit's 2 c cos/(1 - sin)
    # over st < sigma3 < sci/4; compare with an explicit least-squares fit (Hoek's own derivation).
    sci, gsi, mi = 80e6, 100.0 - 1e-9, 12.0
    mb, s, a = hb.parameters(gsi, mi)
    scm = hb.global_strength(sci, mb, s, a)
    c, phi = hb.equivalent_mohr_coulomb(sci, mb, s, a, sigma3_max=sci / 4.0)
    ph = math.radians(phi)
    assert scm == pytest.approx(2 * c * math.cos(ph) / (1 - math.sin(ph)), rel=1e-9)


def test_equivalent_mohr_coulomb_is_a_least_squares_fit():
    # Hoek et al. 2002 derive c, phi by fitting sigma1 = k sigma3 + sigma_cm_mc over
    # st < sigma3 < s3max; redo that fit numerically and compare.
    sci, (mb, s, a) = 40e6, hb.parameters(45.0, 12.0, D=0.0)
    st = hb.tensile_strength(sci, mb, s)
    s3max = 5e6
    s3 = np.linspace(st, s3max, 20001)
    s1 = hb.major_principal_stress(s3, sci, mb, s, a)
    k, b = np.polyfit(s3, s1, 1)
    phi_fit = math.degrees(math.asin((k - 1) / (k + 1)))
    c_fit = b * (1 - math.sin(math.radians(phi_fit))) / (2 * math.cos(math.radians(phi_fit)))
    c, phi = hb.equivalent_mohr_coulomb(sci, mb, s, a, s3max)
    assert phi == pytest.approx(phi_fit, abs=0.05)
    assert c == pytest.approx(c_fit, rel=2e-3)


def test_sigma3max_slope_rule_and_modulus():
    scm, gamma, H = 10e6, 25e3, 100.0
    assert hb.sigma3_max_slope(scm, gamma, H) == pytest.approx(0.72 * 10e6 * 4.0 ** -0.91)
    # Em (2002): sci 100 MPa -> 10^((GSI-10)/40) GPa; halved by D = 1; sqrt rule below 100 MPa.
    assert hb.modulus_hoek2002(50.0, 100e6) == pytest.approx(10e9)
    assert hb.modulus_hoek2002(50.0, 200e6) == pytest.approx(10e9)
    assert hb.modulus_hoek2002(50.0, 25e6, D=1.0) == pytest.approx(0.5 * 0.5 * 10e9)


@pytest.mark.parametrize("bad", [dict(gsi=-1, mi=10), dict(gsi=50, mi=0), dict(gsi=50, mi=10, D=2),
                                 dict(gsi=float("nan"), mi=10)])
def test_bad_input_is_rejected_with_the_name(bad):
    name = [k for k, v in bad.items() if not (0 <= v <= 100) or v != v or (k == "mi" and v <= 0)
            or (k == "D" and v > 1)][0]
    with pytest.raises(ValueError, match=name):
        hb.parameters(**bad)


def test_hoek_brown_imports_without_dolfinx():
    code = (
        "import sys\n"
        "class Block:\n"
        "    def find_spec(self, name, path=None, target=None):\n"
        "        if name.split('.')[0] in ('dolfinx', 'gmsh', 'ufl', 'petsc4py', 'basix'):\n"
        "            raise ImportError('blocked ' + name)\n"
        "sys.meta_path.insert(0, Block())\n"
        "import continuum_ref.hoek_brown, continuum_ref.return_mapping\n"
        "assert 'dolfinx' not in sys.modules\n"
    )
    subprocess.run([sys.executable, "-c", code], check=True)
