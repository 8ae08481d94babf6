"""The quick ``common_toppling`` variant end to end (6 m layers, 3 m flaws in a 24 m zone,
about 970 blocks; six DEM runs and the continuum): which of the thesis's findings (5.2.2) it
shows, and strict xfails, with the measured reason, for those it does not. The numbers the
xfails quote: docs/cases/common_toppling.md."""
import math

import pytest

from comparisons import common_toppling as case
from comparisons.scenes import common_toppling as scene
from dem_core.workflow.scene import Scene


@pytest.fixture(scope="module")
def quick():
    return case.run("quick", seed=1)


def _failure(quick, name=None):
    dem = quick.methods["dem"]
    return dem["tensile_at_rupture_MPa"] if name is None else dem["studies"][name]["failure_MPa"]


def test_the_6m_model_ruptures_when_its_tensile_strength_is_lowered(quick):
    """The damage model forms a rupture somewhere on the schedule (10 MPa down to 0.25 MPa):
    the solve stops coming to equilibrium and a connected path of intact-rock cracks reaches
    the lower half of the face (``find_rupture``), over at least a quarter of the slope
    height."""
    assert _failure(quick) is not None
    rupture = quick.methods["dem"]["rupture"]
    assert rupture is not None and rupture["length_m"] >= case.RUPTURE_MIN * scene.SLOPE_HEIGHT


@pytest.mark.xfail(strict=True, reason="measured (quick, edge elements, 2026-12-01): the 6 m "
                   "model stands at T = 1.75 MPa and ruptures at 1.5 (end springs, the model "
                   "before: 0.5 / 0.25, their threefold bending strength); the rest of the gap "
                   "to 6.8-7 MPa is the assumed 120 m slope (fig 5.6's height is not given): "
                   "1.5 / 2.5 / 3.5 MPa at 120 / 150 / 165 m, and at 180 m it fails at T = "
                   "10 MPa (benchmarks/trials/common_toppling_height.py; docs/cases/"
                   "common_toppling.md, 'The slope height')")
def test_table_5_2_ruptures_the_6m_model_and_t_at_rupture_is_near_7_mpa(quick):
    """Thesis: with table 5.2 (T = 1 MPa) a rupture forms; 7 MPa holds, 6.8 ruptures. Band:
    the quick schedule's levels are 7, 4, 2, 1, ... MPa, so a critical T in [6.8, 7] makes the
    first failed level 4 MPa (or 7, one level early: the random cells)."""
    t = _failure(quick)
    assert t is not None and 4.0 <= t <= 7.0


@pytest.mark.parametrize("study", ["friction 50", "cohesion 15"])
def test_more_flaw_friction_or_cohesion_does_not_stop_the_rupture(quick, study):
    """Thesis: friction 30 -> 50 or cohesion 5 -> 15 MPa does not stop the rupture (tension
    controls it). On the same schedule of T the stronger model must still fail, at the base
    model's level or earlier (a higher T): the shear strength does not hold it longer."""
    base, stronger = _failure(quick), _failure(quick, study)
    assert base is not None and stronger is not None and stronger >= base - 1e-9


def test_conventional_model_never_ruptures(quick):
    """Unbreakable flaws (the conventional model without cross joints): no rupture can form,
    so the schedule runs down to its lowest T without a failure."""
    conv = quick.methods["conventional"]
    lowest = min(case.VARIANTS["quick"]["t_values"]) / 1e6
    assert conv["tensile_at_rupture_MPa"] is None and conv["lowest_tensile_MPa"] == lowest


def test_the_crest_moves_far_more_than_the_toe(quick):
    """Thesis fig 5.9: at rupture the top of the slope moves considerably more than the toe
    (columns rotating about their bases). Band: at least twice as far."""
    moved = quick.methods["dem"]["displacement_at_rupture_m"]
    assert moved["crest"] > 2.0 * moved["toe"]


def test_critical_height_rises_with_tensile_strength(quick):
    """Thesis fig 5.10: Hc rises with T. Quick: 6 m layers, table 5.3, T = 0.25 and 1 MPa; the
    weaker slope must stop standing during the excavation (else the test says nothing) and the
    stronger one later or not at all (None: all 12 lifts stood). Not standing is "failing" or
    "undecided" (the weaker slope creeps on after its last lift, ``critical_height``). The
    weaker one's failure must come with a rupture surface (``find_rupture``), so the trend is
    about toppling."""
    rows = {t: (h, k) for s, t, h, k in quick.methods["dem"]["critical_height"] if s == 6.0}
    (weak, with_rupture), (strong, _) = rows[0.25], rows[1.0]
    assert weak is not None and with_rupture        # a toppling rupture, not a lost block
    assert strong is None or strong > weak


def test_continuum_stands_at_full_height(quick):
    """The intact rock without joints (upper bound) stands the whole excavation with F > 1."""
    c = quick.methods["continuum"]
    assert c["failure_height_m"] is None and c["factor_of_safety"] > 1.0
    assert c["joints_everywhere_fos"] == pytest.approx(math.tan(math.radians(30)) /
                                                      math.tan(math.radians(60)))


def test_scene_round_trips_and_bad_params_are_refused(tmp_path):
    p = scene.ToppleParams(edge_length=3.0, zone_depth=24.0)
    sc = scene.scene(p, case.height_stages(p, case.VARIANTS["quick"]))
    sc.save(tmp_path / "s.json")
    assert Scene.load(tmp_path / "s.json").to_dict() == sc.to_dict()
    for bad in (dict(spacing=-1.0), dict(spacing=1.5, edge_length=3.0),
                dict(flaw_tensile_strength=1e9), dict(zone_depth=500.0), dict(joint_friction=95.0),
                dict(slope_height=float("nan"))):
        with pytest.raises(ValueError, match=next(iter(bad))):
            scene.ToppleParams(**bad)


@pytest.mark.parametrize("height", [120.0, 180.0])
def test_a_taller_slope_keeps_its_crest_and_its_lifts_fill_the_cut(height):
    """``slope_height`` (the sensitivity to fig 5.6's missing height): the crest stays at x =
    CREST_LENGTH, the 12 lifts are H / 12 high and exactly fill the rock in front of the final
    face, and the points lie 1 m inside the crest and toe."""
    from shapely.geometry import Polygon
    from shapely.ops import unary_union

    (tx, ty), (cx, cy) = scene.face(height)
    assert (cx, ty, cy) == (scene.CREST_LENGTH, scene.BASE, scene.BASE + height)
    assert tx == pytest.approx(cx + height / math.tan(math.radians(scene.FACE_DIP)))
    lifts = unary_union([scene.lift(k, height).polygon()
                         for k in range(1, scene.N_LIFTS + 1)])
    width = tx + scene.TOE_LENGTH
    cut = Polygon([(cx, cy), (width, cy), (width, ty), (tx, ty)])
    assert lifts.symmetric_difference(cut).area == pytest.approx(0.0, abs=1e-6)
    assert scene.height_after(scene.N_LIFTS, height) == pytest.approx(height)
    pts = scene.monitoring_points(height)
    assert pts["crest"] == (cx - 2.0, cy - 1.0) and pts["toe"] == (tx - 2.0, ty + 1.0)
