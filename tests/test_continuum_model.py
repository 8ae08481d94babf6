"""DOLFINx continuum model against closed forms: elastic column, Prandtl footing, biaxial
Mohr-Coulomb / Hoek-Brown specimens, vertical cut (critical g and SSR), staged excavation,
and the shared-geometry mesh area.

Meshes are moderate so that the whole file runs in well under two minutes (the DOLFINx JIT
compiles each form once per machine and caches it).
"""
import math
from types import SimpleNamespace

import numpy as np
import pytest

pytest.importorskip("dolfinx")

from continuum_ref import return_mapping as rm  # noqa: E402
from continuum_ref import ssr  # noqa: E402
from continuum_ref.materials import Elastic, HoekBrown, MohrCoulomb  # noqa: E402
from continuum_ref.mesh import (PolygonRegion, WeakBand, build_mesh,  # noqa: E402
                                mesh_from_geometry, refine_near)
from continuum_ref.model import ContinuumModel  # noqa: E402


def _rectangle(w, h, x0=0.0, y0=0.0):
    return [(x0, y0), (x0 + w, y0), (x0 + w, y0 + h), (x0, y0 + h)]


def test_elastic_column_under_gravity_matches_closed_form():
    # Laterally confined column (rollers on the sides, fixed base): uniaxial strain,
    # sigma_yy = -rho g n (H - y), settlement of the top = rho g n H^2 / (2 M), M = lambda + 2G.
    W, H, rho, n = 1.0, 10.0, 2500.0, 3.0
    mat = Elastic(E=2e9, nu=0.25)
    md = build_mesh([PolygonRegion("rock", _rectangle(W, H))], h=1.0, points={"top": (0.5, H)})
    model = ContinuumModel(md, mat, rho)
    model.fix(lambda x: np.isclose(x[1], 0.0), (0, 1))
    model.fix(lambda x: np.isclose(x[0], 0.0) | np.isclose(x[0], W), (0,))
    result = model.solve_gravity(n)
    assert result.converged
    lam, G = mat.E * mat.nu / ((1 + mat.nu) * (1 - 2 * mat.nu)), mat.E / (2 * (1 + mat.nu))
    gamma = rho * 9.81 * n
    settlement = -model.displacement_at(["top"])[0, 1]
    assert settlement == pytest.approx(gamma * H ** 2 / (2 * (lam + 2 * G)), rel=1e-2)
    assert result.displacement["top"][1] == pytest.approx(-settlement)
    y = model.cell_average(model._qp_xy)[:, 1]
    s = model.stress()
    assert np.max(np.abs(s[:, 1] + gamma * (H - y))) < 1e-2 * gamma * H
    assert np.max(np.abs(s[:, 0] - mat.nu / (1 - mat.nu) * s[:, 1])) < 1e-2 * gamma * H
    assert model.reaction(lambda x: np.isclose(x[1], 0.0), 1) == pytest.approx(gamma * H * W,
                                                                               rel=1e-6)


@pytest.fixture(scope="module")
def footing():
    """Smooth rigid strip footing (half model, B = 1 m) pushed into weightless Tresca soil."""
    half, width, depth, c = 0.5, 3.0, 2.0, 1e4
    md = build_mesh([PolygonRegion("soil", [(0, -depth), (width, -depth), (width, 0),
                                             (half, 0), (0, 0)])], h=0.3,
                    size_field=refine_near([(half, 0.0)], 0.03, 0.3, 0.05, 1.0))
    mat = MohrCoulomb(E=1e7, nu=0.3, cohesion=c, friction=0.0)
    model = ContinuumModel(md, mat, 0.0)
    model.fix(lambda x: np.isclose(x[0], 0.0) | np.isclose(x[0], width), (0,))
    model.fix(lambda x: np.isclose(x[1], -depth), (0, 1))
    under = lambda x: np.isclose(x[1], 0.0) & (x[0] <= half + 1e-9)  # noqa: E731
    model.fix(under, (1,), value=(-0.02,))
    loads = []
    for k in range(1, 11):
        assert model.solve_load(0.1 * k).converged
        loads.append(-model.reaction(under, 1) / half / c)
    return SimpleNamespace(model=model, mat=mat, loads=np.array(loads))


def test_footing_collapse_load_is_prandtl(footing):
    prandtl = 2.0 + math.pi
    assert footing.loads[-1] == pytest.approx(prandtl, rel=0.05)
    assert abs(footing.loads[-1] - footing.loads[-2]) < 0.01 * prandtl    # a plateau
    assert footing.loads[0] < 0.8 * prandtl                               # starts elastic


