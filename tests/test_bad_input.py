"""Bad input a new user tries: each is refused with a clear error naming the value,
before any compute; none passes in silence or ends in a traceback from deep inside."""
import json
import math
import re

import numpy as np
import pytest

from comparisons import cli, registry
from dem_core.contact.materials import Material
from dem_core.model import Model
from dem_core.geometry.simple_blocks import from_polygons

SQUARE = [(0, 0), (1, 0), (1, 1), (0, 1)]


def two_blocks() -> Model:
    bs = from_polygons([[(0, 0), (4, 0), (4, 1), (0, 1)], [(1, 1), (2, 1), (2, 2), (1, 2)]],
                       edge_material="joint:base", groups={"base": [0], "block": [1]})
    m = Model(bs, {"joint:*": Material(kn=1e9, ks=1e9, friction=30)}, density=2000)
    m.fix("base")
    m.set_gravity(1.0)
    return m


def one_line(err: str) -> str:
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in err, err
    return lines[0]


# ---------------------------------------------------------------------- the command line
def test_an_unknown_case_is_one_line_listing_the_cases(capsys):
    assert cli.main(["run", "nosuchcase", "--quick"]) == 2
    line = one_line(capsys.readouterr().err)
    assert "'nosuchcase'" in line
    assert all(name in line for name in registry.CASES)


@pytest.fixture
def no_compute(monkeypatch):
    """A run of the lajtai case fails the test: the refusal must come before any compute."""
    def boom(*args, **kwargs):
        raise AssertionError("the case ran before its output folder was checked")
    monkeypatch.setattr(registry.case_module("lajtai"), "run", boom)


def test_an_out_folder_that_is_a_file_is_refused_before_any_compute(tmp_path, capsys,
                                                                    no_compute):
    blocker = tmp_path / "results"
    blocker.write_text("a file where the results folder would go")
    assert cli.main(["run", "lajtai", "--quick", "--out", str(blocker)]) == 2
    line = one_line(capsys.readouterr().err)
    assert "cannot write results" in line and str(blocker) in line


@pytest.mark.parametrize("item, words", [
    ("bogus=1", ["--set bogus", "not a setting of lajtai", "zone_size"]),
    ("zone_size", ["KEY=VALUE", "'zone_size'"]),
    ("ucs_edge=[1, 2]", ["--set ucs_edge", "expected a float", "[1, 2]"]),
])
def test_a_bad_variant_setting_is_refused_before_any_compute(tmp_path, capsys, no_compute,
                                                             item, words):
    assert cli.main(["run", "lajtai", "--set", item, "--out", str(tmp_path)]) == 2
    line = one_line(capsys.readouterr().err)
    assert all(w in line for w in words), line


def test_a_variant_setting_makes_a_custom_variant(tmp_path, monkeypatch):
    seen = {}

    def fake_run(variant, seed, progress):
        seen.update(variant)
        raise KeyboardInterrupt        # stop here: only the settings are checked
    monkeypatch.setattr(registry.case_module("adhikary"), "run", fake_run)
    with pytest.raises(KeyboardInterrupt):
        cli.main(["run", "adhikary", "--full", "--set", 'solver={"edge_elements": true}',
                  "--set", "max_steps=50000", "--out", str(tmp_path)])
    full = registry.case_module("adhikary").VARIANTS["full"]
    assert seen == {**full, "solver": {"edge_elements": True}, "max_steps": 50000}


# ---------------------------------------------------------------------- model files
@pytest.fixture
def saved(tmp_path):
    path = tmp_path / "model.npz"
    two_blocks().save(path)
    return path


