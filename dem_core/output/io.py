"""Model files: one ``.npz`` holding the block system, the state bundles, the contacts, the
component tables, monitoring points and histories; a resumed run is bit-for-bit the same.

Arrays are stored exactly (npz) under ``<bundle>.<field>`` names, scalars and names as JSON in
the ``meta`` entry. ``Model.save`` / ``Model.load`` decide what goes in; this module only writes
and reads parts (it does not import the model).
"""
from __future__ import annotations

import json
import pickle
import zipfile

import numpy as np

from ..geometry.blocks import BlockSystem
from ..contact.contacts import Contacts
from .monitor import History
from ..components.cables import Cables
from ..deformable.component import Deformable
from ..components.liner import Liners
from ..step.state import BlockProps, BlockState, CrackLog

__all__ = ["save_parts", "load_parts"]

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
