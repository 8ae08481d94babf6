"""The quick ``checkerboard`` variant end to end (a 550 m window around the highway cut, 6 m
flaws near it, UCS 76, 50 and 30 MPa, the support pair, the weathering boundary, the conventional
model, the continuum at 20 m elements; about 80 s on 2 cores).

Asserted where the quick model shows the thesis's findings, strict xfail where it does not
(measured reasons in docs/cases/checkerboard.md); no band is tuned to a measurement, each
is the thesis's claim itself (larger / smaller, fails / stands):

- support reduces the cut's displacement: the crest's displacement from the equilibrium at
  high strength through the weathered strength and the support schedule (T 0.8 -> 0.5 ->
  0.2 -> 0.1 MPa at UCS 30) with cables is below that without; the thesis's "the supported
  slope stands where the unsupported fails" is a strict xfail (both stand);
- the flaw strength fed to the model follows Hoek-Brown: lower UCS, lower c and friction, and
  a Hoek-Brown tensile strength of the order the thesis quotes (9-20 kPa; Table 7.2's
  weathered units 16-22 kPa; band 5-40 kPa: a factor 2 around those, the GSI/mi rounding);
- the continuum's factor of safety falls with UCS (same Hoek-Brown masses, weaker at 30);
- every UCS fails inside the schedule (on two of three seeds: one window's verdict is near a
  bifurcation); Table 7.4's trend, T at failure higher at UCS 50 and 30
  than at 76 MPa, is a strict xfail: with 20,000 (and 40,000) steps a level all three fail at
  the same level, 1.0 MPa (with 5,000 the trend appeared, a step-budget artefact: docs);
- Table 7.4's magnitude (strict xfail): T at failure 0.025 MPa at UCS 76;
- weathering: the displaced boundary fractures more than the strength loss; only the cut
  moving on after the release is a strict xfail.
"""
import pytest

from comparisons import checkerboard
from comparisons.variants import STAGED_OPTIONAL, pick_variant


@pytest.fixture(scope="module")
def quick():
    return checkerboard.run("quick", seed=1)


def test_support_reduces_the_crest_displacement(quick):
    """Thesis 7.8: cables and shotcrete (Table 7.5) hold the weathered cut; here both runs
    stand, so the comparison is the crest's movement with and without support."""
    sup = quick.methods["dem"]["support"]
    assert sup["supported"]["crest_displacement_m"] < sup["unsupported"]["crest_displacement_m"]


def test_flaw_strength_follows_hoek_brown(quick):
    rows = {r["ucs_MPa"]: r for r in quick.methods["dem"]["back_analysis"]}
    assert rows[30.0]["c_MPa"] < rows[76.0]["c_MPa"]
    assert rows[30.0]["friction"] < rows[76.0]["friction"]
    for r in rows.values():
        assert 5.0 < r["hoek_brown_t_kPa"] < 40.0


def test_continuum_factor_of_safety_falls_with_ucs(quick):
    fos = {r["ucs_MPa"]: r["factor_of_safety"] for r in quick.methods["continuum"]["rows"]}
    assert fos[30.0] < fos[76.0]


def test_the_window_stands_at_t_equal_to_c_before_t_is_lowered(quick):
    """A back-analysis lowers T from c on a slope that holds at c: the quick window breaks
    under a tenth of its bonds before the schedule, and the case adds no warning note (the
    full variant's 1.3 m flaws break 35-57 % and get one: docs/cases/checkerboard.md)."""
    for r in quick.methods["dem"]["back_analysis"]:
        assert r["cracks_before_search"] < checkerboard.BROKEN_BEFORE * r["contacts"]
    assert not [n for n in quick.notes if "before T was lowered" in n]


