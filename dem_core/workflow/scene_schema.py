"""The JSON Schema of a scene file, generated from the records a scene file is read into.

One source of truth: ``scene_schema()`` walks the dataclass records ``Scene.from_dict`` reads a
file into (``Scene``, ``GeometrySpec``, ``Region``, ``JointSet``, ``JointLine``, ``Voronoi``,
``ZoneSizeField``, ``Material``, ``Boundary``, ``SolverOptions`` and each stage record of
``STAGE_KINDS``): each field's annotation gives its JSON type (``X | None`` also takes null),
its default the ``default``, a field without one is ``required``, and the "name : text" lines
of the record's docstring (or a "name (unit)" in it) its ``description``. A new field of a
record is in the schema without an edit here; only how the levels nest (``_nested``) and which
values come from a fixed set (``_choices``) are written out, as ``Scene.from_dict`` reads them.

The checks of ``Scene.load`` stay the primary ones (a "did you mean" for a typo, value
ranges, group and material names); the schema is for editors (completion, hover text, marks
under a wrong key) and for ``validate_scene``: every error of a file at once, with its path.
``Scene.load`` does not call it: the schema is a little stricter than the loader in places (a
list where the loader would also take a string), so it could refuse a scene that loads today.

    python -m dem_core.workflow.scene_schema --write     writes dem_core/scene.schema.json
                                                         and docs/scene-reference.md (in a
                                                         checkout: the page's example is
                                                         comparisons/scenes/adhikary.json)
    python -m dem_core.workflow.scene_schema FILE ...    lists each file's schema errors
"""
from __future__ import annotations

import argparse
import dataclasses
import functools
import inspect
import json
import re
import sys
from pathlib import Path

from ..contact.materials import Material
from ..geometry import GeometrySpec, JointLine, JointSet, Region, Voronoi, ZoneSizeField
from ..settings import JUDGES, SCENE_SOLVER_KEYS, STEP_ESTIMATES, SolverOptions, SolveSettings
from . import stages as _stages
from .scene import GROUP_SELECTORS, SIDES, Boundary, Scene
from .scene_reference import REFERENCE_PAGE, WRITE_COMMAND, reference_page
from .stages import AFTER_FAILURE, STAGE_KINDS, ChangeMaterial
from .strength import SCHEDULED, StrengthSchedule

__all__ = ["scene_schema", "validate_scene", "json_path", "SCHEMA_FILE", "REFERENCE_PAGE"]

SCHEMA_FILE = Path(__file__).resolve().parents[1] / "scene.schema.json"

_JSON_TYPES = {"bool": "boolean", "int": "integer", "float": "number", "str": "string",
               "tuple": "array", "list": "array", "dict": "object", "None": "null"}
# records whose fields other records carry under the same name (``SolveSettings.of``): a
# stage's field without a note of its own takes the note and choices of these
_SHARED = (SolveSettings,)


def _ref(name: str) -> dict:
    return {"$ref": f"#/$defs/{name}"}


def _map_of(value: dict) -> dict:
    return {"type": "object", "additionalProperties": value}


def _list_of(value: dict) -> dict:
    return {"type": "array", "items": value}


_POINT = {"type": "array", "items": {"type": "number"}, "minItems": 2, "maxItems": 2,
          "description": "[x, y], m"}
_POLYGON = {"type": "array", "items": _POINT, "minItems": 3, "description": "[[x, y], ...], m"}


@functools.cache
def _nested() -> dict:
    """How the levels of a scene file nest, as ``Scene.from_dict`` and
    ``GeometrySpec.from_dict`` read them: (record, field) -> the schema of the field's value.
    Every other field's schema comes from its annotation."""
    return {(Scene, "geometry"): _ref("GeometrySpec"),
            (Scene, "materials"): _map_of(_ref("Material")),
            (Scene, "groups"): _map_of(_ref("GroupSelector")),
            (Scene, "boundaries"): _list_of(_ref("Boundary")),
            (Scene, "points"): _map_of(_POINT),
            (Scene, "stages"): _list_of(_ref("Stage")),
            (Scene, "solver"): _ref("SolverOptions"),
            (GeometrySpec, "regions"): dict(_list_of(_ref("Region")), minItems=1),
            (GeometrySpec, "joint_sets"): _list_of(_ref("JointSet")),
            (GeometrySpec, "joints"): _list_of(_ref("JointLine")),
            (GeometrySpec, "voronoi"): _map_of(_ref("Voronoi")),
            (GeometrySpec, "groups"): _map_of(_POLYGON),
            (Voronoi, "size_field"): _ref("ZoneSizeField"),
            (ChangeMaterial, "changes"): _ref("MaterialChanges")}


