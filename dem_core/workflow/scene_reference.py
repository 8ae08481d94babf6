"""docs/scene-reference.md, generated from the scene file's JSON Schema
(``scene_schema.scene_schema``): every level's keys as a table (type, unit and meaning,
default, required), a minimal example of each stage kind and a minimal scene, each of which
loads with ``Scene.load`` (tests/test_scene_schema.py). Written by
``python -m dem_core.workflow.scene_schema --write``; the minimal scene is read from the
checkout's ``comparisons/scenes/adhikary.json``.
"""
from __future__ import annotations

import json
from pathlib import Path

from .stages import STAGE_KINDS

__all__ = ["reference_page", "example_stages", "minimal_scene", "EXAMPLE_STAGES",
           "REFERENCE_PAGE", "WRITE_COMMAND"]

REFERENCE_PAGE = Path(__file__).resolve().parents[2] / "docs" / "scene-reference.md"
WRITE_COMMAND = "python -m dem_core.workflow.scene_schema --write"

EXAMPLE_SCENE = Path(__file__).resolve().parents[2] / "comparisons" / "scenes" / "adhikary.json"
# the required values of each stage kind's example on the reference page, in the minimal
# scene's groups, materials and points (a stage kind without one fails ``--write``)
EXAMPLE_STAGES = {
    "gravity": {}, "solve": {}, "cycle": {"steps": 1000},
    "raise_gravity": {"g_levels": [50, 100, 150]}, "excavate": {"group": "crest"},
    "change_material": {"material": "joint:bedding", "changes": {"cohesion": 0.0}},
    "prescribe_velocity": {"group": "base"}, "release": {"group": "base"},
    "servo": {"group": "crest", "stress": 1e5, "length": 0.1},
    "load": {"group": "crest", "rate": 1e-7}, "insitu": {},
    "displace": {"group": "crest", "displacement": 0.001},
    "factor_of_safety": {"materials": ["joint:bedding"]},
    "strength_schedule": {"material": "flaw:rock", "property": "tensile_strength",
                          "values": [1e6, 8e5]},
    "water": {"surface": [[0.0, 0.2], [0.4, 0.05]]},
    "cable": {"collar": [0.31, 0.2], "end": [0.2, 0.2], "area": 5e-6, "E": 2e11,
              "yield_tension": 1e3, "grout_stiffness": 1e8, "grout_strength": 1e4},
    "liner": {"group": "crest", "thickness": 0.002, "E": 2e10, "tensile_yield": 2e6,
              "compressive_yield": 2e7, "bond_kn": 1e10, "bond_ks": 1e10, "bond_tension": 1e5,
              "bond_shear": 1e5}}


def example_stages() -> dict:
    """kind -> a minimal stage of that kind (its required keys only)."""
    missing = sorted(set(STAGE_KINDS) - set(EXAMPLE_STAGES))
    if missing:
        raise ValueError(f"stage kind(s) {missing} have no example: add their required values "
                         "to scene_reference.EXAMPLE_STAGES")
    return {kind: {"kind": kind, **EXAMPLE_STAGES[kind]} for kind in STAGE_KINDS}


def minimal_scene(schema: dict) -> dict:
    """The example scene file (``EXAMPLE_SCENE``) without its stages, solver options,
    description and every key at its default, and with a "crest" group for the stages."""
    with open(EXAMPLE_SCENE) as fh:
        d = json.load(fh)
    for key in ("stages", "solver", "description"):
        d.pop(key, None)
    d = _without_defaults(d, schema, schema["$defs"])
    d["name"] = "minimal"
    d["groups"]["crest"] = {"inside": [[0.15, 0.3], [0.3, 0.3], [0.3, 0.4], [0.15, 0.4]]}
    return d


def _without_defaults(value, node, defs):
    """``value`` without the optional keys, at any level, that hold their default (or
    constant)."""
    if "$ref" in node:
        node = defs[node["$ref"].rsplit("/", 1)[1]]
    if isinstance(value, dict) and "properties" in node:
        props, keep = node["properties"], set(node.get("required", ()))
        return {k: _without_defaults(v, props.get(k, {}), defs) for k, v in value.items()
                if k in keep or not _at_default(v, props.get(k, {}))}
    if isinstance(value, dict) and isinstance(node.get("additionalProperties"), dict):
        return {k: _without_defaults(v, node["additionalProperties"], defs)
                for k, v in value.items()}
    if isinstance(value, list) and isinstance(node.get("items"), dict):
        return [_without_defaults(v, node["items"], defs) for v in value]
    return value


def _at_default(value, p: dict) -> bool:
    """Whether a value is its property's default or constant (compared as JSON text)."""
    text = json.dumps(value, sort_keys=True)
    return any(k in p and json.dumps(p[k], sort_keys=True) == text for k in ("default", "const"))


