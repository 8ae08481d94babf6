"""ParaView output of a ``ContinuumModel`` through DOLFINx 0.5.2's own ``XDMFFile``.

Why XDMF: in 0.5.2, ``dolfinx.io.VTKFile`` refuses a P1 vector together with DG0 tensors in
one write ("All point-wise Functions written to VTK file must have same element"), writes
``.vtu`` files of version 2.2 that meshio cannot read, and a DG0 3 x 3 tensor through
``XDMFFile`` comes out as node data: so the stress is a DG0 2 x 2 tensor plus ``stress_zz``.

Fields (SI; the **continuum's sign convention: tension positive**, the opposite of the DEM's
contact ``sn``):

- ``displacement`` (m): P1 vector at the mesh vertices (the P2 solution there; XDMF pads it to
  3 components, z = 0).
- ``stress`` (Pa): DG0 2 x 2 tensor [[xx, xy], [xy, yy]], the average over each cell's
  quadrature points of the converged stress (effective stress where a pore pressure is set);
  XDMF pads it to 9 components (xx, xy, 0, xy, yy, 0, 0, 0, 0).
- ``stress_zz`` (Pa): DG0, the plane-strain out-of-plane stress.
- ``yield_shear``, ``yield_tension`` (-): DG0, fraction 0..1 of each cell's quadrature points
  that have yielded in shear / in tension (``ContinuumModel.yield_indicator``: over the whole
  loading history unless ``ever=False``).
- ``yield`` (-): DG0 code, 0 elastic, 1 shear, 2 tension, 3 both (the colours of
  ``continuum_ref.plot.plot_yield``).
- ``pore_pressure`` (Pa, compression positive): DG0 cell average, 0 without water.

``write_xdmf(model, path)`` writes one state; ``XdmfSeries(path, model)`` keeps the file open
and ``add(model, time)`` appends a state (time: any increasing load parameter, e.g. the g-level).
The default encoding writes ``path`` (.xdmf, light XML) plus ``path.with_suffix(".h5")`` (the
data); ``encoding="ascii"`` puts the numbers inline in the .xdmf (small meshes, tests).
The DOLFINx calls here (``XDMFFile``, ``TensorFunctionSpace``, ``interpolate``) are 0.5.2's.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np
from dolfinx import fem, io

from ._dolfinx05 import compiler_log

__all__ = ["write_xdmf", "XdmfSeries", "FIELDS"]

FIELDS = ("displacement", "stress", "stress_zz", "yield_shear", "yield_tension", "yield",
          "pore_pressure")
_ENCODINGS = {"hdf5": io.XDMFFile.Encoding.HDF5, "ascii": io.XDMFFile.Encoding.ASCII}


class XdmfSeries:
    """An open XDMF file holding the mesh of ``model`` and, per ``add``, its fields."""

    def __init__(self, path, model, encoding: str = "hdf5", ever: bool = True):
        path = Path(path)
        if path.suffix != ".xdmf":
            raise ValueError(f"path must end in .xdmf, got {str(path)!r}")
        if encoding not in _ENCODINGS:
            raise ValueError(f"encoding must be one of {sorted(_ENCODINGS)}, got {encoding!r}")
        path.parent.mkdir(parents=True, exist_ok=True)
        self.path, self.ever, self.count = path, bool(ever), 0
        msh = model.mesh
        self._file = io.XDMFFile(msh.comm, str(path), "w", encoding=_ENCODINGS[encoding])
        self._file.write_mesh(msh)
        degree = msh.geometry.cmap.degree
        with compiler_log():
            self._u = fem.Function(fem.VectorFunctionSpace(msh, ("CG", degree)),
                                   name="displacement")
            self._stress = fem.Function(fem.TensorFunctionSpace(msh, ("DG", 0)), name="stress")
            dg0 = fem.FunctionSpace(msh, ("DG", 0))
        self._scalars = {name: fem.Function(dg0, name=name) for name in FIELDS[2:]}
        self._mesh = msh

    def add(self, model, time=None):
        """Write the fields of ``model``'s last converged state at ``time`` (default: the
        number of states written before, 0, 1, 2, ...)."""
        if model.mesh is not self._mesh:
            raise ValueError("a series holds one mesh: this model has another")
        t = float(self.count if time is None else time)
        self._u.interpolate(model.u)
        cells = np.asarray(model._cells)
        s = model.stress()                                # (ncells, 4): xx, yy, zz, xy
        _set_cells(self._stress, cells, s[:, [0, 3, 3, 1]])
        ind = model.yield_indicator(ever=self.ever)
        values = {"stress_zz": s[:, 2], "yield_shear": ind["shear"],
                  "yield_tension": ind["tension"],
                  "yield": (ind["shear"] > 0) + 2.0 * (ind["tension"] > 0),
                  "pore_pressure": model.cell_average(model.pore_pressure())}
        for name, f in self._scalars.items():
            _set_cells(f, cells, values[name])
        for f in (self._u, self._stress, *self._scalars.values()):
            self._file.write_function(f, t)
        self.count += 1

    def close(self):
        self._file.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


def _set_cells(f, cells, values):
    """DG0 Function ``f``: the value of each cell of ``cells`` (owned and ghost) from
    ``values`` (len(cells), block size), placed through the dofmap."""
    bs = f.function_space.dofmap.index_map_bs
    dofs = np.asarray(f.function_space.dofmap.list.array)[cells]
    f.x.array.reshape(-1, bs)[dofs] = np.asarray(values, dtype=float).reshape(len(cells), bs)


def write_xdmf(model, path, time: float = 0.0, encoding: str = "hdf5", ever: bool = True) -> Path:
    """Write ``model``'s displacement, stress and yield indicators to ``path`` (.xdmf; with
    ``encoding="hdf5"`` also the .h5 beside it) for ParaView; returns the path."""
    with XdmfSeries(path, model, encoding, ever) as series:
        series.add(model, time)
    return Path(path)