def _t_failure_of_seed(seed):
    """{UCS MPa: T at failure MPa or None} of the quick's back-analysis members at ``seed``."""
    _, v = pick_variant("checkerboard", checkerboard.VARIANTS, "quick",
                        optional=STAGED_OPTIONAL)
    out = {}
    for m in checkerboard.members(v, seed):
        if m["kind"] == "back" and not m["params"].get("conventional"):
            r = checkerboard.run_member(m)
            out[r["ucs"] / 1e6] = checkerboard._t_failure(r)[1]
    return out


def test_every_ucs_fails_as_t_is_lowered(quick):
    """Thesis 7.7.1: lowering the weathered gneiss's T fails the cut at each UCS of Table 7.4
    (a T at failure exists inside the schedule, 1.5 ... 0 MPa), on at least two of three
    tessellation seeds. The verdict of one window is near a bifurcation: with the interfaces
    divided (the default since 2026-12-02), seed 1 at UCS 30 MPa fails at 1.0 MPa on an AMD
    EPYC host and on an Intel Xeon host comes to rest after each level down to T = 0 with its
    crest 1 m out; seeds 2 and 3 fail at 1.5 MPa (docs/cases/checkerboard.md)."""
    seeds = [{r["ucs_MPa"]: r["t_failure_MPa"] for r in quick.methods["dem"]["back_analysis"]},
             _t_failure_of_seed(2), _t_failure_of_seed(3)]
    for ucs in seeds[0]:
        fails = [s[ucs] is not None for s in seeds]
        assert sum(fails) >= 2, (ucs, [s[ucs] for s in seeds])


@pytest.mark.xfail(strict=True, reason="measured (2026-11-30, every solve of the quick now "
                   "ends in equilibrium, kinetic_adaptive): T at failure is 1.0 MPa at UCS 76, "
                   "50 and 30 alike, every solve settling in 2,800-8,100 steps, as on the "
                   "Intel host before. The 0.65 MPa at UCS 76 of the AMD host (the trend) was a budget "
                   "answer: every solve then ended still moving at its cap (docs/history.md, "
                   "'Kinetic damping that stopped too late'; docs/cases/checkerboard.md)")
def test_t_at_failure_rises_as_ucs_falls(quick):
    """Table 7.4's trend: the slope fails at a higher T when UCS (so c and friction) is lower
    than the weathered gneiss's own 76 MPa."""
    rows = {r["ucs_MPa"]: r["t_failure_MPa"] for r in quick.methods["dem"]["back_analysis"]}
    assert rows[50.0] > rows[76.0] and rows[30.0] > rows[76.0]


@pytest.mark.xfail(strict=True, reason="measured: T at failure 1.0 MPa at UCS 76 (quick), 40 x "
                   "the thesis's: rigid Voronoi blocks carry tension under their own weight "
                   "(1 % of contacts beyond 0.2 sv, 0.3 MPa at the weathered zone's base; "
                   "benchmarks/gravity_box.py) and at the joints' ends and the toe, so a T of "
                   "tens of kPa cracks the cut (docs/cases/checkerboard.md, 'Why 1.3 m flaws')")
def test_t_at_failure_is_the_thesis_magnitude(quick):
    """Table 7.4: at the weathered gneiss's own UCS (76 MPa) the cut fails at T = 0.025 MPa,
    near the Hoek-Brown tensile strength; asserted within a factor of 2."""
    rows = {r["ucs_MPa"]: r["t_failure_MPa"] for r in quick.methods["dem"]["back_analysis"]}
    assert rows[76.0] is not None and 0.0125 <= rows[76.0] <= 0.05


@pytest.mark.xfail(strict=False, reason="host-dependent (2026-11-30): on one AMD EPYC host "
                   "the quick slope without support also stands at T 0.5, 0.2, 0.1 MPa (UCS 30), "
                   "every level in equilibrium; on another (same code, another kernel build) it "
                   "fails at 0.2 MPa at 1x and 2x the steps, under both judges, while the "
                   "supported one stands: round-off decides it, so it is neither a finding nor "
                   "a strict expectation; with rounded corners (2026-12-02) the unsupported "
                   "slope stands to 0.1 MPa on the Intel host too (docs/cases/checkerboard.md)")
