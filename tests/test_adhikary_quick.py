"""The quick ``adhikary`` variant end to end, asserting the physics the thesis found (4.2):

- failure g rises with the flaw tensile strength T (0.8 < 1.1 <= 1.4 MPa, thesis 70 -> 82 g
  from 1.1 to 1.4);
- the flaw friction (25 instead of 37 degrees) changes the failure g by less than the T range
  does ("little effect");
- a lower bedding cohesion (5 instead of 15 kPa) fails at least the thesis's 20 g earlier
  (about 50 vs 70 g; a strict xfail, see its reason);
- the conventional mode (unbreakable flaws) fails later than the damage model (thesis 115 g);
- the damage model's rupture runs from the toe into the slope;

and that its failure g-levels are the stored regression numbers (tests/case_reference.json).
Quick = 6 mm blocks with edge elements on the step from the largest eigenvalue (the scene's
contact model, whose failure g converges with block size), a ramp in 20 g levels from 20 to
120 g, the failed level bisected and the ramp closed in 5 g steps, each level judged at rest or
failing by the response judge, one process per run (two side by side).
"""
import pytest
from case_reference_check import assert_failure_g_matches

from comparisons import adhikary


@pytest.fixture(scope="module")
def quick():
    return adhikary.run("quick", seed=1)


def _failure_g(result, tensile):
    return dict((t, g) for t, g in result.methods["dem"]["failure_g"])[tensile]


def test_base_run_first_and_every_run_fails_in_range(quick):
    pairs = quick.methods["dem"]["failure_g"]
    assert pairs[0][0] == 1.1                        # the scene's base properties first
    levels = adhikary.VARIANTS["quick"]["g_levels"]
    # every run stands at the first level and fails within the ramp
    assert all(g is not None and levels[0] < g <= levels[-1] for _, g in pairs)
    assert quick.methods["dem"]["g_resolution"] == adhikary.VARIANTS["quick"]["refine_to"]


def test_failure_g_rises_with_tensile_strength(quick):
    g08, g11, g14 = (_failure_g(quick, t) for t in (0.8, 1.1, 1.4))
    assert g08 < g14
    assert g08 <= g11 <= g14


def test_flaw_friction_matters_less_than_tensile_strength(quick):
    (friction, g_friction), = quick.methods["dem"]["friction_study"]
    assert friction == 25.0
    t_range = _failure_g(quick, 1.4) - _failure_g(quick, 0.8)
    assert abs(g_friction - _failure_g(quick, 1.1)) < t_range


@pytest.mark.xfail(strict=True, reason=(
    "on edge elements (2026-12-01) the quick's 5 kPa run fails at 40 g, the base run at 45 g "
    "(rounded corners, 2026-12-02; both at 40 g with sharp ones), not 20 g earlier. "
    "With the thesis's residual law (c = T = 0 once a contact slips) the beds hold by cohesion "
    "alone and have mostly slipped by 40 g at 5-50 kPa; on the end springs, long before their "
    "~80 g failure, 5 and 15 kPa failed at about the same g (6 mm random cells, 1 g steps: 76.4 g at both, seed 1, "
    "after the solver fixes; before them 76.4 vs 75.6 g seed 1, "
    "92.9 vs 77.9 g seed 2; 4 mm seed rows: 56.4 vs 56.6 g). The elastic demand agrees in DEM "
    "and continuum (benchmarks/bedding_demand.py: 61-64 % of the beds past 15 kPa by 40 g, 5 and "
    "15 kPa differ in 6-8 % of the beds at 70 g). Perfectly plastic beds give the trend "
    "(120/140/170 g at 5/15/50 kPa) but are not the thesis's law (docs/comparisons.md)"))
def test_lower_bedding_cohesion_fails_earlier(quick):
    # thesis: about 20 g earlier (50 vs 70 g), one of the quick's 20 g levels. The trend counts
    # when the 5 kPa run fails at least that much earlier (the same 20 g as when the quick had
    # 10 g steps and asked for more than one step; in the 1 g runs above 5 kPa fails 1 and 15 g
    # later than 15 kPa)
    thesis_drop = (adhikary.REFERENCE["thesis_dem_failure_g_T1.1"]
                   - adhikary.REFERENCE["thesis_dem_failure_g_bedding_c5kPa"])
    (cohesion_kpa, g_low), = quick.methods["dem"]["bedding_cohesion_study"]
    assert cohesion_kpa == 5.0
    assert g_low <= _failure_g(quick, 1.1) - thesis_drop


def test_conventional_mode_fails_later_than_the_damage_model(quick):
    conventional = quick.methods["conventional"]["failure_g"]
    assert conventional is None or conventional > _failure_g(quick, 1.1)


def test_rupture_runs_from_the_toe_into_the_slope(quick):
    rupture = quick.methods["dem"]["rupture"]
    assert rupture is not None and rupture["depth_m"] > 0.01
    assert 0.0 < rupture["angle_above_joint_normal_deg"] < 60.0
    assert quick.methods["dem"]["runtime_s"] > 0 and quick.methods["continuum"]["runtime_s"] > 0


def test_failure_g_matches_the_regression_reference(quick):
    measured = {f"T={t}": g for t, g in quick.methods["dem"]["failure_g"]}
    measured["flaw friction 25"] = quick.methods["dem"]["friction_study"][0][1]
    measured["bedding c 5 kPa"] = quick.methods["dem"]["bedding_cohesion_study"][0][1]
    measured["conventional"] = quick.methods["conventional"]["failure_g"]
    assert_failure_g_matches(measured, "adhikary_quick")


def test_the_report_says_what_the_contact_model_makes_of_the_failure_g(quick):
    """The quick runs the scene's edge elements; its notes say the failure g is the converged
    model's and how far that is from the experiment, and how to get the end springs."""
    note = next(n for n in quick.notes if n.startswith("Contact model:"))
    assert "edge elements" in note and "converges with block size" in note
    assert "edge_elements" in note and "false" in note
    assert adhikary.contact_model_note({"edge_elements": False}).startswith(
        "Contact model: the end-spring pair")