@functools.cache
def _choices() -> dict:
    """(record, field) -> the values a field takes, where the code keeps them as a constant."""
    return {(Scene, "after_failure"): AFTER_FAILURE, (SolveSettings, "judge"): JUDGES,
            (SolverOptions, "step_estimate"): STEP_ESTIMATES,
            (StrengthSchedule, "property"): SCHEDULED}


# ---------------------------------------------------------------------- docstrings
def _own_doc(cls) -> str:
    """The record's own docstring ('' when it has none: not the one dataclass makes up)."""
    doc = cls.__dict__.get("__doc__") or ""
    return "" if doc.startswith(cls.__name__ + "(") else inspect.cleandoc(doc)


def _clean(text: str) -> str:
    """One line: whitespace collapsed, ``code`` as `code`."""
    return " ".join(text.replace("``", "`").split())


def summary(cls) -> str:
    """The first paragraph of a record's docstring, on one line ('' without one)."""
    return _clean(_own_doc(cls).split("\n\n")[0])


def _name_pattern(cls) -> str:
    """A regex of a record's field names, and of lists of them ("kn, ks")."""
    names = sorted((re.escape(f.name) for f in dataclasses.fields(cls)), key=len, reverse=True)
    one = "(?:" + "|".join(names) + ")"
    return f"({one}(?:, {one})*)"


@functools.cache
def _notes(cls) -> dict:
    """field -> its text from the "name : text" entries of the record's docstring: numpydoc
    ("name : type" then the text indented below it; a bare type dropped) or one paragraph of
    "name : text" entries (``SolverOptions``, ``Scene``). An entry ends at a blank line."""
    doc = _own_doc(cls)
    numpy = re.search(r"^Parameters\n-+$", doc, re.M)
    body = doc[numpy.end():] if numpy else doc
    heads = list(re.finditer(rf"(?:^[ \t]*|(?<=\. )){_name_pattern(cls)} : ", body, re.M))
    notes = {}
    for m, nxt in zip(heads, heads[1:] + [None]):
        text = body[m.end():nxt.start() if nxt else len(body)].split("\n\n")[0].strip()
        first, _, rest = text.partition("\n")
        if numpy and rest.strip():
            bare = re.fullmatch(r"(float|int|bool|str)(, optional| or None)?", first.strip())
            text = rest if bare else f"{first.strip()}: {rest}"
        for name in m.group(1).split(", "):
            notes.setdefault(name, _clean(text))
    return notes


@functools.cache
def _units(cls) -> dict:
    """field -> the text in parentheses right after its name in the docstring ("area (m^2)",
    "``v_max`` (m/step)"): the unit where no "name : text" entry gives one."""
    nested = r"[^()]*(?:\([^()]*\)[^()]*)*"
    pattern = rf"(?<![\w.])(``)?{_name_pattern(cls)}(?(1)``) \(({nested})\)"
    out = {}
    for m in re.finditer(pattern, _own_doc(cls)):
        if "docstring" in m.group(3):          # a pointer, not a unit
            continue
        for name in m.group(2).split(", "):
            out.setdefault(name, _clean(m.group(3)))
    return out


def _note(cls, name: str) -> str:
    """The description of a field: its docstring entry, else its unit, else, in a record
    that carries a ``_SHARED`` record's fields, that of the shared field ('' when none
    says)."""
    for source in (cls, *_carried(cls)):
        text = _notes(source).get(name) or _units(source).get(name)
        if text:
            return text
    return ""


def _carried(cls) -> list:
    """The ``_SHARED`` records all of whose fields ``cls`` has too."""
    names = {f.name for f in dataclasses.fields(cls)}
    return [s for s in _SHARED if s is not cls
            and {f.name for f in dataclasses.fields(s)} <= names]


@functools.cache
def _stage_words() -> dict:
    """kind -> what the stage does, from the table of the stages module's docstring."""
    rows = re.findall(r'^\| "(\w+)" \| [^|]+ \| (.+?) \|$', _stages.__doc__, re.M)
    return {kind: _clean(does) for kind, does in rows}


# ---------------------------------------------------------------------- records -> schema
def _types(annotation) -> list:
    """JSON types of a field annotation ("float | None" -> ["number", "null"]); [] for
    one that takes anything (``object``) or names a record (nested by ``_nested``)."""
    text = annotation if isinstance(annotation, str) else getattr(annotation, "__name__",
                                                                  str(annotation))
    kinds = [k.strip() for k in text.split("|")]
    if not all(k in _JSON_TYPES for k in kinds):
        return []
    return list(dict.fromkeys(_JSON_TYPES[k] for k in kinds))


