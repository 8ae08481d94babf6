"""The quick ``longtan`` variant end to end (8 mm blocks, 40 g levels bisected to 10 g, about
30 s on 2 cores): the damage model fails, the conventional model not earlier, and the failure
g-levels are the stored regression numbers (tests/case_reference.json), so a change of the
physics that moves them is seen (one went unseen until 2026-11-25: docs/comparisons.md)."""
import pytest
from case_reference_check import assert_failure_g_matches

from comparisons import longtan


@pytest.fixture(scope="module")
def quick():
    return longtan.run("quick", seed=1)


def test_damage_model_fails_before_the_conventional_model(quick):
    (t, g), = quick.methods["dem"]["failure_g"]
    conventional = quick.methods["conventional"]["failure_g"]
    assert t == 4.81 and g is not None
    assert conventional is None or conventional >= g


def test_failure_g_matches_the_regression_reference(quick):
    measured = {f"T={t:g}": g for t, g in quick.methods["dem"]["failure_g"]}
    measured["conventional"] = quick.methods["conventional"]["failure_g"]
    assert_failure_g_matches(measured, "longtan_quick")
