"""The JSON Schema of a scene file, generated from the scene and stage records
(dem_core/workflow/scene_schema.py):

- the shipped schema and docs/scene-reference.md are what the generator writes now (a stale
  file fails, naming the command that writes it);
- it is a valid draft 2020-12 schema whose every level holds the keys the loader allows;
- every scene file in the repository validates, as does the scene each case module writes;
- typical mistakes are each reported with their path (and the loader refuses them too);
- each stage kind's example on the reference page validates and loads with ``Scene.load``;
- a new field of a record is in the schema (type, default, required, description) with no
  edit of the generator;
- ``Scene.load`` ignores a "$schema" key.
No stage is run.
"""
from __future__ import annotations

import copy
import dataclasses
import importlib
import inspect
import json
import re
from dataclasses import dataclass
from pathlib import Path

import jsonschema
import pytest

from dem_core.geometry.spec import GEOMETRY_KEYS
from dem_core.settings import SCENE_SOLVER_KEYS
from dem_core.workflow import scene_schema as ss
from dem_core.workflow.scene import _SCENE_KEYS, Scene
from dem_core.workflow.stages import STAGE_KINDS

ROOT = Path(__file__).resolve().parents[1]
STALE = f"is stale: run `{ss.WRITE_COMMAND}`"


def scene_files() -> list:
    """Every scene file in the repository: examples/*.json and the comparisons' scene JSON."""
    found = sorted(ROOT.glob("examples/*.json")) + sorted(ROOT.glob("comparisons/**/*.json"))
    return [p for p in found if "geometry" in json.loads(p.read_text())]


def adhikary() -> dict:
    with open(ROOT / "comparisons" / "scenes" / "adhikary.json") as fh:
        return json.load(fh)


# ---------------------------------------------------------------------- the generated files
def test_the_shipped_schema_and_reference_page_are_what_the_generator_writes(tmp_path):
    ss.write(tmp_path / "scene.schema.json", tmp_path / "scene-reference.md")
    assert ss.SCHEMA_FILE.read_text() == (tmp_path / "scene.schema.json").read_text(), \
        f"{ss.SCHEMA_FILE} {STALE}"
    assert ss.REFERENCE_PAGE.read_text() == (tmp_path / "scene-reference.md").read_text(), \
        f"{ss.REFERENCE_PAGE} {STALE}"


def test_the_schema_is_valid_and_ships_with_the_package():
    schema = json.loads(ss.SCHEMA_FILE.read_text())
    jsonschema.Draft202012Validator.check_schema(schema)
    assert schema["$schema"] == "https://json-schema.org/draft/2020-12/schema"
    pyproject = (ROOT / "pyproject.toml").read_text()
    assert re.search(r'dem_core = \[[^]]*"scene\.schema\.json"', pyproject)
    assert '"jsonschema>=4"' in pyproject


def test_each_level_holds_the_keys_the_loader_allows():
    schema = ss.scene_schema()
    defs = schema["$defs"]
    assert set(schema["properties"]) == _SCENE_KEYS | {"$schema"}
    assert schema["required"] == ["geometry", "materials", "density"]
    assert set(defs["GeometrySpec"]["properties"]) == set(GEOMETRY_KEYS)
    assert set(defs["SolverOptions"]["properties"]) == set(SCENE_SOLVER_KEYS)
    assert set(defs["Stage"]["properties"]["kind"]["enum"]) == set(STAGE_KINDS)
    for kind, cls in STAGE_KINDS.items():
        stage = defs[f"stage.{kind}"]
        assert set(stage["properties"]) == {"kind"} | {f.name for f in dataclasses.fields(cls)}
        assert stage["additionalProperties"] is False and stage["required"][0] == "kind"
    assert all(d.get("additionalProperties") is False for d in defs.values()
               if "properties" in d and d["title"] != "Stage")


# ---------------------------------------------------------------------- scenes validate
@pytest.mark.parametrize("path", scene_files(), ids=lambda p: str(p.relative_to(ROOT)))
def test_every_scene_file_in_the_repository_validates(path):
    assert ss.validate_scene(json.loads(path.read_text())) == []