def test_a_truncated_model_file_names_the_file_and_what_it_should_be(saved):
    data = saved.read_bytes()
    saved.write_bytes(data[: len(data) // 2])
    with pytest.raises(ValueError, match="not a model file") as e:
        Model.load(saved)
    assert str(saved) in str(e.value) and "Model.save" in str(e.value)


@pytest.mark.parametrize("content", ["text", "other npz"])
def test_a_file_that_is_not_a_model_names_the_file(tmp_path, content):
    path = tmp_path / "notamodel.npz"
    if content == "text":
        path.write_text("just some text\n")
    else:
        np.savez(path, x=np.arange(3))
    with pytest.raises(ValueError, match="not a model file") as e:
        Model.load(path)
    assert str(path) in str(e.value)


def test_a_missing_model_file_is_file_not_found(tmp_path):
    with pytest.raises(FileNotFoundError):
        Model.load(tmp_path / "nothere.npz")


def test_a_saved_model_still_loads(saved):
    assert Model.load(saved).n_blocks == 2


# ---------------------------------------------------------------------- polygons
def test_overlapping_polygons_are_refused_naming_both():
    with pytest.raises(ValueError, match=r"polygons 0 and 2 overlap"):
        from_polygons([SQUARE, [(1, 0), (2, 0), (2, 1), (1, 1)],
                       [(0.5, 0.5), (1.5, 0.5), (1.5, 1.5), (0.5, 1.5)]])


def test_a_self_intersecting_polygon_is_refused_naming_it():
    with pytest.raises(ValueError, match=r"polygon 1 is not a simple polygon"):
        from_polygons([SQUARE, [(1, 0), (2, 1), (2, 0), (1, 1)]])     # a bow tie


@pytest.mark.parametrize("poly, words", [([(0, 0), (1, 0)], "at least 3"),
                                         ([(0, 0), (1, 0), (math.nan, 1)], "finite"),
                                         ([(0, 0), (1, 0), (2, 0)], "polygon 0")])
def test_degenerate_polygons_are_refused(poly, words):
    with pytest.raises(ValueError, match=words):
        from_polygons([poly])


def test_polygons_sharing_edges_and_corners_or_pressed_slightly_in_are_fine():
    bs = from_polygons([SQUARE, [(1, 0), (2, 0), (2, 1), (1, 1)], [(1, 1), (2, 1), (2, 2)]])
    assert bs.n_blocks == 3
    pressed = [(0.2, 1 - 1e-5), (0.8, 1 - 1e-5), (0.8, 1.5), (0.2, 1.5)]   # a contact's depth
    assert from_polygons([SQUARE, pressed]).n_blocks == 2


# ---------------------------------------------------------------------- the model's calls
def test_removing_a_group_twice_names_the_group():
    m = two_blocks()
    m.remove("block")
    with pytest.raises(ValueError, match=r"group 'block' has no blocks left.*removed already"):
        m.remove("block")


@pytest.mark.parametrize("n", [-5, 2.5, math.nan, math.inf, "10", True])
def test_cycle_refuses_a_step_count_that_is_not_a_whole_number(n):
    m = two_blocks()
    with pytest.raises(ValueError, match="whole number") as e:
        m.cycle(n)
    assert repr(n) in str(e.value)
    assert m.step == 0


@pytest.mark.parametrize("n", [0, 3, np.int64(3), 3.0])
def test_cycle_takes_whole_numbers(n):
    m = two_blocks()
    m.cycle(n)
    assert m.step == int(n)


# ---------------------------------------------------------------------- scene files
def scene_dict() -> dict:
    """A small scene file's content: a 0.1 x 0.2 m column of Voronoi blocks with a joint set
    on a base, its groups, boundaries, points and stages."""
    return {"name": "column",
            "geometry": {
                "regions": [{"name": "base", "exterior": [[0, -0.02], [0.1, -0.02], [0.1, 0],
                                                          [0, 0]]},
                            {"name": "rock", "exterior": [[0, 0], [0.1, 0], [0.1, 0.2],
                                                          [0, 0.2]]}],
                "joint_sets": [{"name": "bedding", "dip_deg": 10.0, "spacing": 0.05,
                                "regions": ["rock"]}],
                "voronoi": {"rock": {"edge_length": 0.04, "relax_iterations": 2}}},
            "materials": {"*": {"kn": 1e10, "ks": 5e9, "tensile_strength": 1e6,
                                "cohesion": 2e6, "friction": 35.0}},
            "density": 2500.0,
            "groups": {"floor": {"touching": "bottom"}, "left": {"touching": "left"}},
            "boundaries": [{"group": "base", "x": True, "y": True, "rotation": True}],
            "points": {"A": [0.05, 0.19], "B": [0.05, 0.1]},
            "stages": [{"kind": "gravity", "g_level": 1.0},
                       {"kind": "solve", "max_steps": 1000, "settle": False}],
            "solver": {"damping": 0.7, "history_every": 50}}


def refused(tmp_path, d=None, text=None) -> str:
    """The one-line message loading a scene file of ``d`` (or raw ``text``) is refused with."""
    from dem_core.workflow.scene import Scene

    path = tmp_path / "scene.json"
    path.write_text(text if text is not None else json.dumps(d))
    with pytest.raises(ValueError) as e:
        Scene.load(path)
    return one_line(str(e.value))


def edited(path, value):
    """scene_dict() with the item at ``path`` (keys and indices) set to ``value``, or with a
    key renamed when ``value`` is ``("rename", new)``."""
    d = scene_dict()
    node = d
    for k in path[:-1]:
        node = node[k]
    if isinstance(value, tuple) and value[0] == "rename":
        node[value[1]] = node.pop(path[-1])
    else:
        node[path[-1]] = value
    return d


@pytest.mark.parametrize("path, value, words", [
    (["geometry", "joint_sets"], ("rename", "joint_set"),
     ["geometry: unknown key 'joint_set' (did you mean 'joint_sets'?)", "allowed keys:",
      "regions"]),
    (["geometry", "voronoi"], ("rename", "voronoy"), ["did you mean 'voronoi'?"]),
    (["geometry", "joint_sets", 0, "dip_deg"], ("rename", "dip"),
     ["geometry.joint_sets[0] ('bedding'): unknown key 'dip' (did you mean 'dip_deg'?)"]),
    (["geometry", "regions", 1, "exterior"], ("rename", "exteriour"),
     ["geometry.regions[1] ('rock'): unknown key 'exteriour' (did you mean 'exterior'?)"]),
    (["geometry", "voronoi", "rock", "edge_length"], ("rename", "edge_lenght"),
     ["geometry.voronoi['rock']: unknown key 'edge_lenght' (did you mean 'edge_length'?)"]),
    (["materials", "*", "friction"], ("rename", "frictoin"),
     ["materials['*']: unknown key 'frictoin' (did you mean 'friction'?)"]),
    (["boundaries", 0, "rotation"], ("rename", "rotaton"),
     ["boundaries[0] (group 'base'): unknown key 'rotaton' (did you mean 'rotation'?)"]),
    (["points", "A"], {"x": 0.05, "y": 0.19}, ["points['A'] must be [x, y]"]),
    (["stages", 1, "max_steps"], ("rename", "max_step"),
     ["stage 1 (solve): unknown key 'max_step' (did you mean 'max_steps'?)"]),
    (["stages", 1, "kind"], "sovle", ["stage 1: unknown kind 'sovle' (did you mean 'solve'?)"]),
    (["boundaries"], ("rename", "boundary"),
     ["scene: unknown key 'boundary' (did you mean 'boundaries'?)"]),
    (["groups", "floor"], {"touch": "bottom"},
     ["groups['floor']: unknown key 'touch' (did you mean 'touching'?)"]),
    (["solver", "damping"], ("rename", "dampng"),
     ["solver: unknown key 'dampng' (did you mean 'damping'?)"]),
])
def test_a_typo_anywhere_in_a_scene_file_is_named_with_where_and_a_suggestion(
        tmp_path, path, value, words):
    line = refused(tmp_path, edited(path, value))
    assert all(w in line for w in words), line


def test_a_typo_in_a_scene_file_is_one_line_from_the_command_line(tmp_path, capsys):
    path = tmp_path / "typo.json"
    path.write_text(json.dumps(edited(["geometry", "joint_sets"], ("rename", "joint_set"))))
    assert cli.main(["run-scene", str(path), "--out", str(tmp_path)]) == 2
    line = one_line(capsys.readouterr().err)
    assert str(path) in line and "did you mean 'joint_sets'?" in line
    assert not (tmp_path / "column").exists()            # nothing written, nothing run


@pytest.mark.parametrize("old, new, words", [
    ('"density": 2500.0', '"density": 2500.0, "density": 25.0',
     ["duplicate key 'density'", "top level"]),
    ('"spacing": 0.05', '"spacing": 0.05, "spacing": 0.5',
     ["duplicate key 'spacing'", "geometry.joint_sets[0]"]),
    ('"tensile_strength": 1000000.0', '"tensile_strength": 1e6, "tensile_strength": 0',
     ["duplicate key 'tensile_strength'", "materials['*']"]),
])
def test_a_key_given_twice_in_a_scene_file_is_refused_naming_it(tmp_path, old, new, words):
    text = json.dumps(scene_dict())
    assert old in text
    line = refused(tmp_path, text=text.replace(old, new, 1))
    assert all(w in line for w in words), line


@pytest.mark.parametrize("path, value, words", [
    (["boundaries", 0, "x"], "no",
     "boundaries[0] (group 'base'): x must be true or false, got 'no'"),
    (["materials", "*", "breakable"], "false",
     "materials['*']: breakable must be true or false, got 'false'"),
    (["stages", 1, "settle"], "no", "stage 1 (solve): settle must be true or false, got 'no'"),
    (["stages", 1, "max_steps"], True, "stage 1 (solve): max_steps must be a whole number or "
                                       "null, got True"),
    (["stages", 0, "g_level"], True, "stage 0 (gravity): g_level must be a number, got True"),
    (["geometry", "voronoi", "rock", "edge_seeding"], "yes",
     "geometry.voronoi['rock']: edge_seeding must be true or false, got 'yes'"),
    (["solver", "edge_elements"], 1, "solver: edge_elements must be true or false or null, got 1"),
    (["density"], True, "density (kg/m^3) must be finite and > 0, got True"),
])
def test_a_string_or_number_where_a_bool_is_meant_and_back_is_refused(tmp_path, path, value,
                                                                     words):
    line = refused(tmp_path, edited(path, value))
    assert words in line, line


@pytest.mark.parametrize("name", ["..", ".", "../outside", "a/b", "a\\b", "", "tab\there"])
def test_a_scene_name_that_is_not_a_plain_file_name_is_refused(tmp_path, name, capsys):
    line = refused(tmp_path, edited(["name"], name))
    assert "scene name must be a plain file name" in line and repr(name) in line
    path = tmp_path / "scene.json"
    out = tmp_path / "out"
    assert cli.main(["run-scene", str(path), "--out", str(out)]) == 2
    assert "plain file name" in one_line(capsys.readouterr().err)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["scene.json"]   # nothing written


def test_the_cases_solver_option_merges_over_the_scenes_and_reaches_the_model(monkeypatch):
    """``run adhikary --set 'solver={"damping": 0.5}'``: the case's solver setting is laid
    over its own default damping and the scene's solver options (the case's winning), not a
    TypeError for a keyword given twice."""
    import dataclasses
    from types import SimpleNamespace

    from comparisons import centrifuge
    from dem_core.workflow.scene import Scene, build_model

    small = Scene.from_dict(scene_dict())           # solver damping 0.7, history_every 50
    assert build_model(small, damping=0.5).damping == 0.5     # options over the scene's
    built = {}

    class Built(Exception):
        pass

    def spy(sc, **options):
        built["model"] = build_model(sc, **options)
        raise Built                                   # the model is all this test needs
    monkeypatch.setattr(centrifuge, "build_model", spy)
    case_scene = SimpleNamespace(scene=lambda params, stages: dataclasses.replace(
        small, stages=list(stages)))
    member = dict(label="T=1.1", params={}, g_levels=[10.0], max_steps=100,
                  solver={"damping": 0.5})
    with pytest.raises(Built):
        centrifuge.ramp_run(case_scene, None, member, 0.005, 2e-4)
    m = built["model"]
    assert m.damping == 0.5                                    # the case's solver setting
    assert m.kinetic_damping == centrifuge.KINETIC_DAMPING     # the case's default
    assert m.history_every == 50                               # the scene's own option


@pytest.mark.parametrize("path, value, words", [
    (["groups", "sides"], {"union": [{"touching": "left"}, "floor"]},
     "group 'sides': union takes group names, got {'touching': 'left'}"),
    (["groups", "sides"], {"region": {"touching": "left"}},
     "group 'sides': region takes group names, got {'touching': 'left'}"),
    (["groups", "sides"], {"union": "floor"},
     "group 'sides': union takes a list of group names, got 'floor'"),
    (["boundaries", 0, "group"], {"touching": "bottom"},
     "boundaries[0]: group must be a string, got {'touching': 'bottom'}"),
    (["stages", 2], {"kind": "excavate", "group": {"touching": "left"}},
     "stage 2 (excavate): group must be a string, got {'touching': 'left'}"),
])
def test_a_selector_where_a_group_name_is_meant_is_named(tmp_path, path, value, words):
    d = scene_dict()
    d["stages"].append({"kind": "cycle", "steps": 1})
    node = d
    for k in path[:-1]:
        node = node[k]
    node[path[-1]] = value
    line = refused(tmp_path, d)
    assert words in line, line


@pytest.mark.parametrize("xy", [(0.5, 0.1), (0.05, 0.25), (-1e-3, 0.1), (0.05, -0.03)])
def test_a_monitoring_point_outside_the_model_is_refused_naming_it(tmp_path, xy):
    line = refused(tmp_path, edited(["points", "P"], list(xy)))
    assert f"monitoring point 'P' at ({xy[0]:g}, {xy[1]:g}) m is in no region" in line, line


def test_a_monitoring_point_outside_given_blocks_is_refused_at_build():
    from dem_core.workflow.scene import Scene, build_model

    sc = Scene.from_dict(edited(["points"], {"P": [0.05, 0.15]}))
    d = scene_dict()
    d["geometry"] = {"regions": [{"name": "base", "exterior": [[0, -0.02], [0.1, -0.02],
                                                               [0.1, 0], [0, 0]]},
                                 {"name": "rock", "exterior": [[0, 0], [0.1, 0], [0.1, 0.1],
                                                               [0, 0.1]]}]}
    d["points"] = {}
    short = Scene.from_dict(d)                  # blocks only up to y = 0.1
    from dem_core.geometry import build_block_system
    with pytest.raises(ValueError, match=r"monitoring point 'P' at \(0.05, 0.15\) m is in no "
                                         r"block"):
        build_model(sc, blocks=build_block_system(short.geometry))


def test_monitoring_points_on_block_edges_and_corners_are_taken():
    from dem_core.workflow.scene import Scene, build_model

    on_edges = {"left edge": [0.0, 0.1], "base|rock": [0.05, 0.0], "corner": [0.1, 0.2],
                "bottom": [0.03, -0.02], "inside": [0.05, 0.1]}
    m = build_model(Scene.from_dict(edited(["points"], on_edges)))
    assert set(m.points) == set(on_edges)
    for name, xy in on_edges.items():
        assert np.allclose(m.points[name][2], xy)


# ---------------------------------------------------------------------- magnitudes no rock has
def _column(stages=None, kn=1e10, **materials) -> dict:
    d = scene_dict()
    d["materials"]["*"].update(kn=kn, ks=kn / 2, **materials)
    if stages is not None:
        d["stages"] = stages
    return d


@pytest.mark.parametrize("key, value", [("kn", 1e308), ("ks", 1e308), ("kn", 1e-300),
                                        ("ks", 1.0), ("kn", 1e20)])
def test_an_absurd_contact_stiffness_is_refused_naming_it_and_the_range(tmp_path, key, value):
    line = refused(tmp_path, edited(["materials", "*", key], value))
    assert f"materials['*']: {key} = {value:.3g} Pa/m is not a contact stiffness" in line
    assert "1e+04 to 1e+17 Pa/m" in line


def test_an_absurd_stiffness_in_a_change_material_stage_is_refused(tmp_path):
    d = scene_dict()
    d["stages"].append({"kind": "change_material", "material": "*", "changes": {"kn": 1e308}})
    assert "kn = 1e+308 Pa/m is not a contact stiffness" in refused(tmp_path, d)


def test_a_stiffness_that_overflows_the_time_step_names_the_material_not_zero_division():
    bs = from_polygons([[(0, 0), (4, 0), (4, 1), (0, 1)], [(1, 1), (2, 1), (2, 2), (1, 2)]],
                       edge_material="joint:base")
    with pytest.raises(ValueError, match=r"no time step can be computed.*'joint:base' "
                                         r"\(kn = 1e\+308"):
        with np.errstate(over="ignore"):
            Model(bs, {"joint:*": Material(kn=1e308, ks=1e9)}, density=2000)


@pytest.mark.parametrize("stage, words", [
    ({"kind": "gravity", "g_level": 1e30}, "stage 0 (gravity): g_level 1e+30 is not a physical"),
    ({"kind": "raise_gravity", "g_levels": [10, 1e30]},
     "stage 0 (raise_gravity): g_level 1e+30 is not a physical gravity (at most 10000 g"),
    ({"kind": "insitu", "sxx": 1e300, "syy": 1e300},
     "stage 0 (insitu): sxx = 1e+300 Pa is not a physical in-situ stress (at most 1e+10 Pa"),
    ({"kind": "insitu", "gyy": 1e300, "k": 1.0},
     "stage 0 (insitu): gyy = 1e+300 Pa/m is not a physical in-situ stress gradient"),
])
def test_a_gravity_or_in_situ_stress_no_rock_has_is_refused_naming_it(tmp_path, stage, words):
    line = refused(tmp_path, _column([stage, {"kind": "solve", "max_steps": 100}]))
    assert words in line, line


@pytest.mark.parametrize("kn, stages, words", [
    (1e6, [{"kind": "gravity", "g_level": 100.0}],
     r"stage 0 \(gravity\): gravity of 100 g .* would press the contacts together by about "
     r"0.5\d m .* more than a block's size"),
    (1e10, [{"kind": "gravity"}, {"kind": "insitu", "sxx": 1e9, "syy": 1e9}],
     r"stage 1 \(insitu\): an in-situ normal stress of 1e\+09 Pa would press the contacts "
     r"together by about 0.1 m"),
])
def test_a_load_too_large_for_the_contacts_is_refused_before_the_first_step(kn, stages,
                                                                            words):
    """Values in the physical ranges that these contacts cannot carry: before, the run blew
    up at its first steps with "time step too large: lower safety"."""
    from dem_core.workflow.scene import Scene, build_model
    from dem_core.workflow.stages import run_stages

    sc = Scene.from_dict(_column(stages + [{"kind": "solve", "max_steps": 100}], kn=kn))
    m = build_model(sc)
    with pytest.raises(ValueError, match=words):
        run_stages(m, sc.stages)
    assert m.step == 0


def test_a_blow_up_from_a_contact_stress_names_the_stress_not_the_safety_factor():
    from dem_core.model import ModelUnstable
    from dem_core.workflow.scene import Scene, build_model

    m = build_model(Scene.from_dict(scene_dict()))
    m.set_contact_stress(1e12)                  # what an in-situ stress of 1 TPa would give
    with pytest.raises(ModelUnstable, match=r"a contact stress of 1e\+12 Pa, which would close "
                                            r"a contact .* by 100 m"):
        m.cycle(10)


# ---------------------------------------------------------------------- support
LINER = dict(thickness=0.1, E=30e9, tensile_yield=3e6, compressive_yield=30e6, bond_kn=1e10,
             bond_ks=1e10, bond_tension=1e6, bond_shear=1e6)


def nine_squares(stages, groups=None):
    """A 3 x 3 m square of nine 1 m regions "r<i><j>" (r11 in the middle) on its base."""
    from dem_core.geometry import GeometrySpec
    from dem_core.geometry.regions import rectangle
    from dem_core.workflow.scene import Boundary, Scene

    regions = [rectangle(f"r{i}{j}", i, j, i + 1, j + 1) for i in range(3) for j in range(3)]
    return Scene(GeometrySpec(regions), {"*": Material(kn=1e9, ks=1e9, friction=35.0)},
                 density=2500.0, groups={"bottom": {"touching": "bottom"}, **(groups or {})},
                 boundaries=[Boundary("bottom")], stages=stages)


def test_a_liner_on_a_group_with_no_exposed_face_is_refused_before_the_first_step():
    from dem_core.components.support import Liner
    from dem_core.workflow.scene import build_model
    from dem_core.workflow.stages import Gravity, Solve, run_stages

    sc = nine_squares([Gravity(1.0), Solve(max_steps=300), Liner("r11", **LINER)])
    m = build_model(sc)
    with pytest.raises(ValueError, match=r"stage 2 \(liner\): group 'r11' has no exposed face "
                                         r"\(1 of its 1 blocks left, each edge shared"):
        run_stages(m, sc.stages)
    assert m.step == 0                          # before: after stages 0 and 1 had run


def test_a_liner_on_a_face_an_earlier_excavation_bares_passes_the_check():
    from dem_core.components.support import Liner
    from dem_core.workflow.scene import build_model
    from dem_core.workflow.stages import Excavate, Gravity, check_on_model

    sc = nine_squares([Gravity(1.0), Excavate("r12"), Liner("r11", **LINER)])
    check_on_model(sc.stages, build_model(sc))          # r12 above r11 is gone by then


def test_excavating_what_an_earlier_stage_took_is_refused_before_the_first_step():
    from dem_core.workflow.scene import build_model
    from dem_core.workflow.stages import Excavate, check_on_model

    sc = nine_squares([Excavate("top"), Excavate("r12")],
                      {"top": {"inside": [[0, 2], [3, 2], [3, 3], [0, 3]]}})
    with pytest.raises(ValueError, match=r"stage 1 \(excavate\): group 'r12' has no blocks "
                                         r"left \(excavated by an earlier stage\)"):
        check_on_model(sc.stages, build_model(sc))


def test_a_stage_the_model_cannot_take_is_exit_2_from_run_scene_and_check(tmp_path, capsys):
    """run-scene builds the model and checks every stage against it before the first step
    (before, it ran stage by stage: stage 1 computed, then stage 2 stopped the run, named
    "stage 0")."""
    d = scene_dict()
    d["stages"].append({"kind": "solve", "max_steps": 100, "watch": ["Z"]})
    path = tmp_path / "watch.json"
    path.write_text(json.dumps(d))
    for extra in ([], ["--check"]):
        assert cli.main(["run-scene", str(path), "--out", str(tmp_path / "out")] + extra) == 2
        line = one_line(capsys.readouterr().err)
        assert str(path) in line and "stage 2 (solve): watch names no monitoring point" in line
    assert not (tmp_path / "out" / "column" / "summary.json").exists()


# ---------------------------------------------------------------------- the continuum
@pytest.mark.parametrize("boundaries, free", [
    ([], "(x translation, y translation, rotation)"),
    ([{"group": "floor", "x": False, "y": True, "rotation": False}], "(x translation)")])
def test_a_continuum_its_boundaries_do_not_hold_is_refused_naming_what_is_free(boundaries,
                                                                              free):
    pytest.importorskip("dolfinx")
    from continuum_ref.from_scene import apply_boundaries, mesh_from_scene, scene_bounds
    from continuum_ref.materials import Elastic
    from continuum_ref.model import ContinuumModel
    from dem_core.workflow.scene import Scene

    d = scene_dict()
    d["geometry"]["joint_sets"], d["boundaries"] = [], boundaries
    sc = Scene.from_dict(d)
    model = ContinuumModel(mesh_from_scene(sc, 0.05), Elastic(1e9, 0.25), sc.density)
    with pytest.raises(ValueError, match=r"free to move as a rigid body " + re.escape(free)):
        apply_boundaries(model, sc, scene_bounds(sc))      # before: converged=False, no reason


# ---------------------------------------------------------------------- too large to build
def slope_scene(edge) -> dict:
    """A 14 m slope (60 deg face) of Voronoi blocks of ``edge`` m on a 3 m base."""
    from dem_core.geometry import slope_profile

    rock = slope_profile(14.0, 60, crest_length=10, toe_length=5, base_thickness=3,
                         name="rock")
    return {"name": "slope", "geometry": {"regions": [rock.to_dict()],
                                          "voronoi": {"rock": {"edge_length": edge}}},
            "materials": {"*": {"kn": 1e10, "ks": 5e9, "friction": 35.0}},
            "density": 2600.0, "boundaries": [{"group": "rock"}],
            "stages": [{"kind": "gravity"}, {"kind": "solve", "max_steps": 100}]}


def test_a_1_mm_voronoi_edge_on_a_14_m_slope_is_refused_with_the_numbers(tmp_path, capsys):
    """Before: 79 s into a Qhull out-of-memory error. Now refused before a seed is placed."""
    import time

    path = tmp_path / "slope.json"
    path.write_text(json.dumps(slope_scene(0.001)))
    t0 = time.perf_counter()
    assert cli.main(["run-scene", str(path), "--out", str(tmp_path / "out")]) == 2
    line = one_line(capsys.readouterr().err)
    assert time.perf_counter() - t0 < 5.0
    assert re.search(r"geometry: about 1.1\de\+08 blocks .* would need about [\d.e+]+ GB, "
                     r"more than .* an edge_length of at least 0.0\d+ m in region 'rock' \(now "
                     r"0.001 m\) would fit", line), line


@pytest.mark.parametrize("limit, words", [
    (dict(max_blocks=5), "more than the limit of 5 (DEM_MAX_BLOCKS)"),
    (dict(available=1e5), "more than the 0.0001 GB of memory this machine has available")])
def test_a_block_limit_or_the_memory_refuses_a_geometry(limit, words):
    from dem_core.geometry.budget import check_size
    from dem_core.workflow.scene import Scene

    spec = Scene.from_dict(scene_dict()).geometry
    with pytest.raises(ValueError, match=re.escape(words)):
        check_size(spec, **limit)


def test_the_block_limit_is_read_from_the_environment(monkeypatch):
    from dem_core.geometry import build_block_system
    from dem_core.workflow.scene import Scene

    monkeypatch.setenv("DEM_MAX_BLOCKS", "5")
    with pytest.raises(ValueError, match=r"about [\d.]+ blocks .* more than the limit of 5"):
        build_block_system(Scene.from_dict(scene_dict()).geometry)


@pytest.mark.parametrize("geometry", [
    {"voronoi": {"rock": {"edge_length": 0.3}}, "joint_sets": [{"name": "b", "dip_deg": 30,
                                                                 "spacing": 0.5}]},
    {"joint_sets": [{"name": "b", "dip_deg": 30, "spacing": 0.5},
                    {"name": "c", "dip_deg": 80, "spacing": 0.7}]}])
def test_the_block_estimate_is_within_a_factor_two_of_the_blocks_built(geometry):
    from dem_core.geometry import GeometrySpec, build_block_system
    from dem_core.geometry.budget import estimate_blocks

    spec = GeometrySpec.from_dict({"regions": slope_scene(1.0)["geometry"]["regions"],
                                   **geometry})
    estimate, built = estimate_blocks(spec)["rock"], build_block_system(spec).n_blocks
    assert built / 2 < estimate < 2 * built, (estimate, built)


def test_a_1_mm_continuum_mesh_is_refused_before_gmsh_runs():
    """Before: gmsh aborted with bad_alloc."""
    from continuum_ref.mesh import check_mesh_size, estimate_cells
    from dem_core.workflow.scene import Scene

    rock = Scene.from_dict(slope_scene(1.0)).geometry.regions[0].polygon()
    with pytest.raises(ValueError, match=r"continuum mesh: about 6.1\de\+08 cells \(area 266 "
                                         r"m\^2 at h = 0.001 m\) would need about [\d.e+]+ GB"):
        check_mesh_size(rock, 0.001)
    assert estimate_cells(rock, 0.5, lambda x, y: 0.25) == pytest.approx(
        estimate_cells(rock, 0.25), rel=1e-12)
    pytest.importorskip("gmsh")
    pytest.importorskip("dolfinx")
    from continuum_ref.mesh import mesh_from_geometry
    with pytest.raises(ValueError, match=r"continuum mesh: about 6.1\de\+08 cells"):
        mesh_from_geometry(Scene.from_dict(slope_scene(1.0)).geometry, 0.001)


# ---------------------------------------------------------------------- nothing left
def test_excavating_every_block_is_refused_before_the_first_step_and_a_solve_of_nothing():
    """Before: the solve after it reported "equilibrium" (of no block at all)."""
    from dem_core.workflow.scene import Scene, build_model
    from dem_core.workflow.stages import run_stages

    d = scene_dict()
    d["groups"]["everything"] = {"union": ["rock", "base"]}
    d["stages"] = [{"kind": "gravity"}, {"kind": "excavate", "group": "everything"},
                   {"kind": "solve", "max_steps": 200}]
    sc = Scene.from_dict(d)
    m = build_model(sc)
    with pytest.raises(ValueError, match=r"stage 1 \(excavate\): group 'everything' holds "
                                         r"every block left: nothing would remain"):
        run_stages(m, sc.stages)
    m.remove("everything")
    with pytest.raises(ValueError, match="solve: no block is left"):
        m.solve(max_steps=200)


# ---------------------------------------------------------------------- a case's --set
@pytest.fixture
def no_sweep(monkeypatch):
    """The adhikary case's sweep fails the test: its settings are refused before it."""
    def boom(*args, **kwargs):
        raise AssertionError("the sweep started before the settings were checked")
    monkeypatch.setattr(registry.case_module("adhikary"), "run_sweep", boom)


@pytest.mark.parametrize("item, words", [
    ('solver={"bogus": 1}', "adhikary: solver: unknown key 'bogus'"),
    ("edge_length=-0.006", "member 'conventional': Voronoi edge_length must be finite and > 0"),
    ("g_levels=[120, 100, 80]", "g_levels must be increasing and > 0, got (120, 100, 80)"),
    ("max_steps=0", "max_steps must be a whole number > 0, got 0"),
    ("max_steps=2.5", "max_steps must be a whole number or null, got 2.5")])
def test_a_setting_the_case_refuses_is_one_line_before_its_sweep(tmp_path, capsys, no_sweep,
                                                                 item, words):
    """Before: tracebacks (the solver option from the case's own check, the others from each
    sweep member's worker after the sweep had started)."""
    assert cli.main(["run", "adhikary", "--set", item, "--out", str(tmp_path)]) == 2
    line = one_line(capsys.readouterr().err)
    assert words in line, line


# ---------------------------------------------------------------------- issue 56's list
def _with(*stages):
    d = scene_dict()
    d["stages"] = [{"kind": "gravity"}] + list(stages)
    return d


def _groups(extra, stages):
    d = scene_dict()
    d["groups"].update(extra)
    d["stages"] = stages
    return d


def _moved_region(dy):
    d = scene_dict()
    d["geometry"]["regions"][1]["exterior"] = [[0, dy], [0.1, dy], [0.1, 0.2], [0, 0.2]]
    return d


def _liner_inside():
    d = nine_squares([]).to_dict()
    d["stages"] = [{"kind": "gravity"}, {"kind": "solve", "max_steps": 100},
                   {"kind": "liner", "group": "r11", **LINER}]
    return d


CABLE = {"kind": "cable", "collar": [5, 5], "end": [0.05, 0.1], "area": 1e-4, "E": 2e11,
         "yield_tension": 1e5, "grout_stiffness": 1e9, "grout_strength": 1e6}
# id -> (the scene file's content, exit status of run-scene --check, words of its one line);
# the ids are the rows of docs/bad-input.md (test_the_bad_input_page_lists_every_row)
ISSUE_56 = {
    "S1": (lambda: edited(["geometry", "joint_sets"], ("rename", "joint_set")), 2,
           "did you mean 'joint_sets'?"),
    "S2": (lambda: edited(["geometry", "voronoi"], ("rename", "voronoy")), 2,
           "did you mean 'voronoi'?"),
    "S4": (lambda: _with({"kind": "water", "surface": 5.0}), 0, "warning: stage 1 (water): "
           "the water table is 4.8 m above the ground"),
    "S5": (lambda: _with({"kind": "water", "surface": -5.0}), 2, "below the whole model"),
    "S6": (lambda: edited(["points", "P"], [100, 100]), 2,
           "monitoring point 'P' at (100, 100) m is in no region"),
    "S7": (lambda: _moved_region(2e-4), 2, "regions 'base' and 'rock' are 0.0002 m apart"),
    "S8a": (lambda: edited(["density"], 2.6), 0, "warning: density 2.6 kg/m^3 is below 500"),
    "S8b": (lambda: edited(["materials", "*", "cohesion"], 50.0), 0,
            "warning: materials['*']: cohesion 50 Pa is below 1000 Pa"),
    "S8c": (lambda: edited(["materials", "*", "friction"], 0.6), 0,
            "warning: materials['*']: friction 0.6 deg is below 5 deg"),
    "S9": (lambda: _with({"kind": "raise_gravity", "g_levels": [1, 2], "max_steps": 0}), 2,
           "stage 1 (raise_gravity): max_steps must be a whole number > 0, got 0"),
    "S10": (lambda: _with({"kind": "solve", "failure_displacement": -0.01}), 2,
            "failure_displacement must be > 0 m, got -0.01"),
    "S11a": (lambda: edited(["boundaries", 0, "x"], "no"), 2, "x must be true or false"),
    "S11b": (lambda: edited(["materials", "*", "breakable"], "false"), 2,
             "breakable must be true or false"),
    "S11c": (lambda: edited(["stages", 1, "settle"], "no"), 2, "settle must be true or false"),
    "S12": (lambda: edited(["stages", 1, "max_steps"], True), 2,
            "max_steps must be a whole number or null, got True"),
    "S13": (lambda: json.dumps(scene_dict()).replace('"density": 2500.0',
                                                     '"density": 2500.0, "density": 25.0'),
            2, "duplicate key 'density'"),
    "S14": (lambda: _groups({"all": {"union": ["rock", "base"]}},
                            [{"kind": "excavate", "group": "all"}, {"kind": "solve"}]), 2,
            "stage 0 (excavate): group 'all' holds every block left"),
    "S15": (lambda: edited(["name"], ".."), 2, "scene name must be a plain file name"),
    "C5": (lambda: edited(["geometry", "joint_sets", 0, "dip_deg"], ("rename", "dip")), 2,
           "geometry.joint_sets[0] ('bedding'): unknown key 'dip' (did you mean 'dip_deg'?)"),
    "C6": (lambda: edited(["groups", "sides"], {"union": [{"touching": "left"}, "floor"]}), 2,
           "union takes group names, got {'touching': 'left'}"),
    "C8": (_liner_inside, 2, "stage 2 (liner): group 'r11' has no exposed face"),
    "C9": (lambda: _with({"kind": "solve", "max_steps": 100}, CABLE), 2,
           "stage 2 (cable): the collar (5.0, 5.0) is not inside any active block"),
    "C10": (lambda: _groups({"air": {"inside": [[5, 5], [6, 5], [6, 6]]}},
                            [{"kind": "solve"}, {"kind": "excavate", "group": "air"}]), 2,
            "stage 1 (excavate): group 'air' has no blocks"),
    "C11": (lambda: _with({"kind": "solve"}, {"kind": "solve", "watch": ["Z"]}), 2,
            "stage 2 (solve): watch names no monitoring point ['Z']"),
    "C12": (lambda: edited(["stages", 1, "max_steps"], 2.5), 2,
            "max_steps must be a whole number or null, got 2.5"),
    "C13": (lambda: edited(["materials", "*", "kn"], 1e308), 2,
            "kn = 1e+308 Pa/m is not a contact stiffness"),
    "C14": (lambda: edited(["stages", 0, "g_level"], 1e30), 2,
            "g_level 1e+30 is not a physical gravity"),
    "C15": (lambda: _with({"kind": "insitu", "sxx": 1e300, "syy": 1e300}), 2,
            "sxx = 1e+300 Pa is not a physical in-situ stress"),
    "C17": (lambda: slope_scene(0.001), 2, "geometry: about 1.11e+08 blocks"),
}


@pytest.mark.parametrize("row", list(ISSUE_56))
def test_issue_56s_bad_scene_inputs_are_one_line_before_any_compute(tmp_path, capsys, row):
    """Each bad scene input of issue 56 through ``run-scene --check`` (builds the model, runs
    no step): an error line and status 2, or a warning line and status 0; no traceback."""
    make, status, words = ISSUE_56[row]
    content = make()
    path = tmp_path / "scene.json"
    path.write_text(content if isinstance(content, str) else json.dumps(content))
    assert cli.main(["run-scene", str(path), "--out", str(tmp_path), "--check"]) == status
    err = capsys.readouterr().err
    line = one_line(err) if status else err.strip()
    assert words in line and "Traceback" not in err, line


def test_the_bad_input_page_lists_every_row_and_names_tests_that_exist():
    """docs/bad-input.md: every id of ``ISSUE_56`` is a row, and every test a row names
    exists (the page goes stale when an input or a test is renamed)."""
    from pathlib import Path

    root = Path(__file__).resolve().parents[1]
    page = (root / "docs" / "bad-input.md").read_text()
    rows = re.findall(r"^\| \*\*(\w+)\*\* \|", page, flags=re.M)
    assert set(ISSUE_56) <= set(rows), set(ISSUE_56) - set(rows)
    for path, name in re.findall(r"`(tests/test_\w+\.py)::(test_\w+)", page):
        assert f"def {name}(" in (root / path).read_text(), (path, name)
