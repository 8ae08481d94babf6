"""VTK output of a DEM ``Model`` for ParaView, through meshio (``.vtu`` files and a ``.pvd``
time series).

One unstructured grid per state, in world coordinates (x, y, z = 0; m), with three kinds of
cells told apart by the cell field ``kind``:

========  =====================================================================================
kind 0    blocks: one polygon per active block, at its current position and rotation
          (``x = pos + R(theta) local_vertices``, ``kinematics``)
kind 1    contacts: one line per live contact, from the contact point x_a (the vertex of A)
          along the contact plane, t = (-n_y, n_x) with n the unit normal from A into B, for
          the contact's length L. The two contacts of a shared edge p0-p1 are then its two
          halves (p0 to the midpoint, p1 to the midpoint), so a bonded flaw is drawn as the
          edge itself, in two dashes that can differ in colour.
kind 2    cracks: one vertex (point) per bond failure, where it formed (``Model.crack_log``)
kind 3    support: one line per cable segment and per liner element, between its nodes
          (``dem_core.components.support``)
========  =====================================================================================

Cell fields (every cell has every field: NaN for a float, -1 for an integer where it does not
apply; vectors have 3 components, z = 0, as ParaView expects):

- blocks: ``block`` (index in the BlockSystem), ``displacement`` (centroid, pos - pos0, m),
  ``velocity`` (centroid, m/s), ``rotation`` (theta - theta0, rad, counter-clockwise +),
  ``angular_velocity`` (rad/s), ``group`` (index of the first group in ``blocks.groups`` that
  holds the block, -1 none), ``region`` (``blocks.region_id``: index in ``region_names``).
- contacts: ``sn`` normal stress (Pa, **compression positive**, 0 when open), ``ts`` shear stress
  (Pa, on B along t), ``state`` (``Contacts.state``: 0 intact, 1 slipping, 2 broken in tension,
  3 broken in shear, 4 unbonded: made by the contact search), ``material`` (row of
  ``model.table.names``), ``damage`` (a softening bond's kappa, 0 intact to 1 fully softened;
  0 for every other contact: ``contact.softening``).
- cracks: ``mode`` (1 tension, 2 shear), ``time`` (s, model time of the failure), ``material``.
- support: ``support`` (0 cable, 1 liner), ``element`` (which cable or liner), ``axial_force``
  (N/m per metre out of plane, **tension positive**: a cable's force / its spacing, a liner's
  N), ``moment`` (liner: the larger end moment, N m/m), ``state`` (cable segment: 0 elastic,
  1 yielded, 2 ruptured; liner element: 0 elastic, 1 yielded).

Point field ``vertex_displacement`` (m, 3 components): the rigid-body displacement of each point
(block vertices and contact lines move with their block, crack points are 0, support nodes
move from where they were installed), so ParaView's
"Warp By Vector" with scale factor k - 1 shows the displacement magnified k times.

``legend(model)`` gives the names behind the integer codes (``VtkSeries`` writes it as JSON);
every file carries them as field data too (``legend_field_data``: an array "region 2: lift1"
holding 2, ...).
"""
from __future__ import annotations

import json
from pathlib import Path
from xml.sax.saxutils import quoteattr

import meshio
import numpy as np

__all__ = ["write_vtk", "vtk_mesh", "VtkSeries", "legend", "legend_field_data", "block_groups",
           "KIND_BLOCK", "KIND_CONTACT", "KIND_CRACK", "KIND_SUPPORT"]

KIND_BLOCK, KIND_CONTACT, KIND_CRACK, KIND_SUPPORT = 0, 1, 2, 3
_FLOAT = {"displacement": 3, "velocity": 3, "rotation": 1, "angular_velocity": 1, "sn": 1,
          "ts": 1, "time": 1, "axial_force": 1, "moment": 1, "damage": 1}
_INT = ("kind", "block", "group", "region", "state", "material", "mode", "support", "element")


def _vec3(xy) -> np.ndarray:
    """(n, 2) -> (n, 3) with z = 0."""
    xy = np.asarray(xy, dtype=np.float64).reshape(-1, 2)
    return np.column_stack([xy, np.zeros(len(xy))])