def test_footing_stresses_are_on_the_yield_surface(footing):
    model, mat = footing.model, footing.mat
    eig, _ = rm.principal_decomposition(model.sig_n)
    f = rm.yield_function(-np.sort(eig, axis=1), mat)
    plastic = model.mode > 0
    assert plastic.sum() > 50
    assert np.max(f) < 1e-8 * mat.cohesion
    assert np.max(np.abs(f[plastic])) < 1e-8 * mat.cohesion
    indicator = model.yield_indicator()
    assert indicator["shear"].max() == 1.0 and indicator["tension"].max() == 0.0
    from continuum_ref.plot import plot_yield
    ax = plot_yield(model)
    assert len(ax.collections) == 1


@pytest.mark.parametrize("law", ["mohr_coulomb", "hoek_brown"])
def test_confined_specimen_peak_matches_the_criterion(law):
    # Plane-strain biaxial test, smooth platens: confining traction p on the right side,
    # prescribed shortening on top. Homogeneous stress, so the peak vertical stress is the
    # criterion's sigma1 at sigma3 = p.
    p = 2e6
    if law == "mohr_coulomb":
        mat = MohrCoulomb(E=5e9, nu=0.25, cohesion=3e6, friction=35.0, dilation=10.0)
        kp = (1 + math.sin(math.radians(35))) / (1 - math.sin(math.radians(35)))
        peak = 2 * 3e6 * math.sqrt(kp) + kp * p
    else:
        mat = HoekBrown.from_gsi(60.0, 12.0, 60e6, E=5e9, nu=0.25)
        peak = p + mat.sci * (mat.mb * p / mat.sci + mat.s) ** mat.a
    md = build_mesh([PolygonRegion("specimen", _rectangle(0.05, 0.1))], h=0.025)
    model = ContinuumModel(md, mat, 0.0)
    top = lambda x: np.isclose(x[1], 0.1)  # noqa: E731
    model.fix(lambda x: np.isclose(x[1], 0.0), (1,))
    model.fix(lambda x: np.isclose(x[0], 0.0), (0,))
    model.fix(top, (1,), value=(-3 * peak / mat.E * 0.1,))
    model.add_traction(lambda x: np.isclose(x[0], 0.05), (-p, 0.0))
    # Confinement and shortening grow together; at load scale 1 the confinement is p and the
    # specimen has yielded (shortening 3x the elastic strain at peak), so it sits at the peak.
    assert model.solve_load(1.0, first_step=0.25).converged
    stress = -model.reaction(top, 1) / 0.05
    assert stress == pytest.approx(peak, rel=1e-6)
    assert model.yield_indicator(ever=False)["shear"].min() == 1.0


@pytest.fixture(scope="module")
def vertical_cut():
    """Undrained (Tresca) vertical cut of height H = 1 m; gamma H / c = 1 at 1 g."""
    c = 1e4
    md = build_mesh([PolygonRegion("soil", [(0, 0), (4, 0), (4, 1), (2, 1), (2, 2), (0, 2)])],
                    h=0.3, size_field=refine_near([(2, 1), (2, 2)], 0.06, 0.3, 0.1, 1.2),
                    points={"crest": (2.0, 2.0)})
    mat = MohrCoulomb(E=1e7, nu=0.3, cohesion=c, friction=0.0)
    model = ContinuumModel(md, {"soil": mat}, c / 9.81)
    model.fix(lambda x: np.isclose(x[1], 0.0), (0, 1))
    model.fix(lambda x: np.isclose(x[0], 0.0) | np.isclose(x[0], 4.0), (0,))
    assert model.solve_gravity(1.0).converged
    return model, mat


def test_vertical_cut_critical_g_and_strength_reduction_agree(vertical_cut):
    # Stability number of a vertical cut in Tresca soil: 3.772 <= gamma H / c <= 3.786
    # (Pastor et al. 2000 bounds). With phi = 0 the critical g at 1 g weight equals the SSR
    # factor of safety at 1 g, so the two searches must agree.
    model, mat = vertical_cut
    start = model.save_state()
    crit = ssr.critical_g(model, g_max=6.0, first_step=0.5, tol=0.02)
    assert crit.found
    assert 3.772 * 0.99 < crit.value < 3.786 * 1.06
    assert crit.first_failed - crit.value < 2 * 0.02      # bracket narrower than 2 tol
    model.restore_state(start)
    fos = ssr.factor_of_safety(model, [mat], f_max=6.0, first_step=0.5, tol=0.02)
    assert fos.found
    assert fos.value == pytest.approx(crit.value, abs=0.05)
    assert model.history["crest"] and fos.history[-1][1] > fos.history[0][1]


