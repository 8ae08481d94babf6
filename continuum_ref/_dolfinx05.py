"""Every call that depends on the DOLFINx version (written for Debian's 0.5.2) lives here.

When the project moves to a newer DOLFINx, this is the module to port: `model_to_mesh`
(gmshio signature), quadrature elements (basix.ufl in >= 0.7), Expression.eval (mesh argument
in >= 0.8), `form_compiler_params` (renamed `form_compiler_options` in 0.6) and geometry queries.
"""
import contextlib
import logging
from pathlib import Path

import basix
import numpy as np
import ufl
from dolfinx import fem, geometry
from dolfinx.fem import petsc as fem_petsc
from dolfinx.io import gmshio
from mpi4py import MPI
from petsc4py import PETSc

__all__ = ["compile_form", "compiler_log", "model_to_mesh", "quadrature_space", "quadrature_points", "quadrature_measure",
           "compile_expression", "eval_expression", "block_index", "local_cells",
           "cells_containing", "create_matrix", "create_vector", "assemble_matrix",
           "assemble_residual", "assemble_vector_plain", "keep_cell_dofs", "lu_solver",
           "facet_tags", "scalar"]


def model_to_mesh(model, gdim=2):
    """Read the current gmsh model (on rank 0) into a distributed DOLFINx mesh and tags."""
    with compiler_log():
        return gmshio.model_to_mesh(model, MPI.COMM_WORLD, 0, gdim=gdim)


def quadrature_space(mesh, degree, dim):
    """Function space of `dim` values at every quadrature point (degree `degree`) of each cell."""
    element = ufl.VectorElement("Quadrature", mesh.ufl_cell(), degree=degree, dim=dim,
                                quad_scheme="default")
    with compiler_log():
        return fem.FunctionSpace(mesh, element)


def quadrature_points(degree):
    """Reference points (nq, 2) and weights (nq,) of the default triangle rule."""
    return basix.make_quadrature(basix.CellType.triangle, degree)


def quadrature_measure(mesh, degree, subdomain_data=None):
    """Cell measure matching the quadrature space (same scheme and degree)."""
    return ufl.Measure("dx", domain=mesh, subdomain_data=subdomain_data,
                       metadata={"quadrature_degree": degree, "quadrature_scheme": "default"})


def compile_expression(expr, points):
    """JIT-compile a UFL expression for evaluation at reference `points`."""
    with compiler_log():
        return fem.Expression(expr, points)


def compile_form(form):
    """``fem.form(form)``: JIT-compile a UFL form (``compiler_log`` keeps the compiler's lines
    off the console)."""
    with compiler_log():
        return fem.form(form)


@contextlib.contextmanager
def compiler_log():
    """While forms and elements compile, the compiler's lines go to ``<DOLFINx JIT
    cache>/compile.log`` instead of the console.

    What is not in the JIT cache yet is built by cffi through distutils, which sets the root
    logger to INFO and logs every compiler command through it; ffcx installs a stderr handler
    on the root logger when it is imported (``logging.basicConfig()``), so a first run prints
    dozens of ``INFO:root:x86_64-linux-gnu-gcc ...`` lines. Meanwhile the root logger's own
    records under WARNING (distutils') are kept off its handlers by a filter and written to
    the file; its level is restored afterwards. Named loggers and warnings pass as before."""
    root = logging.getLogger()
    level, handlers = root.level, list(root.handlers)
    chatter = _RootChatter()
    for h in handlers:
        h.addFilter(chatter)
    try:
        from dolfinx import jit
        path = Path(jit.get_parameters()["cache_dir"]) / "compile.log"
        path.parent.mkdir(parents=True, exist_ok=True)
        log = logging.FileHandler(path, delay=True)
    except (OSError, KeyError, ImportError):
        log = logging.NullHandler()
    log.addFilter(lambda record: not chatter.filter(record))
    root.addHandler(log)
    try:
        yield
    finally:
        root.removeHandler(log)
        log.close()
        for h in handlers:
            h.removeFilter(chatter)
        root.setLevel(level)


class _RootChatter(logging.Filter):
    """Rejects the root logger's own records under WARNING (the compiler's lines)."""

    def filter(self, record):
        return not (record.name == "root" and record.levelno < logging.WARNING)


def eval_expression(compiled, cells):
    """Values (len(cells) * nq, value_size) of a compiled Expression, cell-major."""
    values = compiled.eval(cells)
    return values.reshape(len(cells) * compiled.X().shape[0], -1)


def local_cells(mesh):
    """Indices of owned and ghost cells on this process."""
    imap = mesh.topology.index_map(mesh.topology.dim)
    return np.arange(imap.size_local + imap.num_ghosts, dtype=np.int32)


def block_index(space, num_cells):
    """Block (point) index in a quadrature Function for each (cell, point), cell-major."""
    count = num_cells * _points_per_cell(space)
    return np.asarray(space.dofmap.list.array, dtype=np.int64)[:count]


