"""Return mapping (numpy, no DOLFINx): on the surface, closest point, tangent = finite differences.

Trial stresses are random plane-strain states (Mandel, tension positive) spread over compression,
tension, the apex regions and the edges, from a fixed seed.
"""
import numpy as np
import pytest
from scipy.optimize import minimize

from continuum_ref import return_mapping as rm
from continuum_ref.materials import HoekBrown, MohrCoulomb

MATERIALS = {
    "mc_cutoff": (MohrCoulomb(E=1e9, nu=0.3, cohesion=1e6, friction=30.0,
                              tensile_strength=0.5e6), 5e6),
    "tresca": (MohrCoulomb(E=1e9, nu=0.3, cohesion=1e6, friction=0.0), 5e6),
    "mc_nonassociated": (MohrCoulomb(E=1e9, nu=0.25, cohesion=1e6, friction=35.0, dilation=5.0,
                                     tensile_strength=0.2e6), 5e6),
    "hoek_brown": (HoekBrown.from_gsi(50.0, 10.0, 50e6, E=5e9), 10e6),
    # the c-phi slope of tests/test_continuum_ssr.py with psi = 0 (issue 53)
    "mc_psi_zero": (MohrCoulomb(E=1e8, nu=0.3, cohesion=20e3, friction=30.0, dilation=0.0),
                    100e3),
}


def _trial(scale, n=3000, seed=1):
    rng = np.random.default_rng(seed)
    shift = scale * rng.uniform(-0.3, 1.0, size=(n, 1)) * np.array([1, 1, 1, 0])
    return rng.normal(size=(n, 4)) * scale - shift


def _principal_compression(sig):
    eig, _ = rm.principal_decomposition(sig)
    return -np.sort(eig, axis=1)


@pytest.mark.parametrize("name", sorted(MATERIALS))
def test_return_lands_on_the_surface_and_keeps_elastic_points(name):
    mat, scale = MATERIALS[name]
    sig_tr = _trial(scale)
    sig, _, mode = rm.return_map(sig_tr, mat)
    f = rm.yield_function(_principal_compression(sig), mat)
    plastic = mode > 0
    assert 0.3 < plastic.mean() < 0.999                    # both kinds were exercised
    assert np.all(f <= 1e-9 * scale)                        # admissible everywhere
    assert np.max(np.abs(f[plastic])) < 1e-9 * scale        # on the surface where it yielded
    np.testing.assert_array_equal(sig[~plastic], sig_tr[~plastic])
    f_tr = rm.yield_function(_principal_compression(sig_tr), mat)
    assert np.all(f_tr[plastic] > 0)


@pytest.mark.parametrize("name", ["mc_cutoff", "hoek_brown", "tresca"])
def test_associated_return_is_the_closest_point_in_the_energy_norm(name):
    # Independent check with a general optimiser in principal space (ordered, compression +).
    mat, scale = MATERIALS[name]
    sig_tr = _trial(scale, n=40, seed=7)
    sig, _, mode = rm.return_map(sig_tr, mat)
    lam, G = (mat.E * mat.nu / ((1 + mat.nu) * (1 - 2 * mat.nu)), mat.E / (2 * (1 + mat.nu)))
    Dinv = np.linalg.inv(lam * np.ones((3, 3)) + 2 * G * np.eye(3))
    got, trial = _principal_compression(sig), _principal_compression(sig_tr)
    checked = 0
    if isinstance(mat, MohrCoulomb):   # the planes one by one: smooth constraints for SLSQP
        A, b, _, _ = rm._mohr_coulomb_planes(mat)
        surface = lambda x: -(A @ x - b / scale)  # noqa: E731
    else:
        surface = lambda x: -rm.yield_function(x[None] * scale, mat)[:1] / scale  # noqa: E731
    for p in np.nonzero(mode > 0)[0]:
        s_tr = trial[p] / scale
        cons = [{"type": "ineq", "fun": surface},
                {"type": "ineq", "fun": lambda x: np.array([x[0] - x[1], x[1] - x[2]])}]
        start = got[p] / scale * 0.9 + 0.1 * s_tr
        res = minimize(lambda x: (x - s_tr) @ Dinv @ (x - s_tr) * mat.E, start,
                       constraints=cons, method="SLSQP", options={"ftol": 1e-14, "maxiter": 500})
        ours = (got[p] / scale - s_tr) @ Dinv @ (got[p] / scale - s_tr) * mat.E
        feasible = rm.yield_function(res.x[None] * scale, mat)[0] <= 1e-8 * scale
        if res.success and feasible:
            checked += 1
            assert ours <= res.fun * (1 + 1e-5) + 1e-12, (name, p, got[p], res.x * scale)
    assert checked >= 15


@pytest.mark.parametrize("name", sorted(MATERIALS))
def test_tangent_matches_central_finite_differences(name):
    mat, scale = MATERIALS[name]
    sig_tr = _trial(scale, n=400, seed=3)
    _, C, mode = rm.return_map(sig_tr, mat)
    De = rm.elastic_tangent(mat.E, mat.nu)
    h = 1e-6 * scale / mat.E
    fd = np.empty_like(C)
    for k in range(4):
        d = np.zeros(4)
        d[k] = h
        plus, _, _ = rm.return_map(sig_tr + De @ d, mat)
        minus, _, _ = rm.return_map(sig_tr - De @ d, mat)
        fd[:, :, k] = (plus - minus) / (2 * h)
    err = np.abs(fd - C).max(axis=(1, 2)) / mat.E
    assert (mode > 0).sum() > 100
    assert np.quantile(err, 0.99) < 1e-6 and err.max() < 1e-4
    if name not in ("mc_nonassociated", "mc_psi_zero"):   # associated: symmetric tangent
        assert np.abs(C - C.transpose(0, 2, 1)).max() < 1e-9 * mat.E


