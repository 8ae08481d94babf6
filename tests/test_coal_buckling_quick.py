"""The quick ``coal_buckling`` variant end to end (1.75 m Voronoi cells, two across the 3.5 m
layer; T lowered 25 -> 20 -> 15 -> 10 -> 0 kPa, then the cohesion at T = 0; the continuum's
strength reduction; about 45 s on 2 cores), the scene as data and its input checks.

Bands (derived, not fitted): the thesis lowered T from 30 kPa and the layer buckled at 10 kPa
at the lower third of the face; with this variant's 5 kPa steps the finding reads "stands at
25, 20 and 15 kPa, first fails at 10 kPa (or 0, one step on)", the buckle "largest outward
movement at 0-1/3 of the height above the toe".
"""
import pytest

from dem_core.workflow.stages import STOPS

from comparisons import coal_buckling
from comparisons.scenes import coal_buckling as scene
from dem_core.workflow.scene import Scene


@pytest.fixture(scope="module")
def quick():
    return coal_buckling.run("quick", seed=1)


def test_layer_stands_at_the_table_strength_and_above_10_kPa(quick):
    """Stands after gravity at T = 30 kPa and at 25, 20, 15 kPa (the thesis's layer stood
    until T reached 10 kPa)."""
    dem = quick.methods["dem"]
    table_solve, = [s for s in dem["stages"] if s[0] == "solve"]
    assert table_solve[1] not in STOPS
    assert dem["T_levels_kPa"][:3] == [25.0, 20.0, 15.0]
    assert not set(STOPS) & set(dem["T_verdicts"][:3])


@pytest.mark.xfail(strict=True, reason="measured (quick 0.7 m and full 0.5 m cells, "
                   "2026-11-25; again 2026-12-01 on edge elements, rounded corners and "
                   "deformable blocks): the layer stands at T = 0 and even at T = 0 and "
                   "cohesion 0: its thrust, the free slab's, runs along its middle (|e| < "
                   "0.12 t), so no cut opens and the flaws' strength carries nothing; with "
                   "the basal friction 0 (2.7 x the thrust) it stands too. A buckle needs a "
                   "toe or layer shape fig 5.11a does not give (docs/cases/coal_buckling.md, "
                   "'Why the layer stands')")
def test_buckles_when_T_reaches_10_kPa_in_the_lower_third(quick):
    dem = quick.methods["dem"]
    assert dem["T_failure_kPa"] in (10.0, 0.0)
    assert dem["buckle"]["height_fraction"] <= 1.0 / 3.0


def test_the_layer_hands_the_free_slabs_thrust_to_the_toe_along_its_middle(quick):
    """Limit equilibrium of a slab on its basal plane at its friction limit: the thrust at
    the toe is gamma t L (sin 30 - cos 30 tan 20) = 2.38 MN/m (L the face's 150 m); the DEM's,
    read across a cut at the toe at the end of the run (T = 0, c = 0), within 5 % (measured
    +1.1 %). Its line of action stays within the kern (|e| < t / 6) along the exposed layer
    (measured 0.10 t near the crest, 0.05 t below; 0.04 t on end springs): every cut is
    compressed across its whole thickness."""
    toe_n, slab_n, e_max = coal_buckling.thrust_at_toe(quick.methods["dem"]["thrust"])
    assert slab_n == pytest.approx(2500 * 9.81 * 3.5 * 150.0 * 0.184793, rel=1e-4)
    assert toe_n == pytest.approx(slab_n, rel=0.05)
    assert e_max < 1.0 / 6.0
    assert "thrust_line" in quick.figures


def test_continuum_welded_layer_stands_at_T_0(quick):
    """With the basal plane welded the layer is part of a 30 degree slope of c 0.3 MPa,
    friction 25 (T 0): tan 25 / tan 30 = 0.81 from friction alone on the steepest plane and
    c / (gamma H) = 0.16, several times Taylor's critical value for a 30 degree slope at
    friction 25 (about 0.01): F above 1.5 by a wide margin."""
    assert quick.methods["continuum"]["last_converged"] > 1.5


def test_scene_round_trips(tmp_path):
    p = scene.CoalBucklingParams(edge_length=1.75)
    sc = scene.scene(p, coal_buckling.stages(p, coal_buckling.VARIANTS["quick"]))
    sc.save(tmp_path / "coal.json")
    assert Scene.load(tmp_path / "coal.json").to_dict() == sc.to_dict()


def test_regions_tile_the_section():
    p = scene.CoalBucklingParams()
    from shapely.geometry import Polygon
    area = sum(Polygon(r.exterior).area for r in scene.regions(p))
    assert area == pytest.approx(scene.slope_region(p).polygon().area, rel=1e-9)


@pytest.mark.parametrize("bad", [dict(layer_thickness=0.0), dict(basal_friction=95.0),
                                 dict(layer_thickness=8.0), dict(density=-1.0),
                                 dict(edge_length=float("inf"))])
def test_bad_params_raise(bad):
    name = next(iter(bad))
    with pytest.raises(ValueError, match=name):
        scene.CoalBucklingParams(**bad)