def test_staged_excavation_equals_the_final_geometry_when_elastic():
    # Linear elasticity is path independent: gravity, then removing a block, gives the stress
    # of the final geometry loaded directly (up to the soft void's stiffness).
    rock = [(0, 0), (6, 0), (6, 4), (0, 4)]
    cut = _rectangle(2.0, 1.5, x0=4.0, y0=2.5)
    md = build_mesh([PolygonRegion("rock", rock)], h=0.4, groups={"stage1": cut},
                    points={"toe": (4.0, 2.5), "crest": (3.0, 4.0)})
    mat = Elastic(E=1e9, nu=0.3)

    def run(model):
        model.fix(lambda x: np.isclose(x[1], 0.0), (0, 1))
        model.fix(lambda x: np.isclose(x[0], 0.0) | np.isclose(x[0], 6.0), (0,))
        return model
    staged = run(ContinuumModel(md, mat, 2600.0))
    assert staged.solve_gravity(1.0).converged
    result = staged.excavate("stage1")
    assert result.converged
    assert result.displacement["toe"][1] > 1e-7          # the floor heaves after unloading
    void = Elastic(E=1e9 * 1e-6, nu=0.3)
    direct = run(ContinuumModel(md, {"rock": mat, "stage1": void}, {"rock": 2600.0,
                                                                    "stage1": 0.0}))
    assert direct.solve_gravity(1.0).converged
    keep = np.setdiff1d(np.arange(len(staged._cells)), md.cells("stage1"))
    scale = 2600.0 * 9.81 * 4.0
    assert np.max(np.abs(staged.stress()[keep] - direct.stress()[keep])) < 1e-4 * scale


def test_slope_described_once_meshes_to_its_area():
    # A GeometrySpec-like object (duck-typed as dem_core.geometry will provide).
    H, face = 0.33, 61.0
    toe, crest = 0.1, 0.1 + H / math.tan(math.radians(face))
    exterior = [(0, 0), (0.4, 0), (0.4, 0.395), (crest, 0.395), (toe, 0.395 - H), (0, 0.395 - H)]
    region = SimpleNamespace(name="rock", exterior=exterior, holes=[[(0.3, 0.1), (0.35, 0.1),
                                                                     (0.35, 0.15)]], groups=())
    spec = SimpleNamespace(regions=[region],
                           groups={"toe_zone": _rectangle(0.1, 0.05, x0=0.08, y0=0.05)})
    md = mesh_from_geometry(spec, h=0.03, weak_bands=[WeakBand("fault", [(0.05, 0.0),
                                                                         (0.38, 0.395)], 0.004)],
                            points={"A": (crest, 0.395), "B": (0.2, 0.2)})
    expected = (0.4 * 0.395 - 0.5 * (crest - toe) * H - toe * H) - 0.5 * 0.05 * 0.05
    assert md.area == pytest.approx(expected, rel=1e-12)
    assert abs(md.mesh_area() - md.area) < 1e-6 * md.area
    cells = {name: len(md.cells(name)) for name in ("rock", "toe_zone", "fault")}
    assert all(n > 0 for n in cells.values())
    assert cells["rock"] == md.mesh.topology.index_map(2).size_local
    with pytest.raises(KeyError, match="nope"):
        md.cells("nope")


def test_dem_core_geometry_spec_meshes_to_its_area():
    geometry = pytest.importorskip("dem_core.geometry")
    spec = geometry.GeometrySpec(
        regions=[geometry.Region("rock", [(0, 0), (2, 0), (2, 1), (1, 1), (0, 0.5)],
                                 groups=["stage0"]),
                 geometry.Region("cap", [(0, 0.5), (1, 1), (0, 1)])],
        groups={"toe": _rectangle(0.3, 0.2, x0=1.0, y0=0.1)})
    md = mesh_from_geometry(spec, h=0.1)
    assert abs(md.mesh_area() - 2.0 * 1.0) < 1e-6 * 2.0
    assert md.tags["stage0"] == md.tags["rock"] and md.tags["toe"]


def test_bad_geometry_and_points_are_rejected():
    with pytest.raises(ValueError, match="bow"):
        build_mesh([PolygonRegion("bow", [(0, 0), (1, 1), (1, 0), (0, 1)])], h=0.1)
    with pytest.raises(ValueError, match="P"):
        build_mesh([PolygonRegion("sq", _rectangle(1, 1))], h=0.5, points={"P": (2.0, 2.0)})


def test_one_slope_gives_a_block_system_and_a_mesh_of_the_same_area():
    """The shared-geometry path: the Adhikary slope (joints and Voronoi flaws for the DEM) and
    its DOLFINx mesh cover the same area (relative difference < 1e-6)."""
    from comparisons.scenes import adhikary as scene
    from dem_core.geometry import build_block_system

    spec = scene.geometry(scene.AdhikaryParams(edge_length=0.01, relax_iterations=2))
    blocks = build_block_system(spec)
    md = mesh_from_geometry(spec, h=0.02)
    assert md.mesh_area() == pytest.approx(blocks.area.sum(), rel=1e-6)