def block_groups(model) -> np.ndarray:
    """(nb,) int32: index of the first group of ``model.blocks.groups`` holding each block,
    -1 for a block in none."""
    out = np.full(model.n_blocks, -1, np.int32)
    for i, idx in reversed(list(enumerate(model.blocks.groups.values()))):
        out[np.asarray(idx, dtype=np.int64)] = i
    return out


def _rigid_displacement(model, owner, x) -> np.ndarray:
    """(n, 2) displacement (m) of the points ``x`` (n, 2) carried by blocks ``owner`` since the
    start pose (pos0, theta0): x - [pos0 + R(theta0) R(theta)^T (x - pos)]."""
    s = model.state
    cos_t, sin_t = s.rot[owner, 0], s.rot[owner, 1]
    d = x - s.pos[owner]
    lx, ly = cos_t * d[:, 0] + sin_t * d[:, 1], -sin_t * d[:, 0] + cos_t * d[:, 1]
    c0, s0 = np.cos(s.theta0[owner]), np.sin(s.theta0[owner])
    x0 = s.pos0[owner] + np.column_stack([c0 * lx - s0 * ly, s0 * lx + c0 * ly])
    return x - x0


def _blocks(model):
    """Points (m), polygon cell blocks and cell fields of the active blocks."""
    p, s = model.props, model.state
    off = p.vertex_offsets
    act = np.flatnonzero(p.active > 0)
    count = np.diff(off)[act]
    owner = np.repeat(np.arange(model.n_blocks), np.diff(off))
    lv = p.local_vertices
    cos_t, sin_t = s.rot[owner, 0], s.rot[owner, 1]
    world = s.pos[owner] + np.column_stack([cos_t * lv[:, 0] - sin_t * lv[:, 1],
                                            sin_t * lv[:, 0] + cos_t * lv[:, 1]])
    keep = p.active[owner] > 0                      # points of removed blocks are left out
    new_index = np.cumsum(keep) - 1
    order = act[np.argsort(count, kind="stable")]   # meshio: one cell block per polygon size
    sizes = np.diff(off)[order]
    cells, rows = [], []
    for k in np.unique(sizes):
        b = order[sizes == k]
        cells.append(("polygon", new_index[off[b][:, None] + np.arange(k)[None, :]]))
        rows.append(b)
    b = np.concatenate(rows) if rows else np.zeros(0, np.int64)
    fields = {"block": b, "displacement": _vec3((s.pos - s.pos0)[b]),
              "velocity": _vec3(s.vel[b]), "rotation": (s.theta - s.theta0)[b],
              "angular_velocity": s.omega[b], "group": block_groups(model)[b],
              "region": np.asarray(model.blocks.region_id)[b]}
    world, owner = world[keep], owner[keep]
    return world, _rigid_displacement(model, owner, world), cells, [len(r) for r in rows], fields


def _contacts(model):
    """Points, line cells and fields of the live contacts (segment x_a -> x_a + L t)."""
    c, s = model.contacts, model.state
    n = c.n
    xa = c.position(s.pos, s.rot)
    nrm = c.normal(s)
    xb = xa + c.live("length")[:, None] * np.column_stack([-nrm[:, 1], nrm[:, 0]])
    pts = np.empty((2 * n, 2))
    pts[0::2], pts[1::2] = xa, xb
    owner = np.repeat(c.live("block_a").astype(np.int64), 2)
    fields = {"sn": c.live("sn"), "ts": c.live("ts"), "state": c.state(),
              "material": c.live("material"), "damage": c.live("damage")}
    lines = [("line", np.arange(2 * n).reshape(n, 2))]
    return pts, _rigid_displacement(model, owner, pts), lines, [n], fields


def _cracks(model):
    """Points, vertex cells and fields of the crack log."""
    log = model.crack_log()
    n = len(log["time"])
    pts = np.column_stack([log["x"], log["y"]])
    names = list(model.table.names)
    fields = {"mode": log["mode"], "time": log["time"],
              "material": np.array([names.index(m) for m in log["material"]], np.int32)}
    return pts, np.zeros((n, 2)), [("vertex", np.arange(n).reshape(n, 1))], [n], fields


