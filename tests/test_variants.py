"""A case's variant settings (comparisons.variants.pick_variant): named, or a custom mapping
of the same keys, where settings added later may be left out and take their defaults."""
import pytest

from comparisons.variants import pick_variant

VARIANTS = {"quick": dict(edge=0.01, solver={}), "full": dict(edge=0.005, solver={})}


def test_a_named_variant_is_a_copy():
    name, v = pick_variant("case", VARIANTS, "full")
    assert (name, v) == ("full", VARIANTS["full"]) and v is not VARIANTS["full"]


def test_an_optional_setting_left_out_takes_its_default():
    name, v = pick_variant("case", VARIANTS, dict(edge=0.02), optional={"solver": {}})
    assert (name, v) == ("custom", dict(edge=0.02, solver={}))


def test_a_given_optional_setting_is_kept():
    _, v = pick_variant("case", VARIANTS, dict(edge=0.02, solver={"edge_elements": True}),
                        optional={"solver": {}})
    assert v["solver"] == {"edge_elements": True}


@pytest.mark.parametrize("custom, words", [
    (dict(edge=0.02), "lacks ['solver']"),
    (dict(edge=0.02, solver={}, extra=1), "unknown settings ['extra']"),
])
def test_a_custom_variant_with_other_keys_is_refused(custom, words):
    with pytest.raises(ValueError, match=words.replace("[", r"\[").replace("]", r"\]")):
        pick_variant("case", VARIANTS, custom)


@pytest.mark.parametrize("solver, words", [({"step_estimat": "eigen"}, "step_estimat"),
                                           ("eigen", "must be a mapping")])
def test_a_bad_solver_setting_is_named_before_any_run(solver, words):
    with pytest.raises(ValueError, match=words):
        pick_variant("case", VARIANTS, dict(edge=0.02, solver=solver))


def test_a_settle_setting_that_is_not_a_bool_is_named_before_any_run():
    with pytest.raises(ValueError, match="settle must be true or false, got 'yes'"):
        pick_variant("case", {"quick": dict(edge=0.01, settle=False)}, dict(edge=0.02,
                                                                          settle="yes"))