def _compact(value, indent=0, lead=0) -> str:
    """JSON with each object or list on one line where it fits in 100 characters."""
    flat = json.dumps(value)
    if indent + lead + len(flat) <= 100 or not isinstance(value, (dict, list)) or not value:
        return flat
    pad = " " * (indent + 2)
    if isinstance(value, dict):
        items = [f"{pad}{json.dumps(k)}: {_compact(v, indent + 2, len(json.dumps(k)) + 3)}"
                 for k, v in value.items()]
    else:
        items = [pad + _compact(v, indent + 2, 1) for v in value]
    ends = "{}" if isinstance(value, dict) else "[]"
    return ends[0] + "\n" + ",\n".join(items) + "\n" + " " * indent + ends[1]


def _where(schema: dict) -> dict:
    """def name -> where in a file it is first met ("geometry.regions[i]")."""
    out = {}

    def walk(node, path):
        if "$ref" in node:
            name = node["$ref"].rsplit("/", 1)[1]
            if name not in out:
                out[name] = path
                walk(schema["$defs"][name], path)
            return
        for key, sub in node.get("properties", {}).items():
            walk(sub, f"{path}.{key}" if path else key)
        if isinstance(node.get("items"), dict):
            walk(node["items"], path + "[i]")
        if isinstance(node.get("additionalProperties"), dict):
            walk(node["additionalProperties"], path + "[name]")
        for sub in node.get("anyOf", []) + node.get("allOf", []):
            walk(sub, path)
        if "then" in node:
            walk(node["then"], path)

    walk(schema, "")
    return out


def _type_words(p: dict) -> str:
    """A property's type, in words, for the page."""
    if "$ref" in p:
        return f"`{p['$ref'].rsplit('/', 1)[1]}`"
    if "const" in p:
        return f"`{json.dumps(p['const'])}`"
    if "enum" in p:
        return "one of " + ", ".join(f"`{json.dumps(v)}`" for v in p["enum"])
    if "anyOf" in p:
        return " or ".join(_type_words(s) for s in p["anyOf"])
    types = p.get("type", [])
    words = []
    for t in types if isinstance(types, list) else [types]:
        items, values = p.get("items"), p.get("additionalProperties")
        if t == "array" and items and p.get("minItems") == p.get("maxItems") is not None:
            words.append("[" + ", ".join([_type_words(items)] * p["minItems"]) + "]")
        elif t == "array" and items:
            words.append(f"array of {_type_words(items)}")
        elif t == "object" and isinstance(values, dict):
            words.append(f"object: name -> {_type_words(values)}")
        else:
            words.append(t)
    return " or ".join(words) or "any"


def _cell(text: str) -> str:
    return text.replace("|", "\\|").replace("<", "\\<")


def _table(node: dict) -> list:
    """The key table of one level: key, type, required, default, description."""
    rows = ["| key | type | required | default | description |", "|---|---|---|---|---|"]
    required = set(node.get("required", ()))
    for key, p in node["properties"].items():
        default = f"`{json.dumps(p['default'])}`" if "default" in p else ""
        rows.append(f"| `{key}` | {_cell(_type_words(p))} | {'yes' if key in required else ''}"
                    f" | {_cell(default)} | {_cell(p.get('description', ''))} |")
    return rows


def _section(title: str, node: dict, level: str = "##") -> list:
    about = [_cell(node["description"]), ""] if node.get("description") else []
    return [f"{level} {title}", "", *about, *_table(node), ""]


PAGE_HEAD = f"""# Scene file reference

<!-- Generated by `{WRITE_COMMAND}` from the records a scene
file is read into; do not edit by hand (tests/test_scene_schema.py fails when it is stale). -->

Every key of a scene file (docs/scenes.md), level by level: its JSON type, whether it is
required, its default and what it is (with the unit where the record's docstring gives one).
The same as a JSON Schema (draft 2020-12) for editors and `validate_scene`:
`dem_core/scene.schema.json`. `Scene.load` checks all this and more (value ranges, group and
material names) with its own messages. At the end: a minimal scene and a minimal example of
each stage kind, each of which loads with `Scene.load`.
"""


def reference_page(schema: dict) -> str:
    """docs/scene-reference.md: every level's table, then the minimal scene and each stage
    kind's example."""
    defs, where = schema["$defs"], _where(schema)
    out = [PAGE_HEAD, *_section("The top level (`Scene`)", schema)]
    for name, node in defs.items():
        if not name.startswith("stage.") and name != "Stage":
            out += _section(f"`{name}` (at `{where.get(name, '?')}`)", node)
    out += ["## Stages", "", _cell(defs["Stage"]["description"]) + " Each item of `stages` is "
            "one of these; the example is the kind with its required keys only.", ""]
    examples = example_stages()
    for kind in STAGE_KINDS:
        node = defs[f"stage.{kind}"]
        out += _section(f"`{kind}`", node, "###")
        out += ["Example:", "", "```json", _compact(examples[kind]), "```", ""]
    out += ["## A minimal scene", "", f"`{EXAMPLE_SCENE.relative_to(REFERENCE_PAGE.parents[1])}`"
            " with the keys at their defaults left out, no stages and a `crest` group: each "
            "example above goes into its `stages` list.", "", "```json",
            _compact(minimal_scene(schema)), "```"]
    return "\n".join(out) + "\n"
