"""The quick ``lornex`` variant end to end (8 m flaws, the 15 mining blocks in 5 stages of 3,
each solve judged over windows of the response time; the DEM at T 0.1 and 1.0 MPa,
conventional, continuum at h = 15 m; about 65 s on 2 cores), and the scene's own checks.

What is asserted is the thesis's chapter-6 findings that the quick resolution can show
(Table 6.4's field record and the thesis's text, sections 6.8.1-6.8.4), with bands derived
from them, not from our numbers:

- displacement grows with mining (the field's cumulative record never decreases);
- T = 1.0 MPa cracks less and moves less than T = 0.1 MPa (6.8.4): fewer cracks, and less
  movement averaged over the four prisms at the same model time within the first mining
  solve that both runs fail (``lornex.equal_time``: a failing solve's end is where its judge
  stopped);
- the damage model moves more than the conventional model (flaws unbreakable) at the toe
  prism SMP 560 and fits the field better over all prisms (6.8.3, fig. 6.22);
- the movement mode (6.8.1): the crest drops (normal scarps), the mid-slope rotates forward
  (toppling), the toe heaves (bulging);
- the continuum (Hoek-Brown rock mass, no joints) moves less than the jointed DEM.

Not reproduced (strict xfail with the measured reason): the field's magnitude (12-16 m after
block 15) and the toe prism moving most.
"""
import json

import numpy as np
import pytest

from comparisons import lornex
from comparisons.scenes import lornex as scene
from dem_core.workflow.scene import Scene


@pytest.fixture(scope="module")
def quick():
    return lornex.run("quick", seed=1)


def _runs(quick):
    return {r["label"]: r for r in quick.methods["dem"]["runs"]}


def test_displacement_grows_with_mining(quick):
    """Every prism's cumulative displacement rises from stage to stage (1 mm tolerance: a
    cumulative magnitude may turn slightly) and ends above 10 x its first stage's (the field:
    0-1.5 m after block 3, 12-16 m after block 15)."""
    for run in _runs(quick).values():
        for k, vals in run["cumulative_m"].items():
            assert np.all(np.diff(vals) > -1e-3), (run["label"], k, vals)
            assert vals[-1] > 10.0 * vals[0], (run["label"], k, vals)


def test_higher_tensile_strength_cracks_less_and_moves_less(quick):
    """Thesis 6.8.4: T 1.0 MPa reduced the fracturing and the mining-induced displacement.
    Both runs fail from the fourth mining stage on, and a failing solve ends where its judge
    proved the mechanism (T = 1 MPa's took 262,500 steps, T = 0.1 MPa's 160,500), so their
    displacements at the solves' ends compare the judges' stopping times. They are compared
    at the same model time within the first solve neither ends at rest (``lornex.equal_time``:
    the mean over the four prisms), i.e. by the mechanisms' speeds (docs/cases/lornex.md)."""
    weak, strong = _runs(quick)["T=0.1 MPa"], _runs(quick)["T=1 MPa"]
    assert strong["cracks"] < weak["cracks"]
    same = quick.methods["dem"]["equal_time"]
    assert same is not None and same["time_s"] > 0
    moved = same["mean_m"]
    assert moved[strong["label"]] < moved[weak["label"]], same
    assert any(n.startswith("At the same model time") for n in quick.notes)


def test_damage_model_moves_more_and_fits_better_than_conventional(quick):
    """Thesis 6.8.3: at the toe prism SMP 560 the conventional model stays far below the field
    and the damage model does better (fig. 6.22); over all prisms its RMS error is smaller."""
    dem, conv = _runs(quick)["T=0.1 MPa"], quick.methods["conventional"]
    assert conv["cracks"] == 0
    assert dem["cumulative_m"]["SMP 560"][-1] > conv["cumulative_m"]["SMP 560"][-1]
    assert dem["rms"]["all"]["rms_m"] < conv["rms"]["all"]["rms_m"]


def test_movement_mode_crest_drops_mid_slope_topples_toe_heaves(quick):
    """Thesis 6.8.1: sliding at the crest (its blocks move down: normal scarps), toppling over
    the mid-slope (forward, clockwise rotation of its blocks: obsequent scarps), bulging at the
    toe (its blocks move up)."""
    mode = _runs(quick)["T=0.1 MPa"]["mode"]
    assert mode["crest"]["uy_m"] < 0.0
    assert mode["mid-slope"]["rotation_deg"] < 0.0
    assert mode["toe"]["uy_m"] > 0.0


def test_continuum_moves_less_than_the_jointed_dem(quick):
    """A Hoek-Brown rock mass without joints cannot slide on the faults nor topple: all its
    stages converge and its prisms move less than the conventional DEM's."""
    c, conv = quick.methods["continuum"], quick.methods["conventional"]
    assert all(s["converged"] for s in c["stages"])
    assert len(c["stages"]) == len(lornex.MERGED)
    for k in lornex.PRISMS:
        assert c["cumulative"][k][-1] < conv["cumulative_m"][k][-1], k


def test_errors_against_table_6_4_are_recorded(quick):
    for method in ("dem", "conventional", "continuum"):
        for k in lornex.PRISMS:
            name = f"{method} {k} cumulative displacement after block 15 (m)"
            assert quick.errors[name]["reference"] == lornex.TABLE_6_4[k][-1]


