"""The quick ``underdip`` variant end to end (1.5 m Voronoi bricks in 0.75 m beds, T lowered
40 -> 20 -> 10 -> 0 kPa, then the cohesion at T = 0 halved from 300 kPa; the continuum's
strength reduction; about 25 s on 2 cores), the scene as data and its input checks.

Bands (derived, not fitted): the thesis's slope stood under gravity at T = 60 kPa and through
the schedule until it collapsed at 10 kPa; with this variant's schedule (20 kPa steps, then
10 kPa) the thesis's finding reads "stands at 40 and 20 kPa, first fails at 10 or 0 kPa". The
toppled zone "in the order of 15 m" is read as 10-20 m (one third either way), its start "at
the toe" as a failed mass that reaches into the lowest third of the face.
"""
import pytest

from dem_core.workflow.stages import STOPS

from comparisons import underdip
from comparisons.scenes import underdip as scene
from dem_core.workflow.scene import Scene


@pytest.fixture(scope="module")
def quick():
    return underdip.run("quick", seed=1)


def test_slope_stands_at_the_table_strength_and_above_the_thesis_collapse(quick):
    """Stands at T = 60 kPa after gravity and at T = 40 and 20 kPa (the thesis's slope stood
    above its 10 kPa collapse)."""
    dem = quick.methods["dem"]
    table_solve, = [s for s in dem["stages"] if s[0] == "solve"]
    assert table_solve[1] not in STOPS
    assert dem["T_levels_kPa"][:2] == [40.0, 20.0]
    assert not set(STOPS) & set(dem["T_verdicts"][:2])


@pytest.mark.xfail(strict=True, reason="measured: the slope stands at T = 0 (quick and full, "
                   "2026-11-25): with their cohesion (0.6 MPa) the flaws carry the compressive "
                   "gravity load; lowering T breaks only the flaws in tension")
def test_collapse_when_T_is_lowered_to_10_kPa(quick):
    assert quick.methods["dem"]["T_failure_kPa"] in (10.0, 0.0)


def test_lowering_the_cohesion_at_T_0_fails_the_slope(quick):
    """Not in the thesis: a mechanism exists within the zone of flaws; the slope fails at a
    cohesion below the table's 600 kPa (and stood at 600 kPa with T = 0)."""
    c = quick.methods["dem"]["c_failure_kPa"]
    assert c is not None and 0.0 <= c < 600.0
    top = quick.methods["dem"]["toppled"]
    assert top is not None and top["blocks"] > 0


@pytest.mark.xfail(strict=True, reason="measured: the failed mass fills the zone of flaws: "
                   "17.5 m thick (95 %), deepest block 21.7 m behind the face in the 25 m zone "
                   "(quick, rounded corners; 19.9 / 22.0 m sharp); 28.2 m / 32.0 m in a 35 m "
                   "zone (full, sharp corners): the zone, not the mechanics, sets its thickness")
def test_toppled_zone_about_15_m_thick_inside_the_zone(quick):
    """The failed zone (of the cohesion schedule: T alone does not fail the slope) is 10-20 m
    thick, the thesis's "in the order of 15 m", and stays 5 m (several bricks) clear of the
    back of the zone of flaws (else the zone, not the rock, bounds it)."""
    top = quick.methods["dem"]["toppled"]
    assert top["max_depth_m"] < top["zone_depth_m"] - 5.0
    assert 10.0 <= top["thickness_m"] <= 20.0


def test_failed_mass_reaches_down_to_the_toe(quick):
    """The mass that fails under the cohesion schedule reaches down into the lowest third of
    the face (the thesis: toppling starts at the toe). Measured 0.17 H (rounded corners;
    sharp: 0.09 H, and 0.11-0.14 H with the density changed by 1 ULP). Where the *fastest*
    block lies is not asserted: it is chaotic (0.38 H, and 0.78 H with the density 1 ULP
    higher; 0.78 H with rounded corners; docs/cases/underdip.md)."""
    assert quick.methods["dem"]["toppled"]["lowest_height_fraction"] <= 1.0 / 3.0


def test_continuum_intact_mass_stands_at_T_0(quick):
    """The equivalent mass (c 0.6 MPa, friction 30, T 0) on a 75 m, 61 degree slope has the
    stability number c / (gamma H) = 0.6e6 / (24.5e3 x 75) = 0.33, about three times Taylor's
    critical value for friction 30 and a 60 degree slope (about 0.1): F about 3, above 1.5 even
    with the tension cut-off; so the search must converge well past F = 1.5."""
    cont = quick.methods["continuum"]
    assert cont["last_converged"] > 1.5


def test_scene_round_trips(tmp_path):
    p = scene.UnderdipParams(edge_length=3.0)
    sc = scene.scene(p, underdip.stages(p, underdip.VARIANTS["quick"]))
    sc.save(tmp_path / "underdip.json")
    assert Scene.load(tmp_path / "underdip.json").to_dict() == sc.to_dict()


@pytest.mark.parametrize("bad", [dict(bed_spacing=0.0), dict(jitter=1.0),
                                 dict(flaw_friction=90.0), dict(zone_depth=50.0),
                                 dict(kn=float("nan"))])
def test_bad_params_raise(bad):
    name = next(iter(bad))
    with pytest.raises(ValueError, match=name):
        scene.UnderdipParams(**bad)