def test_there_is_a_scene_file_to_validate():
    assert scene_files()


def case_scene_modules() -> list:
    """The case modules of comparisons.scenes that write a scene from default parameters."""
    out = []
    for p in sorted((ROOT / "comparisons" / "scenes").glob("*.py")):
        mod = importlib.import_module(f"comparisons.scenes.{p.stem}")
        params = [c for n, c in vars(mod).items() if n.endswith("Params")
                  and inspect.isclass(c) and c.__module__ == mod.__name__]
        if hasattr(mod, "scene") and params:
            out.append((p.stem, params[0]))
    return out


@pytest.mark.parametrize("name, params", case_scene_modules(), ids=lambda v: str(v))
def test_the_scene_each_case_writes_validates(name, params):
    scene = importlib.import_module(f"comparisons.scenes.{name}").scene(params())
    assert ss.validate_scene(json.loads(json.dumps(scene.to_dict()))) == []


# ---------------------------------------------------------------------- mistakes
def _rename(node, old, new):
    node[new] = node.pop(old)


MISTAKES = {
    "joint_set": (lambda d: _rename(d["geometry"], "joint_sets", "joint_set"),
                  "geometry: Additional properties are not allowed ('joint_set' was unexpected)"),
    "dip": (lambda d: _rename(d["geometry"]["joint_sets"][0], "dip_deg", "dip"),
            "geometry.joint_sets[0]: Additional properties are not allowed ('dip' was "
            "unexpected)"),
    "x no": (lambda d: d["boundaries"][0].update(x="no"),
             "boundaries[0].x: 'no' is not of type 'boolean'"),
    "max_steps true": (lambda d: d["stages"][1].update(max_steps=True),
                       "stages[1].max_steps: True is not of type 'integer'"),
    "unknown kind": (lambda d: d["stages"][0].update(kind="sovle"),
                     "stages[0].kind: 'sovle' is not one of ['cable', 'change_material', "),
    "no kind": (lambda d: d["stages"][0].pop("kind"), "stages[0]: 'kind' is a required property"),
    "material key": (lambda d: d["materials"]["flaw:rock"].update(frictoin=30),
                     "materials['flaw:rock']: Additional properties are not allowed "
                     "('frictoin' was unexpected)"),
    "size field": (lambda d: d["geometry"]["voronoi"]["rock"].update(size_field={"zone": 1}),
                   "geometry.voronoi.rock.size_field.zone: 1 is not of type 'array'"),
}


@pytest.mark.parametrize("mistake", list(MISTAKES))
def test_a_typical_mistake_is_reported_with_its_path(mistake, tmp_path):
    d = adhikary()
    d["stages"].insert(0, {"kind": "gravity", "g_level": 1.0})
    assert ss.validate_scene(d) == []
    edit, words = MISTAKES[mistake]
    edit(d)
    errors = ss.validate_scene(d)
    assert any(e.startswith(words) for e in errors), errors
    with pytest.raises(ValueError):                 # the loader refuses it too
        Scene.from_dict(copy.deepcopy(d))


def test_the_command_line_lists_a_files_errors(tmp_path, capsys):
    good, bad = tmp_path / "good.json", tmp_path / "bad.json"
    good.write_text(json.dumps(adhikary()))
    d = adhikary()
    d["boundaries"][0]["x"] = "no"
    bad.write_text(json.dumps(d))
    assert ss.main([str(good)]) == 0
    assert ss.main([str(good), str(bad)]) == 1
    out = capsys.readouterr().out
    assert f"{good}: valid" in out and f"{bad}: boundaries[0].x: 'no' is not of type" in out


# ---------------------------------------------------------------------- the reference page
def page_examples() -> tuple:
    """(the minimal scene, {kind: stage}) of docs/scene-reference.md's JSON blocks."""
    blocks = [json.loads(b) for b in
              re.findall(r"```json\n(.*?)\n```", ss.REFERENCE_PAGE.read_text(), re.S)]
    base = [b for b in blocks if "geometry" in b]
    stages = [b for b in blocks if "geometry" not in b]
    assert len(base) == 1 and len(stages) == len({s["kind"] for s in stages})
    return base[0], {s["kind"]: s for s in stages}


