"""Save a Model to one ``.npz`` file and load it back; a resumed run is bit-for-bit the same.

Everything the next step reads is stored: the block system, materials, settings, block
properties and state, the live contacts with their history, the crack log, servo groups,
history points and recorded histories. Arrays are stored exactly (npz), scalars and names as
JSON in the ``meta`` entry.
"""
from __future__ import annotations

import json
from dataclasses import asdict, fields

import numpy as np

from .blocks import BlockSystem
from .contacts import Contacts
from .materials import Material, material_table
from .monitor import History
from .state import BlockProps, BlockState

__all__ = ["save_model", "load_model"]

_BS_ARRAYS = ("vertices", "vertex_offsets", "centroid", "area", "region_id", "edge_p0",
              "edge_p1", "edge_block_a", "edge_block_b", "edge_normal", "edge_length",
              "edge_material")
_SETTINGS = ("unbreakable", "damping", "safety", "mass_scaling", "fixed_dt", "search_margin",
             "search_enabled", "new_contact_material", "time", "step", "dt", "critical_dt",
             "threads", "kinetic_damping")


def save_model(model, path) -> None:
    """Write ``model`` to ``path`` (.npz)."""
    bs = model.blocks
    arrays = {f"bs.{k}": getattr(bs, k) for k in _BS_ARRAYS}
    arrays.update({f"group.{k}": np.asarray(v) for k, v in bs.groups.items()})
    arrays.update({f"props.{f.name}": getattr(model.props, f.name) for f in fields(BlockProps)})
    arrays.update({f"state.{f.name}": getattr(model.state, f.name) for f in fields(BlockState)})
    arrays.update(model.contacts.to_dict())
    arrays["block_E"], arrays["block_nu"] = model.block_E, model.block_nu
    arrays["cracks"], arrays["crack_count"] = model.cracks, model.crack_count
    arrays["gravity"] = model.gravity
    arrays["ke_last"] = model.ke_last
    for i, (g, prm) in enumerate(model.servo_groups):
        arrays[f"servo.{i}.blocks"], arrays[f"servo.{i}.params"] = g, prm
    for name, (b, local, x0) in model.points.items():
        arrays[f"point.{name}"] = np.concatenate([[b], local, x0])
    for k, v in model.history.columns.items():
        arrays[f"history.{k}"] = np.asarray(v)
    meta = {
        "region_names": bs.region_names, "material_names": bs.material_names,
        "groups": list(bs.groups), "table_names": model.table.names,
        "materials": {k: asdict(m) for k, m in model.materials.items()},
        "settings": {k: getattr(model, k) for k in _SETTINGS},
        "history_every": model.history.every, "history_columns": list(model.history.columns),
        "n_servo": len(model.servo_groups), "points": list(model.points),
    }
    arrays["meta"] = np.frombuffer(json.dumps(meta).encode(), dtype=np.uint8)
    with open(path, "wb") as fh:
        np.savez(fh, **arrays)


def load_model(path):
    """Read a Model written by ``save_model``."""
    from .model import Model

    with np.load(path) as z:
        d = {k: z[k] for k in z.files}
    meta = json.loads(bytes(d["meta"]).decode())
    bs = BlockSystem(**{k: d[f"bs.{k}"] for k in _BS_ARRAYS},
                     region_names=meta["region_names"],
                     groups={g: d[f"group.{g}"] for g in meta["groups"]},
                     material_names=meta["material_names"])
    m = Model.__new__(Model)
    m.blocks = bs
    m.materials = {k: Material(**v) for k, v in meta["materials"].items()}
    m.kinetic_damping = 0                    # files written before the option existed
    for k, v in meta["settings"].items():
        setattr(m, k, v)
    m.table = material_table(meta["table_names"], m.materials, m.unbreakable)
    m.props = BlockProps(**{f.name: d[f"props.{f.name}"] for f in fields(BlockProps)})
    m.state = BlockState(**{f.name: d[f"state.{f.name}"] for f in fields(BlockState)})
    m.contacts = Contacts.from_dict(d)
    m.block_E, m.block_nu = d["block_E"], d["block_nu"]
    m.cracks, m.crack_count = d["cracks"], d["crack_count"]
    m.gravity = d["gravity"]
    m.ke_last = np.zeros(3)                  # files before 2026-11-21 hold two entries
    ke = d.get("ke_last", np.zeros(0))
    m.ke_last[:len(ke)] = ke
    m.servo_groups = [(d[f"servo.{i}.blocks"], d[f"servo.{i}.params"])
                      for i in range(meta["n_servo"])]
    m.points = {}
    for name in meta["points"]:
        p = d[f"point.{name}"]
        m.points[name] = (int(p[0]), p[1:3].copy(), p[3:5].copy())
    m.history = History(every=meta["history_every"])
    m.history.columns = {k: list(d[f"history.{k}"]) for k in meta["history_columns"]}
    m._rot = np.zeros((bs.n_blocks, 2))
    from .integrate import update_rotation
    update_rotation(m.state.theta, m._rot)
    return m
