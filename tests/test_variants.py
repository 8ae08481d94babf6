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


@pytest.mark.parametrize("value", [1, "yes"])
def test_an_edge_elements_setting_that_is_not_a_bool_or_null_is_named_before_any_run(value):
    with pytest.raises(ValueError, match=f"edge_elements must be true, false or null, got "
                                         f"{value!r}"):
        pick_variant("case", {"quick": dict(edge=0.01, edge_elements=None)},
                     dict(edge=0.02, edge_elements=value))


def test_the_lajtai_setting_edge_elements_reaches_the_specimens_contacts():
    """None keeps the scenes' end springs (the thesis's UDEC contacts); True gives edge
    elements, on the compression and the shear specimen alike."""
    from comparisons import lajtai
    _, cfg = pick_variant("lajtai", lajtai.VARIANTS, "quick")
    cfg["seed"] = 1
    q = lajtai.ucs_query(cfg, 1.2e6)
    assert lajtai.ucs_scene_of(q).solver["edge_elements"] is False
    assert lajtai.ucs_scene_of({**q, "edge_elements": True}).solver["edge_elements"] is True
    zoned = lajtai.ucs_scene_of({**q, "zone_size": 0.007}).solver
    assert zoned["edge_elements"] is False and zoned["deformable"] == {"rock": 0.007}