@pytest.mark.xfail(strict=True, reason="measured (quick, response judge, 2026-11-30): the "
                   "damage model's prisms move 3.3-6.0 m after block 15 against the field's "
                   "12.4-16.3 m; its last two mining solves are failing (a mechanism seen "
                   "twice; before, on the budget judge, every one ended at its cap with "
                   "1.5-2.4 m), so the number is where the mechanism was proven, not an "
                   "equilibrium; and the reconstructed section is not the thesis's")
def test_final_displacement_within_a_factor_two_of_the_field(quick):
    """The thesis calls its agreement with Table 6.4 good (figs. 6.18-6.22: within about a
    metre); a factor of 2 is a generous band for a reconstructed section."""
    run = _runs(quick)["T=0.1 MPa"]
    for k in lornex.PRISMS:
        ratio = run["cumulative_m"][k][-1] / lornex.TABLE_6_4[k][-1]
        assert 0.5 < ratio < 2.0, (k, ratio)


@pytest.mark.xfail(strict=True, reason="measured (quick, response judge, 2026-11-30): the "
                   "top prism (SMP 413, 5.7 m) moves most and the toe prism (SMP 560, 3.5 m) "
                   "least, as on the budget judge (2.4 / 1.5 m): the model's displacement grows "
                   "up the slope, the field's (and the thesis's fig. 6.20) is largest at the toe")
def test_toe_prism_moves_most(quick):
    """Table 6.4 after block 15: SMP 560 (the lowest prism) 16.3 m, the others 12.4-13.3 m."""
    final = {k: v[-1] for k, v in _runs(quick)["T=0.1 MPa"]["cumulative_m"].items()}
    assert max(final, key=final.get) == "SMP 560"


# ------------------------------------------------------------------ the scene (fast)
def test_scene_round_trips_through_json(tmp_path):
    sc = scene.scene(scene.LornexParams(edge_length=8.0, relax_iterations=2))
    sc.save(tmp_path / "lornex.json")
    back = Scene.load(tmp_path / "lornex.json")
    assert json.dumps(back.to_dict(), sort_keys=True) == json.dumps(sc.to_dict(), sort_keys=True)


def test_fifteen_mining_blocks_fill_the_space_in_front_of_the_final_face():
    """The blocks are disjoint and together the rock between the pre-mining and final
    surfaces: 6 lifts of 15 m in front of the 35 degree face, out to x = 400 m."""
    blocks = scene.mining_blocks()
    assert sorted(blocks) == list(range(1, 16))
    area = sum(b.area for b in blocks.values())
    h = scene.Y_PREMINING - scene.Y_TOE
    x_faces = scene.x_face(scene.Y_PREMINING) + scene.x_face(scene.Y_TOE)
    expected = h * scene.X_END - h * x_faces / 2
    assert area == pytest.approx(expected, rel=1e-9)
    assert set(scene.TOE_PASSES) == {2, 5, 8, 11, 13, 15}      # Table 6.4's toe passes


@pytest.mark.parametrize("bad, word", [(dict(edge_length=-1.0), "edge_length"),
                                       (dict(tensile=-1.0), "tensile"),
                                       (dict(stage_blocks=((1, 2), (2, 3))), "stage_blocks"),
                                       (dict(stage_blocks=((16,),)), "stage_blocks"),
                                       (dict(zone_depth=500.0), "zone_depth")])
def test_bad_parameters_are_refused_by_name(bad, word):
    with pytest.raises(ValueError, match=word):
        scene.LornexParams(**bad)


def test_equal_time_compares_runs_inside_the_first_solve_they_all_fail():
    """Two runs whose third solve both fail, one proven after 10 s and one after 30 s: they
    are compared 10 s into that solve, each displacement read off its own history."""
    def run(label, end, speed):
        stages = [{"time": 0.0}, {"time": 1.0}, {"time": 1.0}, {"time": 2.0},
                  {"time": 2.0}, {"time": 2.0 + end}]
        t = np.linspace(0.0, 2.0 + end, 401)
        u = np.where(t > 2.0, speed * (t - 2.0), 0.0)
        hist = {"time": t.tolist(), **{f"{k}.ux": u.tolist() for k in lornex.PRISMS},
                **{f"{k}.uy": np.zeros_like(t).tolist() for k in lornex.PRISMS}}
        motion = lornex._stage_motion(hist, stages, [1, 3, 5], {k: (0.0, 0.0)
                                                                for k in lornex.PRISMS})
        return {"label": label, "mining": {"verdict": ["equilibrium", "failing", "failing"],
                                           "motion": motion}}

    fast, slow = run("fast", 10.0, 0.5), run("slow", 30.0, 0.2)
    fast["mining"]["verdict"][1] = "equilibrium"       # the first solve both fail: the third
    same = lornex.equal_time([fast, slow])
    assert same["stage"] == 3 and same["time_s"] == pytest.approx(10.0)
    assert same["mean_m"]["fast"] == pytest.approx(5.0, rel=1e-9)
    assert same["mean_m"]["slow"] == pytest.approx(2.0, rel=1e-9)
    assert lornex.equal_time([{"label": "old", "mining": {"verdict": ["failing"]}}]) is None
