"""Model files: one ``.npz`` holding the block system, the state bundles, the contacts, the
component tables, monitoring points and histories; a resumed run is bit-for-bit the same.

Arrays are stored exactly (npz) under ``<bundle>.<field>`` names, scalars and names as JSON in
the ``meta`` entry, with the file's ``format`` version (``FORMAT``). ``write_model`` and
``read_model`` decide what goes in (the model is only read: this module does not import it);
``save_parts`` and ``load_parts`` write and read the parts. A file of an older format is
converted by ``_upgrade`` (one function per version step) or refused with a message naming the
file and its version.

Format versions: 1, files written before the format was versioned (2026-11-24 to 28: the
options as attributes, ``fixed_dt`` for the option ``dt``, the options added later missing);
2, the ``SolverOptions`` record under ``meta["options"]``; 3 (2026-11-29), without the
``control`` arrays of the cables, liners and zones bundles (copies of the model's dt, damping,
time and gravity, from when those parts had their own clock: the step now gives them its own);
4 (2026-11-29), with the softening bonds' damage and the energy account (the contacts'
``damage``, ``work_fracture``, ``work_friction``, the blocks' ``work``, ``energy_bank``): files
before it read as undamaged, with nothing spent so far; 5 (2026-11-30), with the option
``kinetic_adaptive`` and the kinetic-damping memory of eight numbers (``step.relaxation``):
files before it go on with the fixed check interval they ran with.
"""
from __future__ import annotations

import dataclasses
import json
import pickle
import zipfile

import numpy as np

from ..geometry.blocks import BlockSystem
from ..components.water import exposed_faces
from ..contact.contacts import Contacts
from ..contact.materials import material_table
from ..contact.rounding import rounding_bundle
from .energy import BANK
from .monitor import History
from ..components.cables import Cables, no_cables
from ..deformable.component import Deformable, no_deformable
from ..components.liner import Liners, no_liners
from ..step.state import BlockProps, BlockState, CrackLog

__all__ = ["save_parts", "load_parts", "write_model", "read_model", "RUNNING", "FORMAT"]

FORMAT = 5

# What changes while a model runs (``Model.snapshot``/``restore`` copy these attributes); the
# rest is fixed when it is built, or changed only by ``Model.set_options``.
RUNNING = ("props", "state", "contacts", "cracks", "materials", "table", "gravity", "load",
           "servo_groups", "time", "step", "dt", "critical_dt", "kinetic", "history",
           "points", "search_enabled", "water", "water_faces", "cables", "liners",
           "zone_state", "response_steps", "in_motion", "energy_bank")
# saved with the model but not part of a snapshot: ``measured_steps`` counts the cost of every
# response-time measurement, also those of levels a search later undoes
_CLOCK = ("time", "step", "dt", "critical_dt", "search_enabled", "response_steps", "in_motion",
          "measured_steps")

_BS_ARRAYS = ("vertices", "vertex_offsets", "centroid", "area", "region_id", "edge_p0",
              "edge_p1", "edge_block_a", "edge_block_b", "edge_normal", "edge_length",
              "edge_material")
_BUNDLES = {"props": BlockProps, "state": BlockState, "cracks": CrackLog, "cables": Cables,
            "liners": Liners, "zone_state": Deformable}


def save_parts(path, blocks, bundles: dict, contacts: Contacts, arrays: dict, meta: dict,
               servo_groups, points: dict, history: History) -> None:
    """Write a model's parts to ``path`` (.npz)."""
    out = {f"bs.{k}": getattr(blocks, k) for k in _BS_ARRAYS}
    out.update({f"group.{k}": np.asarray(v) for k, v in blocks.groups.items()})
    for name, bundle in bundles.items():
        out.update({f"{name}.{f}": v for f, v in zip(bundle._fields, bundle)})
    out.update(contacts.to_dict())
    out.update({f"array.{k}": v for k, v in arrays.items()})
    for i, (g, prm) in enumerate(servo_groups):
        out[f"servo.{i}.blocks"], out[f"servo.{i}.params"] = g, prm
    for name, (b, local, x0) in points.items():
        out[f"point.{name}"] = np.concatenate([[b], local, x0])
    for k, v in history.columns.items():
        out[f"history.{k}"] = np.asarray(v)
    meta = dict(meta, region_names=blocks.region_names, material_names=blocks.material_names,
                groups=list(blocks.groups), arrays=list(arrays), n_servo=len(servo_groups),
                points=list(points), history_every=history.every,
                history_columns=list(history.columns))
    out["meta"] = np.frombuffer(json.dumps(meta).encode(), dtype=np.uint8)
    with open(path, "wb") as fh:
        np.savez(fh, **out)