def test_unsupported_slope_fails_supported_stands(quick):
    """Thesis 7.8: at UCS 30 with T lowered 0.8 -> 0.5 -> 0.2 -> 0.1 MPa the slope with cables
    and shotcrete stands, the one without fails."""
    sup = quick.methods["dem"]["support"]
    assert sup["supported"]["t_failure_MPa"] is None
    assert sup["unsupported"]["t_failure_MPa"] is not None


def test_weathering_boundary_fractures_more_than_strength_loss(quick):
    """Thesis 7.7.2: the constant-velocity boundary (1.85 m) fractures the weathered rock more
    than the tensile-strength degradation at the same UCS (76 MPa) does."""
    dem = quick.methods["dem"]
    weathering = dem["weathering"]
    assert weathering["displace_verdict"] == "displaced"
    back76 = next(r for r in dem["back_analysis"] if r["ucs_MPa"] == 76.0)
    assert weathering["cracks"] > back76["cracks"]


@pytest.mark.xfail(strict=True, reason="measured: after the release the displaced skin itself "
                   "moves on most (slope point 0.46 m, crest 0.13 m, face 0.04 m): its "
                   "momentum, not a failure of the cut alone")
def test_after_release_only_the_cut_moves_on(quick):
    """Thesis 7.7.2: after the displacement boundary is freed only the part at the highway cut
    fails; the rest comes to rest. Asserted as: the cut's crest moves more after the release
    than the point on the natural slope."""
    after = quick.methods["dem"]["weathering"]["after_release_m"]
    assert after["crest"] > after["slope"]


def test_conventional_model_does_not_fracture(quick):
    """Unbreakable flaws: the conventional model has no cracks through intact rock and no T
    at failure (only the joints and the fault could slip, and they hold)."""
    conv = quick.methods["conventional"]
    assert conv["cracks"] == 0 and conv["t_failure_MPa"] is None


def test_scene_round_trips_and_bad_params_are_refused(tmp_path):
    from comparisons.scenes import checkerboard as cb
    from dem_core.workflow.scene import Scene

    p = cb.CheckerboardParams(**checkerboard.VARIANTS["quick"]["params"])
    sc = cb.scene(p, checkerboard.member_stages("supported", p, checkerboard.VARIANTS["quick"]))
    sc.save(tmp_path / "checkerboard.json")
    assert Scene.load(tmp_path / "checkerboard.json").to_dict() == sc.to_dict()
    for bad, word in ((dict(edge_length=-1.0), "edge_length"), (dict(natural_slope=60.0),
                      "natural_slope"), (dict(window=(3690.0, 700.0)), "window"),
                      (dict(ucs=float("nan")), "ucs")):
        with pytest.raises(ValueError, match=word):
            cb.CheckerboardParams(**bad)


def test_a_run_that_failed_before_its_schedule_fails_at_the_t_it_started_with():
    from comparisons import staged
    from comparisons.scenes import checkerboard as cb

    params = dict(checkerboard.VARIANTS["quick"]["params"], ucs=50e6)
    c = cb.flaw_strength("weathered_gneiss", 50e6)[0]
    early = {"params": params, "search": None,
             "stages": [{"kind": "solve", "verdict": "stable"},
                        {"kind": "strength", "verdict": "failed"}]}
    assert staged.stopped_before_search(early) == {
        "stage": 1, "kind": "strength", "verdict": "failed"}
    assert checkerboard._t_failure(early) == (None, pytest.approx(c / 1e6, rel=1e-12))
    with_t = dict(early, params=dict(params, tensile=0.8e6))
    assert checkerboard._t_failure(with_t)[1] == pytest.approx(0.8)
    ran = dict(early, search={"last_stable": 0.5e6, "failure": 0.2e6})
    assert staged.stopped_before_search(ran) is None
    assert checkerboard._t_failure(ran) == (pytest.approx(0.5), pytest.approx(0.2))