def test_the_reference_page_has_an_example_of_every_stage_kind():
    assert set(page_examples()[1]) == set(STAGE_KINDS)


@pytest.mark.parametrize("kind", list(STAGE_KINDS))
def test_each_stage_kinds_example_validates_and_loads(kind, tmp_path):
    base, stages = page_examples()
    d = dict(base, stages=[stages[kind]])
    assert ss.validate_scene(d) == []
    path = tmp_path / "scene.json"
    path.write_text(json.dumps(d))
    scene = Scene.load(path)
    assert type(scene.stages[0]) is STAGE_KINDS[kind]


def test_the_minimal_scene_loads_and_is_the_example_scene_without_its_defaults():
    base, _ = page_examples()
    full = Scene.from_dict(adhikary())
    small = Scene.from_dict(dict(base, name=full.name, description=full.description,
                                 groups={k: v for k, v in base["groups"].items()
                                         if k != "crest"},
                                 stages=adhikary()["stages"], solver=adhikary()["solver"]))
    assert small.to_dict() == full.to_dict()


# ---------------------------------------------------------------------- one source of truth
@dataclass(frozen=True)
class Toy:
    """A stage kind made up for this test.

    Parameters
    ----------
    depth : float
        How deep the toy digs, m.
    label : str or None
        What it is called.
    """

    depth: float
    count: int = 3
    label: str | None = None
    flag: bool = False
    points: tuple = ()


def test_a_new_field_of_a_record_is_in_the_schema_with_no_edit(monkeypatch):
    monkeypatch.setitem(STAGE_KINDS, "toy", Toy)
    toy = ss.scene_schema()["$defs"]["stage.toy"]
    assert toy["required"] == ["kind", "depth"] and toy["additionalProperties"] is False
    assert toy["properties"] == {
        "kind": {"description": "the stage's kind", "const": "toy"},
        "depth": {"description": "How deep the toy digs, m.", "type": "number"},
        "count": {"type": "integer", "default": 3},
        "label": {"description": "What it is called.", "type": ["string", "null"],
                  "default": None},
        "flag": {"type": "boolean", "default": False},
        "points": {"type": "array", "default": []}}


# ---------------------------------------------------------------------- "$schema"
def test_scene_load_ignores_a_schema_key(tmp_path):
    d = adhikary()
    path = tmp_path / "scene.json"
    path.write_text(json.dumps({"$schema": "../dem_core/scene.schema.json", **d}))
    assert ss.validate_scene(json.loads(path.read_text())) == []
    assert Scene.load(path).to_dict() == Scene.from_dict(d).to_dict()


def test_every_documented_stage_example_runs_on_the_documented_scene():
    """A scene written from docs/scene-reference.md alone runs: the page's minimal scene is
    built once, and each stage kind's example runs on it, from the same state (its step
    budget, displacement and levels cut short: this checks that it runs, not what it finds)."""
    import dataclasses
    import warnings

    import numpy as np

    from dem_core.workflow.scene import build_model
    from dem_core.workflow.stages import run_stages, stage_to_dict

    base, stages = page_examples()
    scene = Scene.from_dict(dict(base, stages=list(stages.values())))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")              # (the page's scene is a small one)
        model = build_model(scene)
    start = model.snapshot()
    short = {"max_steps": 200, "steps": 200, "max_displacement": 2e-6, "displacement": 2e-6}
    ran = []
    for stage in scene.stages:
        cut = {k: v for k, v in short.items() if hasattr(stage, k)}
        cut.update({k: tuple(getattr(stage, k))[:1] for k in ("g_levels", "f_levels", "values")
                    if hasattr(stage, k)})
        model.restore(start)
        rec = run_stages(model, [dataclasses.replace(stage, **cut)])[0]
        assert rec.verdict not in ("failed", "unstable"), (rec.kind, rec.verdict)
        assert np.all(np.isfinite(model.state.pos)), rec.kind
        ran.append(rec.kind)
    assert ran == [stage_to_dict(s)["kind"] for s in scene.stages] == list(stages)
