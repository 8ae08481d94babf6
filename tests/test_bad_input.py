"""Bad input a new user tries: each is refused with a clear error naming the value,
before any compute; none passes in silence or ends in a traceback from deep inside."""
import json
import math
import os

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


@pytest.mark.skipif(os.geteuid() == 0, reason="root writes into read-only folders")
def test_a_read_only_out_folder_is_refused_before_any_compute(tmp_path, capsys, no_compute):
    out = tmp_path / "ro"
    out.mkdir()
    out.chmod(0o500)
    try:
        assert cli.main(["run", "lajtai", "--out", str(out)]) == 2
    finally:
        out.chmod(0o700)
    assert "cannot write results" in one_line(capsys.readouterr().err)


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
    (["stages", 1, "max_steps"], True, "stage 1 (solve): max_steps must be a whole number, "
                                       "got True"),
    (["stages", 0, "g_level"], True, "stage 0 (gravity): g_level must be a number, got True"),
    (["geometry", "voronoi", "rock", "edge_seeding"], "yes",
     "geometry.voronoi['rock']: edge_seeding must be true or false, got 'yes'"),
    (["solver", "edge_elements"], 1, "solver: edge_elements must be true or false, got 1"),
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