def _support(model):
    """Points, line cells and fields of the cable segments and liner elements."""
    cb, ln = model.cables, model.liners
    pts = np.concatenate([cb.node_pos, ln.node_pos])
    disp = pts - np.concatenate([cb.node_pos0, ln.node_pos0])
    nc = cb.node_pos.shape[0]
    conn = np.concatenate([np.column_stack([cb.seg_a, cb.seg_b]),
                           np.column_stack([ln.el_a, ln.el_b]) + nc]).astype(np.int64)
    ns, ne = cb.seg_a.size, ln.el_a.size
    fields = {"support": np.repeat([0, 1], [ns, ne]),
              "element": np.concatenate([cb.seg_cable, ln.el_liner]),
              "axial_force": np.concatenate([cb.seg_force, ln.el_force[:, 0]]),
              "moment": np.concatenate([np.full(ns, np.nan),
                                        np.abs(ln.el_force[:, 1:]).max(axis=1, initial=0.0)]),
              "state": np.concatenate([cb.seg_state, ln.el_state])}
    return pts, disp, [("line", conn)], [ns + ne], fields


def _rows(fields, kind, first, n) -> dict:
    """Every cell field for ``n`` cells of one kind from row ``first`` of that kind's
    ``fields``: NaN (floats) or -1 (integers) for a field the kind does not have."""
    out = {}
    for name, width in _FLOAT.items():
        v = fields.get(name)
        out[name] = np.full((n, width) if width > 1 else n, np.nan) if v is None else \
            np.asarray(v, np.float64)[first:first + n]
    for name in _INT:
        v = fields.get(name, kind if name == "kind" else -1)
        v = np.broadcast_to(v, n) if np.ndim(v) == 0 else np.asarray(v)[first:first + n]
        out[name] = v.astype(np.int32)
    return out


def vtk_mesh(model) -> meshio.Mesh:
    """The model's blocks, contacts, cracks and support as one ``meshio.Mesh`` (module
    docstring)."""
    points, disp, cells, data = [], [], [], {k: [] for k in (*_FLOAT, *_INT)}
    start = 0
    for kind, part in ((KIND_BLOCK, _blocks), (KIND_CONTACT, _contacts), (KIND_CRACK, _cracks),
                       (KIND_SUPPORT, _support)):
        pts, u, cblocks, counts, fields = part(model)
        first = 0
        for (ctype, conn), n in zip(cblocks, counts):
            if n:
                cells.append((ctype, conn + start))
                for name, v in _rows(fields, kind, first, n).items():
                    data[name].append(v)
                first += n
        points.append(pts)
        disp.append(u)
        start += len(pts)
    return meshio.Mesh(_vec3(np.concatenate(points)), cells, cell_data=data,
                       point_data={"vertex_displacement": _vec3(np.concatenate(disp))})


def write_vtk(model, path, field_data=None) -> Path:
    """Write the model's current state to ``path`` (.vtu, binary, zlib) for ParaView; returns
    the path. Fields and conventions: the module docstring; the file's field data names the
    integer codes (``legend_field_data``) and holds ``field_data`` (name -> number, e.g. the
    stage or the search level it shows)."""
    path = Path(path)
    if path.suffix != ".vtu":
        raise ValueError(f"write_vtk writes an unstructured grid: the path must end in .vtu, "
                         f"got {str(path)!r}")
    meshio.write(path, vtk_mesh(model), file_format="vtu")
    _add_field_data(path, {**legend_field_data(model), **{
        str(k): np.atleast_1d(np.asarray(v, np.float64)) for k, v in (field_data or {}).items()}})
    return path


def legend_field_data(model) -> dict:
    """The names of the integer codes as VTK field data: for each code of ``kind``,
    ``support``, ``group``, ``region``, ``material``, ``mode`` and ``state`` (``legend``) an
    array named "<field> <code>: <name>" holding the code, so ParaView's Information panel
    lists them. (Named arrays, not VTK string arrays: meshio, which reads the files back,
    does not read string arrays.)"""
    names = legend(model)
    out = {}
    for key in ("kind", "support", "group", "region", "material", "mode"):
        items = names[key].items() if isinstance(names[key], dict) else enumerate(names[key])
        for code, name in items:
            out[f"{key} {code}: {name}"] = np.array([int(code)], np.int32)
    contact, support = names["state"], names["support_state"]
    for code in range(max(len(contact), len(support))):
        words = [f"{what} {n[code]}" for what, n in (("contact", contact), ("support", support))
                 if code < len(n)]
        out[f"state {code}: {'; '.join(words)}"] = np.array([code], np.int32)
    return out