def _points_per_cell(space):
    return space.dofmap.cell_dofs(0).size


def cells_containing(mesh, points):
    """One cell index per point (-1 where no local cell contains it). points: (n, 2)."""
    pts = np.zeros((len(points), 3))
    pts[:, :2] = np.asarray(points, dtype=float)
    tree = geometry.BoundingBoxTree(mesh, mesh.topology.dim)
    candidates = geometry.compute_collisions(tree, pts)
    colliding = geometry.compute_colliding_cells(mesh, candidates, pts)
    cells = np.full(len(pts), -1, dtype=np.int32)
    for i in range(len(pts)):
        links = colliding.links(i)
        if len(links):
            cells[i] = links[0]
    return pts, cells


def facet_tags(mesh, marked):
    """MeshTags of boundary facets: marked is a list of (tag, predicate on x (2|3, n))."""
    from dolfinx import mesh as dmesh
    fdim = mesh.topology.dim - 1
    indices, values = [], []
    for tag, predicate in marked:
        facets = dmesh.locate_entities_boundary(mesh, fdim, predicate)
        indices.append(facets)
        values.append(np.full(len(facets), tag, dtype=np.int32))
    if not indices:
        return dmesh.meshtags(mesh, fdim, np.zeros(0, np.int32), np.zeros(0, np.int32))
    idx = np.concatenate(indices).astype(np.int32)
    val = np.concatenate(values)
    order = np.argsort(idx, kind="stable")
    idx, val = idx[order], val[order]
    if len(np.unique(idx)) != len(idx):
        raise ValueError("a boundary facet was marked by two traction predicates")
    return dmesh.meshtags(mesh, fdim, idx, val)


def scalar(mesh, value):
    """A fem.Constant (keep a reference: reading a temporary Constant is unsafe in 0.5.2)."""
    return fem.Constant(mesh, PETSc.ScalarType(value))


def create_matrix(form):
    return fem_petsc.create_matrix(form)


def create_vector(form):
    return fem_petsc.create_vector(form)


def assemble_matrix(A, form, bcs):
    """Assemble into an existing matrix with Dirichlet rows/columns set to identity."""
    A.zeroEntries()
    fem_petsc.assemble_matrix(A, form, bcs=bcs)
    A.assemble()
    return A


def assemble_residual(b, form, jacobian_form, bcs, x0, scale=-1.0, extra=None):
    """Residual vector with the Newton lifting: Dirichlet entries become scale*(x0 - g).
    ``extra`` = (alpha, vector): alpha * vector (an assembled nodal force) is added to the
    free entries."""
    with b.localForm() as loc:
        loc.set(0.0)
    fem_petsc.assemble_vector(b, form)
    if bcs:
        fem_petsc.apply_lifting(b, [jacobian_form], bcs=[bcs], x0=[x0], scale=scale)
    b.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
    if extra is not None:
        b.axpy(*extra)
    if bcs:
        fem_petsc.set_bc(b, bcs, x0, scale)
    return b


def assemble_vector_plain(b, form, extra=None):
    """Assemble a vector without boundary conditions (for reactions); ``extra`` as in
    `assemble_residual`."""
    with b.localForm() as loc:
        loc.set(0.0)
    fem_petsc.assemble_vector(b, form)
    b.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
    if extra is not None:
        b.axpy(*extra)
    return b


def keep_cell_dofs(b, space, cells):
    """Zero the entries of vector ``b`` (of ``space``, owned and ghost) at every dof that no
    cell of ``cells`` touches."""
    dofmap = space.dofmap
    bs = dofmap.index_map_bs
    blocks = np.asarray(dofmap.list.array).reshape(-1, dofmap.cell_dofs(0).size)[cells]
    keep = np.zeros(dofmap.index_map.size_local + dofmap.index_map.num_ghosts, dtype=bool)
    keep[blocks.ravel()] = True
    with b.localForm() as loc:
        loc.array[~np.repeat(keep, bs)] = 0.0
    return b


def lu_solver(A):
    """Direct solver: MUMPS when PETSc was built with it, else PETSc's own LU."""
    ksp = PETSc.KSP().create(A.getComm())
    ksp.setOperators(A)
    ksp.setType("preonly")
    pc = ksp.getPC()
    pc.setType("lu")
    if PETSc.Sys.hasExternalPackage("mumps"):
        pc.setFactorSolverType("mumps")
    return ksp


def solve_linear(ksp, A, b, x) -> bool:
    """Solve A x = b with ``ksp``; False (instead of an exception) when the factorisation or
    the solve fails (PETSc error, e.g. MUMPS error 76, or a diverged reason)."""
    from petsc4py import PETSc

    try:
        ksp.setOperators(A)
        ksp.solve(b, x)
    except PETSc.Error:
        return False
    return ksp.getConvergedReason() >= 0
