"""Smoke test of the environment the set-up made: every stack the toolkit needs works together.

The DOLFINx check solves -u'' = 1 on a gmsh-made unit square with u = 0 on x = 0 and x = 1 and
natural conditions on the other sides; the exact solution u = x (1 - x) / 2 is quadratic, so P2
elements reproduce it to round-off.
"""
import subprocess
import sys

import numpy as np
import pytest


def test_dem_core_imports_without_dolfinx_or_gmsh():
    # A fresh interpreter in which dolfinx and gmsh imports are made to fail.
    code = (
        "import sys\n"
        "class Block:\n"
        "    def find_spec(self, name, path=None, target=None):\n"
        "        if name.split('.')[0] in ('dolfinx', 'gmsh', 'ufl', 'petsc4py'):\n"
        "            raise ImportError('blocked ' + name)\n"
        "sys.meta_path.insert(0, Block())\n"
        "import dem_core\n"
        "assert 'dolfinx' not in sys.modules and 'gmsh' not in sys.modules\n"
    )
    subprocess.run([sys.executable, "-c", code], check=True)


def test_packages_import():
    import comparisons  # noqa: F401
    import continuum_ref  # noqa: F401
    import dem_core  # noqa: F401


def test_numba_compiles_and_runs():
    from numba import njit

    @njit(cache=False)
    def dot(a, b):
        s = 0.0
        for i in range(a.size):
            s += a[i] * b[i]
        return s

    a = np.arange(10.0)
    assert dot(a, a) == pytest.approx(float(a @ a))


def _gmsh_unit_square(h):
    import gmsh

    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.model.add("square")
    gmsh.model.occ.addRectangle(0.0, 0.0, 0.0, 1.0, 1.0)
    gmsh.model.occ.synchronize()
    gmsh.model.addPhysicalGroup(2, [1], 1)
    gmsh.option.setNumber("Mesh.CharacteristicLengthMax", h)
    gmsh.model.mesh.generate(2)
    return gmsh


def test_dolfinx_poisson_on_gmsh_mesh_matches_closed_form():
    from mpi4py import MPI

    import ufl
    from dolfinx import fem
    from dolfinx.fem.petsc import LinearProblem
    from dolfinx.io import gmshio

    gmsh = _gmsh_unit_square(0.25)
    try:
        mesh, _, _ = gmshio.model_to_mesh(gmsh.model, MPI.COMM_WORLD, 0, gdim=2)
    finally:
        gmsh.finalize()
    V = fem.FunctionSpace(mesh, ("CG", 2))
    u, v = ufl.TrialFunction(V), ufl.TestFunction(V)
    facets = fem.locate_dofs_geometrical(
        V, lambda x: np.isclose(x[0], 0.0) | np.isclose(x[0], 1.0))
    bc = fem.dirichletbc(np.float64(0.0), facets, V)
    f = fem.Constant(mesh, np.float64(1.0))
    problem = LinearProblem(ufl.inner(ufl.grad(u), ufl.grad(v)) * ufl.dx, f * v * ufl.dx,
                            bcs=[bc], petsc_options={"ksp_type": "preonly", "pc_type": "lu"})
    uh = problem.solve()
    x = V.tabulate_dof_coordinates()[:, 0]
    exact = x * (1.0 - x) / 2.0
    assert np.max(np.abs(uh.x.array - exact)) < 1e-10
    assert np.max(exact) == pytest.approx(0.125, rel=0.05)  # the mesh really spans the square