def _add_field_data(path, arrays) -> None:
    """Put ``arrays`` (name -> 1-D int32 or float64 array) into the .vtu at ``path`` as the
    grid's FieldData (meshio 5 reads field data but does not write it)."""
    rows = []
    for name, v in arrays.items():
        kind = "Int32" if v.dtype == np.int32 else "Float64"
        text = " ".join(str(int(x)) if kind == "Int32" else repr(float(x)) for x in v)
        rows.append(f'<DataArray type="{kind}" Name={quoteattr(name)} '
                    f'NumberOfTuples="{v.size}" format="ascii">{text}</DataArray>\n')
    text = path.read_text()
    head, sep, tail = text.partition("<UnstructuredGrid>\n")
    if not sep:
        raise ValueError(f"{str(path)!r}: no <UnstructuredGrid> to hold the field data")
    path.write_text(head + sep + "<FieldData>\n" + "".join(rows) + "</FieldData>\n" + tail)


def legend(model) -> dict:
    """The names behind the integer fields: kinds, groups, regions, materials, states (a
    contact's ``state``; a support element's ``support_state``), modes."""
    return {"kind": ["block", "contact", "crack", "support"], "support": ["cable", "liner"],
            "group": list(model.blocks.groups),
            "region": list(model.blocks.region_names), "material": list(model.table.names),
            "state": ["intact", "slipping", "broken in tension", "broken in shear", "unbonded"],
            "support_state": ["elastic", "yielded", "ruptured (cables)"],
            "mode": {"1": "tension", "2": "shear"},
            "units": {"displacement": "m", "velocity": "m/s", "rotation": "rad (CCW +)",
                      "angular_velocity": "rad/s", "sn": "Pa (compression +)", "ts": "Pa",
                      "time": "s", "axial_force": "N/m (tension +)", "moment": "N m/m",
                      "damage": "- (0 intact, 1 fully softened)"}}


class VtkSeries:
    """A time series for ParaView: ``folder/<name>_0000.vtu, ...`` and ``folder/<name>.pvd``.

    ``add(model, time=None)`` writes the next file and rewrites the .pvd collection (so a run
    that stops early still leaves a readable series), with ``time`` = the model time (s) unless
    another value is given (e.g. the g-level of a centrifuge ramp, so ParaView's time axis is
    the load). Open the .pvd in ParaView; ``<name>_legend.json`` names the integer codes.
    ``VtkSeries.reopen`` goes on with a series an interrupted run left.
    """

    def __init__(self, folder, name: str = "model"):
        self.folder = Path(folder)
        self.name = str(name)
        self.entries = []           # (time, file name)
        self.folder.mkdir(parents=True, exist_ok=True)

    @classmethod
    def reopen(cls, folder, name: str = "model", until: float = float("inf")) -> "VtkSeries":
        """The series in ``folder`` named ``name`` with its members up to the first whose time
        exceeds ``until`` (a resumed run goes on from there: the next ``add`` follows them);
        an empty series if there is none."""
        import xml.etree.ElementTree as ET

        series = cls(folder, name)
        if series.pvd.exists():
            for item in ET.parse(series.pvd).getroot().iter("DataSet"):
                t = float(item.get("timestep"))
                if t > until:
                    break
                series.entries.append((t, item.get("file")))
        return series

    @property
    def pvd(self) -> Path:
        return self.folder / f"{self.name}.pvd"

    def add(self, model, time=None, field_data=None) -> Path:
        """Write the model's state as the next member of the series (``field_data``:
        ``write_vtk``'s); returns its path."""
        t = float(model.time if time is None else time)
        if not np.isfinite(t):
            raise ValueError(f"time of a series member must be finite, got {time!r}")
        if not self.entries:
            (self.folder / f"{self.name}_legend.json").write_text(json.dumps(legend(model),
                                                                             indent=1))
        path = write_vtk(model, self.folder / f"{self.name}_{len(self.entries):04d}.vtu",
                         field_data)
        self.entries.append((t, path.name))
        rows = "".join(f'    <DataSet timestep="{t!r}" group="" part="0" file={quoteattr(f)}/>\n'
                       for t, f in self.entries)
        self.pvd.write_text('<?xml version="1.0"?>\n<VTKFile type="Collection" version="0.1">\n'
                            f"  <Collection>\n{rows}  </Collection>\n</VTKFile>\n")
        return path