def _default(f):
    """A field's default as JSON (tuples as lists), or MISSING."""
    value = f.default
    if f.default_factory is not dataclasses.MISSING:
        value = f.default_factory()
    if value is dataclasses.MISSING:
        return value
    try:
        return json.loads(json.dumps(value))
    except (TypeError, ValueError):
        return dataclasses.MISSING


def _field_choices(cls, f, note: str):
    """The fixed set of values of a field: ``_choices``, a shared record's, or a numpydoc
    type line "{"a", "b"}"; None when it takes any value of its type."""
    for source in (cls, *_carried(cls)):
        if (source, f.name) in _choices():
            return list(_choices()[(source, f.name)])
    m = re.match(r'\{("[^"]*"(?:, "[^"]*")*)\}', note)
    return json.loads(f"[{m.group(1)}]") if m else None


def _field(cls, f) -> dict:
    """The schema of one field of a record."""
    out, note, default = {}, _note(cls, f.name), _default(f)
    if note:
        out["description"] = note
    nested, types = _nested().get((cls, f.name)), _types(f.type)
    if nested is not None:
        nullable = default is None or "null" in types
        out.update({"anyOf": [nested, {"type": "null"}]} if nullable else nested)
    elif types:
        out["type"] = types[0] if len(types) == 1 else types
    choices = _field_choices(cls, f, note)
    if choices:
        out["enum"] = choices + ([None] if "null" in types else [])
    if default is not dataclasses.MISSING:
        out["default"] = default
    return out


def _required(f) -> bool:
    return f.default is dataclasses.MISSING and f.default_factory is dataclasses.MISSING


def _record(cls, keys=None, partial=False, kind=None) -> dict:
    """The schema of a record's file form: its fields (those in ``keys``), no other key,
    the fields without a default required (none when ``partial``: a record of changes).
    ``kind``: the optional "kind" key a joint or size field may carry, this constant."""
    fields = [f for f in dataclasses.fields(cls) if keys is None or f.name in keys]
    props = {f.name: _field(cls, f) for f in fields}
    if kind is not None:
        props["kind"] = {"description": "the record's kind, optional", "const": kind}
    out = {"type": "object", "title": cls.__name__}
    if summary(cls):
        out["description"] = summary(cls)
    out.update(properties=props, additionalProperties=False)
    required = [] if partial else [f.name for f in fields if _required(f)]
    if required:
        out["required"] = required
    return out


def _changes(cls) -> dict:
    """New values of some fields of a record (no field required, none with a default)."""
    rec = _record(cls, partial=True)
    props = {k: {n: v for n, v in p.items() if n != "default"}
             for k, p in rec["properties"].items()}
    return dict(rec, title=f"{cls.__name__}Changes", properties=props,
                description=f"New values of some fields of `{cls.__name__}`.")


def _stage(kind: str, cls) -> dict:
    """A stage kind's record: "kind" (this constant) and its fields."""
    rec = _record(cls)
    does = ". ".join(t for t in (_stage_words().get(kind, ""), rec.get("description")) if t)
    props = {"kind": {"description": "the stage's kind", "const": kind}, **rec["properties"]}
    out = {"type": "object", "title": f"{kind} ({cls.__name__})"}
    if does:
        out["description"] = does
    out.update(properties=props, additionalProperties=False,
               required=["kind", *rec.get("required", [])])
    return out


def _stage_choice() -> dict:
    """An item of "stages": an object whose "kind" picks the stage record it must match
    (if/then rather than oneOf, so an error names the stage's own key)."""
    return {"type": "object", "title": "Stage",
            "description": "A stage: its `kind` says which record the other keys are.",
            "required": ["kind"],
            "properties": {"kind": {"enum": sorted(STAGE_KINDS)}},
            "allOf": [{"if": {"properties": {"kind": {"const": kind}}, "required": ["kind"]},
                       "then": _ref(f"stage.{kind}")} for kind in STAGE_KINDS]}