def load_parts(path) -> dict:
    """The parts written by ``save_parts``: blocks, bundles, contacts, arrays, meta, servo,
    points, history. A file that is not one (truncated, another kind of file, an .npz of
    something else) raises ValueError naming it; a missing file, FileNotFoundError."""
    try:
        return _parts(path)
    except (OSError, EOFError, ValueError, KeyError, TypeError, AttributeError,
            zipfile.BadZipFile, pickle.UnpicklingError) as e:
        if isinstance(e, FileNotFoundError) or str(e).startswith(f"{path}: a model file"):
            raise
        raise ValueError(f"{path}: not a model file (an .npz written by Model.save, holding "
                         f"the blocks, state and contacts) or a truncated one: "
                         f"{type(e).__name__}: {e}") from None


def _bundle(d, name, cls):
    """Bundle ``name`` of the file's arrays ``d``; fields added since the file was written
    come from ``cls.fields_of_old_files(the bundle's fields the file has)``, if the class has
    it (else
    the KeyError says the file is not a model file)."""
    have = {f: d[f"{name}.{f}"] for f in cls._fields if f"{name}.{f}" in d}
    if len(have) < len(cls._fields) and hasattr(cls, "fields_of_old_files"):
        held = {k.split(".", 1)[1]: v for k, v in d.items() if k.startswith(name + ".")}
        have = {**cls.fields_of_old_files(held), **have}
    return cls(**{f: have[f] for f in cls._fields})


def _parts(path) -> dict:
    with np.load(path) as z:
        d = {k: z[k] for k in z.files}
    meta = json.loads(bytes(d["meta"]).decode())
    if "arrays" not in meta:
        raise ValueError(f"{path}: a model file from before 2026-11-24 (the state bundles); "
                         "re-run the model to write it again")
    blocks = BlockSystem(**{k: d[f"bs.{k}"] for k in _BS_ARRAYS},
                         region_names=meta["region_names"],
                         groups={g: d[f"group.{g}"] for g in meta["groups"]},
                         material_names=meta["material_names"])
    bundles = {name: _bundle(d, name, cls) for name, cls in _BUNDLES.items()
               if f"{name}.{cls._fields[0]}" in d}
    points = {}
    for name in meta["points"]:
        p = d[f"point.{name}"]
        points[name] = (int(p[0]), p[1:3].copy(), p[3:5].copy())
    history = History(every=meta["history_every"])
    history.columns = {k: list(d[f"history.{k}"]) for k in meta["history_columns"]}
    return {"blocks": blocks, "bundles": bundles, "contacts": Contacts.from_dict(d),
            "arrays": {k: d[f"array.{k}"] for k in meta["arrays"]}, "meta": meta,
            "servo": [(d[f"servo.{i}.blocks"], d[f"servo.{i}.params"])
                      for i in range(meta["n_servo"])],
            "points": points, "history": history}


def write_model(path, model) -> None:
    """Write ``model`` (a ``dem_core.model.Model``, only read) to ``path`` (.npz)."""
    bundles = {k: getattr(model, k) for k in _BUNDLES}
    arrays = {k: getattr(model, k) for k in ("block_E", "block_nu", "gravity", "load",
                                              "kinetic", "energy_bank")}
    options = {k: v for k, v in dataclasses.asdict(model.options).items()
               if k not in ("block_E", "block_nu")}
    meta = {"format": FORMAT, "options": options,
            "clock": {k: getattr(model, k) for k in _CLOCK},
            "materials": {k: vars(m) for k, m in model.materials.items()},
            "table_names": model.table.names,
            "water": None if model.water is None else model.water.to_dict()}
    save_parts(path, model.blocks, bundles, model.contacts, arrays, meta, model.servo_groups,
               model.points, model.history)