def _central_difference_tangent(sig_tr, mat, h):
    """d sigma / d eps by central differences in each Mandel strain component (step h)."""
    De = rm.elastic_tangent(mat.E, mat.nu)
    fd = np.empty((len(sig_tr), 4, 4))
    for k in range(4):
        d = np.zeros(4)
        d[k] = h
        fd[:, :, k] = (rm.return_map(sig_tr + De @ d, mat)[0]
                       - rm.return_map(sig_tr - De @ d, mat)[0]) / (2 * h)
    return fd


def test_psi_zero_tangent_at_one_point_is_the_non_symmetric_consistent_tangent():
    # One Gauss point of the psi = 0 slope material on the main plane (distinct principal
    # stresses, rotated axes). Principal part: d s / d s_tr = I - Dp g a^T / (a^T Dp g) with
    # the normal a = (1, 0, -kp) and the flow direction g = (1, 0, -kq), kq = 1 for psi = 0
    # (de Souza Neto, Peric & Owen 2008, sec. 8.2); the full tangent, spin terms included,
    # equals central differences and is not symmetric (a Cholesky / CG solver would be wrong).
    mat = MohrCoulomb(E=1e8, nu=0.3, cohesion=20e3, friction=30.0, dilation=0.0)
    sig_tr = np.array([[-150e3, -20e3, -60e3, np.sqrt(2) * 30e3]])
    _, C, mode = rm.return_map(sig_tr, mat)
    assert mode[0] == rm.SHEAR
    lam, G = mat.E * mat.nu / ((1 + mat.nu) * (1 - 2 * mat.nu)), mat.E / (2 * (1 + mat.nu))
    Dp = lam * np.ones((3, 3)) + 2 * G * np.eye(3)
    kp = (1 + np.sin(np.radians(30.0))) / (1 - np.sin(np.radians(30.0)))
    a, g = np.array([1.0, 0.0, -kp]), np.array([1.0, 0.0, -1.0])
    _, jac, _ = rm.mohr_coulomb_principal(_principal_compression(sig_tr), mat)
    np.testing.assert_allclose(jac[0], np.eye(3) - np.outer(Dp @ g, a) / (a @ Dp @ g),
                               atol=1e-12)
    fd = _central_difference_tangent(sig_tr, mat, 1e-7 * 100e3 / mat.E)
    assert np.abs(fd - C).max() < 1e-7 * mat.E
    assert np.abs(C - C.transpose(0, 2, 1)).max() > 0.05 * mat.E


def test_psi_zero_loses_ellipticity_where_associated_flow_does_not():
    # Acoustic tensor of the algorithmic tangent at yielding points of the slope material:
    # associated flow stays on the border (min det Q = 0), psi = 0 is past it at most shear
    # points (Vermeer & de Borst 1984): no unique rate solution there, whatever the solver.
    elastic, _ = MATERIALS["mc_psi_zero"]
    sig_tr = _trial(100e3, n=2000, seed=11)
    dets = {}
    for psi in (None, 0.0):
        mat = MohrCoulomb(E=1e8, nu=0.3, cohesion=20e3, friction=30.0, dilation=psi)
        _, C, mode = rm.return_map(sig_tr, mat)
        dets[psi] = rm.acoustic_determinant(C[mode == rm.SHEAR]) / mat.E ** 2
    De = rm.elastic_tangent(elastic.E, elastic.nu)[None]
    assert rm.acoustic_determinant(De)[0] > 0.1 * elastic.E ** 2
    assert dets[None].min() > -1e-9 and np.median(dets[None]) < 1e-4
    assert np.mean(dets[0.0] < -1e-4) > 0.5 and dets[0.0].min() < -0.01


def test_tresca_return_matches_the_closed_form():
    # phi = 0: radial return of the in-plane deviator when zz is the intermediate stress.
    mat = MohrCoulomb(E=1e9, nu=0.3, cohesion=1e6, friction=0.0)
    sig_tr = np.array([[-10e6, -2e6, -6e6, 0.0]])
    sig, _, mode = rm.return_map(sig_tr, mat)
    assert mode[0] == rm.SHEAR
    np.testing.assert_allclose(sig[0], [-7e6, -5e6, -6e6, 0.0], atol=1e-3)


def test_hoek_brown_beyond_the_apex_returns_to_the_apex():
    mat = HoekBrown(E=5e9, nu=0.25, sci=50e6, mb=1.0, s=0.01, a=0.5)
    st = mat.tensile_strength
    sig, C, mode = rm.return_map(np.array([[5 * st, 5 * st, 5 * st, 0.0]]), mat)
    np.testing.assert_allclose(sig[0], [st, st, st, 0.0], rtol=1e-9)
    assert mode[0] == rm.TENSION and np.abs(C).max() == 0.0


def test_bad_material_input_is_rejected():
    with pytest.raises(ValueError, match="friction"):
        MohrCoulomb(E=1e9, nu=0.3, cohesion=1e6, friction=95.0)
    with pytest.raises(ValueError, match="nu"):
        MohrCoulomb(E=1e9, nu=0.5, cohesion=1e6, friction=30.0)
    with pytest.raises(ValueError, match="cohesion"):
        MohrCoulomb(E=1e9, nu=0.3, cohesion=float("nan"), friction=30.0)