def _selector() -> dict:
    """A group selector: one of ``GROUP_SELECTORS`` with its argument."""
    names = {"type": "array", "items": {"type": "string"}}
    args = {"touching": {"description": "a side of the model's box", "enum": list(SIDES)},
            "region": {"description": "a region (or geometry group)", "type": "string"},
            "inside": dict(_POLYGON, description="blocks whose centroid lies in this polygon"),
            "union": dict(names, description="blocks in any of these groups"),
            "minus": dict(names, minItems=2, maxItems=2,
                          description="blocks of the first group not in the second")}
    assert set(args) == set(GROUP_SELECTORS), "a new selector needs its argument here"
    return {"type": "object", "title": "GroupSelector",
            "description": "One selector with its argument.", "properties": args,
            "additionalProperties": False, "minProperties": 1, "maxProperties": 1}


def _defs() -> dict:
    """Every record of a scene file, by name, in the order the reference page gives them."""
    defs = {"GeometrySpec": _record(GeometrySpec), "Region": _record(Region),
            "JointSet": _record(JointSet, kind="JointSet"),
            "JointLine": _record(JointLine, kind="JointLine"), "Voronoi": _record(Voronoi),
            "ZoneSizeField": _record(ZoneSizeField, kind="ZoneSizeField"),
            "Material": _record(Material), "MaterialChanges": _changes(Material),
            "GroupSelector": _selector(), "Boundary": _record(Boundary),
            "SolverOptions": _record(SolverOptions, keys=SCENE_SOLVER_KEYS, partial=True),
            "Stage": _stage_choice()}
    defs.update({f"stage.{kind}": _stage(kind, cls) for kind, cls in STAGE_KINDS.items()})
    return defs


def scene_schema() -> dict:
    """The JSON Schema (draft 2020-12) of a scene file, built from the records (module
    docstring). The top level is ``Scene``'s fields and "$schema" (an editor's link to this
    schema, which ``Scene.load`` ignores)."""
    top = _record(Scene)
    link = {"description": "the schema an editor checks this file against (ignored by "
                           "Scene.load)", "type": "string"}
    return {"$schema": "https://json-schema.org/draft/2020-12/schema",
            "title": "rockdm scene file",
            "$comment": f"Generated by `{WRITE_COMMAND}`; do not edit.",
            "description": top["description"],
            "type": "object", "properties": {"$schema": link, **top["properties"]},
            "additionalProperties": False, "required": top["required"], "$defs": _defs()}


# ---------------------------------------------------------------------- validation
def json_path(parts) -> str:
    """A path of keys and indices as the loader's messages write it: stages[1].max_steps,
    materials['flaw:rock'].kn ('' for the top level)."""
    out = ""
    for p in parts:
        if isinstance(p, int):
            out += f"[{p}]"
        elif re.fullmatch(r"[A-Za-z_]\w*", str(p)):
            out += f".{p}" if out else str(p)
        else:
            out += f"[{p!r}]"
    return out


@functools.cache
def _validator():
    import jsonschema
    return jsonschema.Draft202012Validator(scene_schema())


def validate_scene(data) -> list:
    """Every schema error of a scene file's content (``json.load`` of it), one line each:
    "<path>: <message>", e.g. "stages[1].max_steps: True is not of type 'integer'"; []
    when it is valid."""
    out = {f"{json_path(e.absolute_path) or 'scene'}: {e.message}"[:400]
           for err in _validator().iter_errors(data) for e in _leaves(err)}
    return sorted(out)


def _leaves(err) -> list:
    """The errors to report for one: under an "anyOf" (a record or null), those of the
    branches the value's type fits, not "is not of type 'null'"."""
    if not err.context:
        return [err]
    fits = [e for e in err.context if not (e.validator == "type" and not e.relative_path)]
    return [leaf for e in fits for leaf in _leaves(e)] or [err]


def write(schema_file=SCHEMA_FILE, page=REFERENCE_PAGE) -> None:
    """Write the shipped schema and the reference page as the records are now."""
    Path(schema_file).write_text(schema_text())
    Path(page).write_text(reference_page(scene_schema()))


def schema_text() -> str:
    """The shipped file's content."""
    return json.dumps(scene_schema(), indent=1) + "\n"


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m dem_core.workflow.scene_schema",
                                     description=__doc__.split("\n\n")[0])
    parser.add_argument("--write", action="store_true",
                        help=f"write {SCHEMA_FILE.name} and docs/{REFERENCE_PAGE.name}")
    parser.add_argument("files", nargs="*", help="scene files to check against the schema")
    args = parser.parse_args(argv)
    if args.write:
        write()
        print(f"wrote {SCHEMA_FILE} and {REFERENCE_PAGE}")
    bad = 0
    for name in args.files:
        with open(name) as fh:
            errors = validate_scene(json.load(fh))
        bad += bool(errors)
        print("\n".join(f"{name}: {e}" for e in errors) or f"{name}: valid")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