def read_model(path, material, water_table) -> dict:
    """The attributes of the model saved at ``path``: its parts, ``options`` (a
    ``SolverOptions``), ``materials`` (``material(**fields)`` each), the material table, the
    corners and the water (``water_table(dict)``: a WaterTable, with its exposed faces)."""
    from ..settings import SolverOptions

    parts = load_parts(path)
    meta = _upgrade(parts["meta"], path)
    a = parts["arrays"]
    options = SolverOptions(**meta["options"], block_E=a["block_E"], block_nu=a["block_nu"])
    out = {"blocks": parts["blocks"], "options": options, "contacts": parts["contacts"],
           "response_steps": None,              # not in files before it was measured
           "in_motion": False,                  # nor this, before a mechanism kept N_r
           "measured_steps": 0,                 # nor the cost of the measurements
           **meta["clock"],
           "materials": {k: material(**v) for k, v in meta["materials"].items()},
           "servo_groups": parts["servo"], "points": parts["points"],
           "history": parts["history"]}
    out["table"] = material_table(meta["table_names"], out["materials"], options.unbreakable)
    out.update({k: a[k] for k in ("block_E", "block_nu", "gravity", "load", "kinetic")})
    # the kinetic-damping memory was (3,) before format 5 (``step.relaxation``)
    out["kinetic"] = np.concatenate([out["kinetic"], np.zeros(8 - len(out["kinetic"]))])
    out["energy_bank"] = a.get("energy_bank", np.zeros(len(BANK)))   # (files before it)
    out.update({k: parts["bundles"][k] for k in ("props", "state", "cracks")})
    out["cables"] = parts["bundles"].get("cables", no_cables())
    out["liners"] = parts["bundles"].get("liners", no_liners())
    out["zone_state"] = parts["bundles"].get("zone_state", no_deformable())
    out["corners"] = rounding_bundle(out["props"], options.rounding)
    water = meta.get("water")
    out["water"] = None if water is None else water_table(water)
    if water is not None:
        out["water"].check()
    out["water_faces"] = None if water is None else exposed_faces(out["blocks"],
                                                                  out["props"].active)
    return out


def _upgrade(meta, path) -> dict:
    """``meta`` in today's format (``FORMAT``); ValueError naming the file for a format this
    code does not know."""
    version = meta.get("format", 1)
    if version == 1:
        meta = _from_1(meta)
        version = 2
    if version == 2:
        meta = _from_2(meta)
        version = 3
    if version == 3:
        meta = dict(meta, format=4)     # the added arrays default to zero (``Contacts``,
        version = 4                     # ``BlockState.fields_of_old_files``, ``read_model``)
    if version == 4:                    # they go on with the fixed kinetic-damping interval
        meta = dict(meta, format=5, options=dict(meta["options"], kinetic_adaptive=False))
        version = 5
    if version != FORMAT:
        raise ValueError(f"{path}: a model file of format {version}; this dem_core reads "
                         f"formats 1 to {FORMAT}: save it again with a dem_core that knows it")
    return meta


def _from_1(meta) -> dict:
    """Format 1 -> 2: the options were the model's attributes under "settings" (the fixed
    step as ``fixed_dt``); options added after a file was written take their defaults (the
    behaviour the file's model had), the history interval comes from the history."""
    settings = dict(meta["settings"])
    settings["dt"] = settings.pop("fixed_dt", None)
    settings["history_every"] = meta["history_every"]
    clock = dict(meta["clock"])
    clock.setdefault("critical_dt", float("inf"))
    return dict(meta, format=2, options=settings, clock=clock)


def _from_2(meta) -> dict:
    """Format 2 -> 3: the cables', liners' and zones' ``control`` arrays (dt, damping, time
    and gravity: copies of the model's own, taken from the model before every run) are
    dropped; ``load_parts`` reads a bundle's present fields only (``_bundle``), so the old
    arrays in the file are left behind and nothing else changes."""
    return dict(meta, format=3)
