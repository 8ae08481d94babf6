"""Plane-strain elasto-plastic continuum model on a DOLFINx mesh (P2 displacements).

Signs and units: stresses in Pa, **tension positive** in the FE state (Mandel vectors
[xx, yy, zz, sqrt(2) xy] at quadrature points); the in-situ ratio K0 = sigma_h / sigma_v and the
strength parameters use the rock-mechanics convention (compression positive) as documented in
`materials`. Displacements in m, x horizontal, y up; gravity acts in -y.

Loads are driven by load parameters so that every loading (gravity level, traction scale,
prescribed displacement scale, excavation release) uses the same stepping with step cutting
(`newton.load_path`). The model keeps the last converged state (displacement, stress, strain,
yield history); a failed step restores it.

Excavation (`excavate`): the removed cells become a soft elastic "void" (E x 1e-6, no weight,
no stress, no pore pressure) and the forces they exerted on the remaining body (their total
stress and weight, as nodal forces at the nodes they share with it) are applied to it and
released, (1 - t) f_exc with the release factor t = 0 -> 1: the excavation-load method on a
fixed mesh (Ghaboussi & Pecknold 1984, "Incremental finite element analysis of geometrically
altered structures"; Brown & Booker 1985, "Finite element analysis of excavation").

Pore pressure (`set_pore_pressure`): effective stress (Terzaghi). The plasticity and the
stored state (`sig_n`) are effective stresses sigma'; equilibrium uses the total stress
sigma = sigma' - p m, m = [1, 1, 1, 0] (Mandel, tension positive, p compression positive), and
the weight is the total (saturated where wet) density. p is given at 1 g and scales with the
g-level like the weight (hydrostatic water in a centrifuge weighs N times more).
"""
import math
from dataclasses import dataclass

import numpy as np
import ufl
from dolfinx import fem, mesh as dmesh
from petsc4py import PETSc

from . import _dolfinx05 as dx
from . import return_mapping as rm
from .materials import Elastic
from .newton import NewtonSettings, load_path, newton, relax
from .supports import check_supported
from dem_core.units import STANDARD_GRAVITY

__all__ = ["ContinuumModel", "StageResult"]

GRAVITY = STANDARD_GRAVITY     # m/s2 (dem_core.units: one g for both methods)
VOID_STIFFNESS = 1e-6


@dataclass
class StageResult:
    """Outcome of one loading stage.

    Attributes
    ----------
    converged : bool
        True if the target load was reached.
    load_reached : float
        Last converged value of the stage's load parameter.
    failed_at : float or None
        Smallest value that did not converge after step cutting.
    steps : int
        Converged load steps.
    newton_iterations : int
        Total Newton iterations of converged steps.
    displacement : dict
        Monitoring-point name -> (ux, uy) change over the stage (m).
    """

    converged: bool
    load_reached: float
    failed_at: float
    steps: int
    newton_iterations: int
    displacement: dict


def _eps_mandel(w):
    e = ufl.sym(ufl.grad(w))
    return ufl.as_vector([e[0, 0], e[1, 1], 0.0, math.sqrt(2.0) * e[0, 1]])


class ContinuumModel:
    """Plane-strain continuum (elastic, Mohr-Coulomb, Hoek-Brown) for slopes and specimens.

    Parameters
    ----------
    mesh_data : continuum_ref.mesh.MeshData
    materials : dict name -> material, or one material for every cell
        Applied in dict order; a later name overrides earlier ones on shared cells (put weak
        bands last). Materials from `continuum_ref.materials`.
    density : dict name -> kg/m3, or one value
    degree : int
        Polynomial degree of the displacement (2 recommended: P1 locks in plastic flow).
    newton : NewtonSettings, optional
    """

    def __init__(self, mesh_data, materials, density, degree=2, newton_settings=None):
        self.mesh_data = mesh_data
        self.mesh = msh = mesh_data.mesh
        self.newton_settings = newton_settings or NewtonSettings()
        self._cells = dx.local_cells(msh)
        ncells = len(self._cells)
        self.materials, self._cell_material = self._assign(materials, ncells, "materials")
        rho_list, rho_index = self._assign(density, ncells, "density")
        rho_cell = np.array(rho_list, dtype=float)[rho_index]
        if np.any(~np.isfinite(rho_cell)) or np.any(rho_cell < 0):
            raise ValueError(f"density must be finite and >= 0, got {rho_list}")
        # Spaces and state.
        with dx.compiler_log():                    # each space compiles its element once
            self.V = fem.VectorFunctionSpace(msh, ("CG", degree))
            dg0 = fem.FunctionSpace(msh, ("DG", 0))
        self._qdeg = 2 * (degree - 1) if degree > 1 else 1
        self._qdeg = max(self._qdeg, 1)
        qpts, self._qwts = dx.quadrature_points(self._qdeg)
        self._nq = len(qpts)
        self._W4 = W4 = dx.quadrature_space(msh, self._qdeg, 4)
        W16 = dx.quadrature_space(msh, self._qdeg, 16)
        self._b4, self._b16 = dx.block_index(W4, ncells), dx.block_index(W16, ncells)
        self.u = fem.Function(self.V, name="displacement")
        self._sig = fem.Function(W4)
        self._tan = fem.Function(W16)
        self.rho = fem.Function(dg0)
        self.rho.x.array[: ncells] = rho_cell
        npts = ncells * self._nq
        self._point_material = np.repeat(self._cell_material, self._nq)
        self.sig_n = np.zeros((npts, 4))           # converged stress (Mandel, tension +)
        self.eps_n = np.zeros((npts, 4))           # converged total strain
        self._sig_now = np.zeros((npts, 4))
        self.mode = np.zeros(npts, dtype=np.int64)          # yield mode at the last solve
        self.mode_ever = np.zeros(npts, dtype=np.int64)     # bitwise OR over the history
        self._mode_now = np.zeros(npts, dtype=np.int64)
        self._qp_xy = self._quadrature_coordinates(qpts)
        # Loads.
        self.g_level = 0.0
        self._g_vec = fem.Constant(msh, PETSc.ScalarType((0.0, 0.0)))
        self._dirichlet = []                       # (dofs, sub, Constant, base value)
        self._tractions = []                       # (tag, predicate, Constant, base vector)
        self._load_scale = 0.0                     # scales prescribed values and tractions
        self._release_force = None                 # f_exc of `excavate` (PETSc Vec, N)
        self._release = 0.0                        # release factor t of `excavate`
        self._exc_form = None                      # (form, stress, density) giving f_exc
        self._pore = None                          # pore pressure at 1 g (npts,), Pa
        self._pore_fn = None                       # -g p m at quadrature points (forms)
        self.history = {name: [] for name in mesh_data.points}
        self._forms = None
        self._elastic = None                       # (key, matrix, solver) of K_e (relaxation)
        self._qpts = qpts

    # ------------------------------------------------------------------ set-up
    def _assign(self, spec, ncells, what):
        if not isinstance(spec, dict):
            return [spec], np.zeros(ncells, dtype=np.int64)
        values, index = [], np.full(ncells, -1, dtype=np.int64)
        for name, value in spec.items():
            index[self.mesh_data.cells(name)] = len(values)
            values.append(value)
        if np.any(index < 0):
            raise ValueError(f"{what}: {np.sum(index < 0)} cells are covered by none of "
                             f"{list(spec)}; known names: {sorted(self.mesh_data.tags)}")
        return values, index

    def _quadrature_coordinates(self, qpts):
        geo = self.mesh.geometry
        nodes = geo.dofmap.array.reshape(-1, geo.dofmap.offsets[1] - geo.dofmap.offsets[0])
        xy = geo.x[nodes[self._cells, :3], :2]                  # (ncells, 3, 2) vertices
        shape = np.stack([1 - qpts[:, 0] - qpts[:, 1], qpts[:, 0], qpts[:, 1]], axis=1)
        return np.einsum("pv,cvd->cpd", shape, xy).reshape(-1, 2)

    def fix(self, where, components=(0, 1), value=None):
        """Prescribe displacement on boundary facets where `where(x)` is True.

        Parameters
        ----------
        where : callable x (3, n) -> bool (n,)
        components : tuple of 0 (x) and/or 1 (y)
        value : sequence of float, optional
            Displacement per component (m), multiplied by the load scale of `solve_load`;
            default 0 (fixed).
        """
        fdim = self.mesh.topology.dim - 1
        facets = dmesh.locate_entities_boundary(self.mesh, fdim, where)
        if len(facets) == 0:
            raise ValueError("fix(): the predicate selects no boundary facet")
        values = [0.0] * len(components) if value is None else list(value)
        for comp, val in zip(components, values):
            sub = self.V.sub(comp)
            dofs = fem.locate_dofs_topological(sub, fdim, facets)
            const = fem.Constant(self.mesh, PETSc.ScalarType(0.0))
            self._dirichlet.append((fem.dirichletbc(const, dofs, sub), const, float(val), dofs))
        self._update_boundary_values()

    def add_traction(self, where, traction):
        """Distributed load (Pa = N/m2) on boundary facets where `where(x)`; scaled by the load
        scale of `solve_load`. traction: (tx, ty), e.g. (0, -q) pushes down on a top face."""
        tag = len(self._tractions) + 1
        const = fem.Constant(self.mesh, PETSc.ScalarType((0.0, 0.0)))
        self._tractions.append((tag, where, const, np.asarray(traction, dtype=float)))
        self._forms = None                          # the residual form changes
        self._update_boundary_values()

    def _update_boundary_values(self):
        for _, const, val, _ in self._dirichlet:
            const.value = val * self._load_scale
        for _, _, const, vec in self._tractions:
            const.value = vec * self._load_scale

    def _build_forms(self):
        msh, v, du = self.mesh, ufl.TestFunction(self.V), ufl.TrialFunction(self.V)
        dxq = dx.quadrature_measure(msh, self._qdeg)
        sig = self._sig
        C = ufl.as_matrix([[self._tan[4 * i + j] for j in range(4)] for i in range(4)])
        F = ufl.inner(sig, _eps_mandel(v)) * dxq - ufl.inner(self.rho * self._g_vec, v) * ufl.dx
        if self._pore is not None:                 # total stress = effective - p m
            self._pore_fn = fem.Function(self._W4)
            self._update_pore_values()
            F += ufl.inner(self._pore_fn, _eps_mandel(v)) * dxq
        if self._tractions:
            tags = dx.facet_tags(msh, [(tag, where) for tag, where, _, _ in self._tractions])
            ds = ufl.Measure("ds", domain=msh, subdomain_data=tags)
            for tag, _, const, _ in self._tractions:
                F -= ufl.inner(const, v) * ds(tag)
        J = ufl.inner(ufl.dot(C, _eps_mandel(du)), _eps_mandel(v)) * dxq
        self._F, self._J = dx.compile_form(F), dx.compile_form(J)
        self._eps_expr = dx.compile_expression(_eps_mandel(self.u), self._qpts)
        self._A = dx.create_matrix(self._J)
        self._b = dx.create_vector(self._F)
        self._b_plain = dx.create_vector(self._F)
        self._du = fem.Function(self.V)
        self._ksp = dx.lu_solver(self._A)
        self._forms = True

    # ------------------------------------------------------------------ state
    def _bcs(self):
        return [bc for bc, _, _, _ in self._dirichlet]

    def _constrained_dofs(self):
        """Indices (into the flat dof array) of every prescribed displacement component."""
        out = [np.asarray(dofs, dtype=np.int64) for _, _, _, dofs in self._dirichlet]
        return np.unique(np.concatenate(out)) if out else np.zeros(0, dtype=np.int64)

    def _trial_stress(self):
        eps = dx.eval_expression(self._eps_expr, self._cells)
        return eps, self.sig_n, eps - self.eps_n

    def _update_stress(self, tangent=True):
        """Return map at every quadrature point from the current displacement (tangent=False:
        stresses only, the stored tangent is left as it was)."""
        self._eps_now, sig_n, deps = self._trial_stress()
        sig = np.empty_like(sig_n)
        tan = np.empty((sig.shape[0], 4, 4)) if tangent else None
        mode = np.zeros(sig.shape[0], dtype=np.int64)
        for k, mat in enumerate(self.materials):
            pts = self._point_material == k
            if not pts.any():
                continue
            De = rm.elastic_tangent(mat.E, mat.nu)
            sig[pts], tan_k, mode[pts] = rm.return_map(sig_n[pts] + deps[pts] @ De, mat,
                                                       tangent)
            if tangent:
                tan[pts] = tan_k
        self._sig_now, self._mode_now = sig, mode
        self._sig.x.array.reshape(-1, 4)[self._b4] = sig
        if tangent:
            self._tan.x.array.reshape(-1, 16)[self._b16] = tan.reshape(-1, 16)

    def _residual(self, tangent=True):
        self._update_stress(tangent)
        bcs = self._bcs()
        extra = None if self._release_force is None else (1.0 - self._release,
                                                           self._release_force)
        b = dx.assemble_residual(self._b, self._F, self._J, bcs, self.u.vector, extra=extra)
        plain = dx.assemble_vector_plain(self._b_plain, self._F, extra=extra)
        dofs = self._constrained_dofs()
        reaction = np.linalg.norm(plain.array[dofs]) if len(dofs) else 0.0
        # Dirichlet entries of b hold u - g: non-zero until the first correction imposes g.
        pending = len(dofs) > 0 and np.any(b.array[dofs] != 0.0)
        return b.norm(), reaction, pending

    def _solve_update(self):
        dx.assemble_matrix(self._A, self._J, self._bcs())
        self._u_prev = self.u.x.array.copy()
        if not dx.solve_linear(self._ksp, self._A, self._b, self._du.vector):
            # the tangent could not be factorised (e.g. a singular plastic tangent): this
            # Newton attempt fails (NaN residual) and the load path halves the step; a fresh
            # solver is made so the failed factorisation does not poison the retry
            self._ksp.destroy()
            self._ksp = dx.lu_solver(self._A)
            self._du.x.array[:] = np.nan
        self._du.x.scatter_forward()
        self._scale_step(1.0)

    def _scale_step(self, alpha):
        """u = u_before - alpha du: the line search's trial (``newton``)."""
        self.u.x.array[:] = self._u_prev - alpha * self._du.x.array
        self.u.x.scatter_forward()

    def _attempt(self):
        # Boundary values enter through the lifting of the first correction, with the tangent
        # of the converged state (spiking u on the boundary first would make the first tangent
        # plastic in a layer of elements that ends up elastic, and Newton then diverges).
        if self._forms is None:
            self._build_forms()
        return newton(self._residual, self._solve_update, self.newton_settings,
                      scale_step=self._scale_step)

    def _attempt_relaxed(self, settings):
        """One load step by `newton.relax`: the initial-stiffness iteration with the elastic
        stiffness of the current materials (factorised once and kept while they and the
        boundary conditions stay the same)."""
        if self._forms is None:
            self._build_forms()
        solve = self._elastic_solver()

        def correction():
            solve(self._b, self._du.vector)
            self._du.x.scatter_forward()
            return self._du.x.array.copy()

        def set_x(x):
            self.u.x.array[:] = x
            self.u.x.scatter_forward()
        return relax(lambda: self._residual(tangent=False), correction,
                     lambda: self.u.x.array.copy(), set_x, settings)

    def _elastic_solver(self):
        """K_e^{-1} as a callable (b, x): the elastic stiffness with the model's Dirichlet rows,
        assembled and factorised on first use and again when the elastic constants, the
        material of a point or the boundary conditions change."""
        key = (tuple((m.E, m.nu) for m in self.materials), self._point_material.tobytes(),
               len(self._dirichlet), id(self._J))
        if self._elastic is None or self._elastic[0] != key:
            saved = self._tan.x.array.copy()
            tan = np.empty((len(self._point_material), 4, 4))
            for k, mat in enumerate(self.materials):
                tan[self._point_material == k] = rm.elastic_tangent(mat.E, mat.nu)
            self._tan.x.array.reshape(-1, 16)[self._b16] = tan.reshape(-1, 16)
            A = dx.create_matrix(self._J)
            dx.assemble_matrix(A, self._J, self._bcs())
            self._tan.x.array[:] = saved
            ksp = dx.lu_solver(A)
            self._elastic = (key, A, ksp)
        return self._elastic[2].solve

    def _snapshot(self):
        return (self.u.x.array.copy(), self.sig_n.copy(), self.eps_n.copy(), self.mode.copy(),
                self.mode_ever.copy())

    def _commit(self):
        self.sig_n = self._sig_now.copy()
        self.eps_n = self._eps_now.copy()
        self.mode = self._mode_now.copy()
        self.mode_ever |= self.mode
        self._saved = self._snapshot()

    def _restore(self):
        u, self.sig_n, self.eps_n, self.mode, self.mode_ever = (a.copy() for a in self._saved)
        self.u.x.array[:] = u
        self.u.x.scatter_forward()

    def _record(self, t, label):
        if not self.history:
            return
        disp = self.displacement_at(list(self.mesh_data.points.values()))
        for (name, _), d in zip(self.mesh_data.points.items(), disp):
            self.history[name].append((label, t, float(d[0]), float(d[1])))

    def _run(self, label, apply, t0, t1, first_step, min_step):
        check_supported(self)          # a rigid-body motion left free: say so, not "no converge"
        if self._forms is None:
            self._build_forms()
        self._saved = self._snapshot()
        before = self._point_displacements()
        t, records, failed = load_path(apply, self._attempt, self._commit, self._restore,
                                       t0, t1, first_step, min_step,
                                       on_converged=lambda t: self._record(t, label))
        after = self._point_displacements()
        disp = {k: (after[k][0] - before[k][0], after[k][1] - before[k][1]) for k in after}
        return StageResult(failed is None, t, failed, len(records),
                           sum(r.iterations for r in records), disp)

    def _point_displacements(self):
        if not self.mesh_data.points:
            return {}
        d = self.displacement_at(list(self.mesh_data.points.values()))
        return {k: tuple(map(float, v)) for k, v in zip(self.mesh_data.points, d)}

    # ------------------------------------------------------------------ stages
    def set_gravity(self, g_level):
        """Set the body force rho * g_level * 9.81 m/s2 downwards (no solve); a pore pressure
        scales with it."""
        self.g_level = float(g_level)
        self._g_vec.value = np.array([0.0, -GRAVITY * self.g_level])
        self._update_pore_values()

    def set_pore_pressure(self, pressure):
        """Pore pressure for an effective-stress analysis (module docstring).

        Parameters
        ----------
        pressure : callable p(x, y) -> Pa, or None
            Pore pressure at 1 g, compression positive (e.g. ``dem_core.workflow.water.WaterTable(...)
            .pressure``), evaluated once at every quadrature point (zero in excavated cells: a
            void holds no water); None removes it. It is applied at the current g-level
            without a solve: set it before `solve_gravity`, or bring it in on a model at
            equilibrium with `solve_pore_pressure`. SSR then reduces the effective strength
            c', tan(phi').
        """
        if pressure is None:
            self._pore, self._pore_fn, self._forms = None, None, None
            return
        self._pore, self._forms = self._pore_values(pressure), None

    def _pore_values(self, pressure):
        x, y = self._qp_xy[:, 0], self._qp_xy[:, 1]
        p = np.broadcast_to(np.asarray(pressure(x, y), dtype=float), x.shape).copy()
        if not np.all(np.isfinite(p)):
            raise ValueError(f"pore pressure is not finite at {np.sum(~np.isfinite(p))} points")
        void = self._void_index()
        if void is not None:
            p[self._point_material == void] = 0.0
        return p

    def solve_pore_pressure(self, pressure, first_step=1.0, min_step=1e-3):
        """Change the pore pressure of a model at equilibrium to `pressure` (as in
        `set_pore_pressure`; None: dry) with load stepping: p = p_old + t (p_new - p_old),
        t = 0 -> 1, step cutting on non-convergence. The effective stresses carry the change
        (a rising water table lowers them and may make the ground yield, so one Newton solve
        is often not enough). Returns a StageResult."""
        old = self._pore.copy() if self._pore is not None else np.zeros(len(self._qp_xy))
        new = np.zeros_like(old) if pressure is None else self._pore_values(pressure)
        if self._pore is None:
            self._pore, self._forms = old.copy(), None

        def apply(t):
            self._pore = old + t * (new - old)
            self._update_pore_values()
        result = self._run("water", apply, 0.0, 1.0, first_step, min_step)
        if pressure is None:
            self.set_pore_pressure(None)
        return result

    def pore_pressure(self):
        """Pore pressure (npts,) in Pa at the quadrature points at the current g-level."""
        return np.zeros(len(self._qp_xy)) if self._pore is None else self._pore * self.g_level

    def _update_pore_values(self):
        if self._pore_fn is not None:
            m = np.array([1.0, 1.0, 1.0, 0.0])
            self._pore_fn.x.array.reshape(-1, 4)[self._b4] = -np.outer(self.pore_pressure(), m)

    def solve_gravity(self, g_level, first_step=None, min_step=None):
        """Raise (or lower) gravity from the current level to `g_level` (multiples of 9.81 m/s2),
        with load stepping and step cutting. Returns a StageResult."""
        if not (math.isfinite(g_level) and g_level >= 0):
            raise ValueError(f"g_level={g_level!r} must be finite and >= 0")
        span = abs(g_level - self.g_level)
        first_step = first_step or max(span, 1e-12)
        min_step = min_step or max(span, 1.0) * 1e-3
        return self._run("g", self.set_gravity, self.g_level, g_level, first_step, min_step)

    def solve_load(self, scale, first_step=None, min_step=None):
        """Ramp the prescribed displacements and tractions to `scale` x their given values."""
        def apply(t):
            self._load_scale = t
            self._update_boundary_values()
        span = abs(scale - self._load_scale)
        first_step = first_step or max(span, 1e-12)
        min_step = min_step or max(span, 1e-12) * 1e-3
        return self._run("load", apply, self._load_scale, scale, first_step, min_step)

    def set_initial_stress(self, k0, surface=None, g_level=None):
        """Geostatic stress: sigma_v = rho g g_level (surface(x) - y), sigma_h = sigma_zz =
        k0 sigma_v (both compressive), no shear; with a pore pressure p the ratio applies to
        the effective stresses (sigma'_v = sigma_v - p, sigma'_h = k0 sigma'_v). Sets gravity
        to g_level (default: current, or 1 if zero). Displacements are not changed; call
        `solve_gravity` (same level) to re-equilibrate where the surface is not flat, then
        `reset_displacement`.

        surface : callable x (n,) -> elevation (m), default: the top of the mesh.
        """
        if not (math.isfinite(k0) and k0 >= 0):
            raise ValueError(f"k0={k0!r} must be finite and >= 0")
        g_level = g_level if g_level is not None else (self.g_level or 1.0)
        self.set_gravity(g_level)
        x, y = self._qp_xy[:, 0], self._qp_xy[:, 1]
        top = np.full_like(x, self.mesh.geometry.x[:, 1].max()) if surface is None else surface(x)
        rho = np.repeat(self.rho.x.array[self._cells], self._nq)
        sv = rho * GRAVITY * g_level * np.maximum(top - y, 0.0) - self.pore_pressure()
        self.sig_n = np.stack([-k0 * sv, -sv, -k0 * sv, 0.0 * sv], axis=1)
        self._sig_now = self.sig_n.copy()

    def set_stress_field(self, field, top=None):
        """Start from an in-situ stress field (``dem_core.workflow.insitu.InSitu``: sxx, syy, sxy,
        compression +; the out-of-plane stress = sxx) at every quadrature point; ``top``: the
        model's top polyline when the field's surface is None (``from_scene.scene_top``).
        Displacements and gravity are not changed: solve gravity at the level the field
        balances, then ``reset_displacement``."""
        field.check()
        x, y = self._qp_xy[:, 0], self._qp_xy[:, 1]
        sxx, syy, sxy = field.stress(x, y, top)
        sxx, syy, sxy = (np.broadcast_to(v, x.shape) for v in (sxx, syy, sxy))
        self.sig_n = np.stack([-sxx, -syy, -sxx, -math.sqrt(2.0) * sxy], axis=1)
        self._sig_now = self.sig_n.copy()

    def equilibrate(self):
        """Bring the current stress, gravity and loads to equilibrium by one Newton solve (no
        load stepping: meant for an in-situ field near equilibrium, e.g. a geostatic field under
        a slope, whose imbalance the material carries elastically). Returns a StageResult."""
        return self._run("equilibrate", lambda t: None, 0.0, 1.0, 1.0, 1.0)

    def reset_displacement(self):
        """Zero displacements (and strain reference) keeping stresses: start of a new stage."""
        if self._forms is None:
            self._build_forms()
        self._eps_now = dx.eval_expression(self._eps_expr, self._cells)
        self.u.x.array[:] = 0.0
        self.eps_n = np.zeros_like(self.eps_n)
        for k in self.history:
            self.history[k].clear()

    def excavate(self, name, first_step=1.0, min_step=1e-3):
        """Remove the cells of `name` (a region or group) and re-equilibrate.

        The cells become a weightless, stress-free soft solid (E x 1e-6, no pore pressure)
        and the remaining body carries (1 - t) f_exc, the nodal forces that the removed cells'
        total stress and weight exerted on the nodes they share with it,

            f_exc = int_removed (sigma_0 - p m) : eps(v) - rho g . v,

        while the release factor t goes 0 -> 1 by load stepping (at t = 0 the body is in the
        equilibrium it had before). Nodes of removed cells only (not shared with the remaining
        body) get no force: a cell removed earlier next to this one carries nothing, so the
        stress of this one must not push on it. Returns a StageResult whose `displacement` is
        the excavation-induced displacement at the monitoring points.
        """
        cells = self.mesh_data.cells(name)
        pts = (cells[:, None] * self._nq + np.arange(self._nq)).ravel()
        void = self._void_material()
        force = self._excavation_force(cells, pts)
        self._cell_material[cells] = void
        self._point_material[pts] = void
        self.rho.x.array[cells] = 0.0
        self.sig_n[pts] = 0.0
        if self._pore is not None:
            self._pore[pts] = 0.0
            self._update_pore_values()
        remaining = np.nonzero(self._cell_material != void)[0].astype(np.int32)
        self._release_force = dx.keep_cell_dofs(force, self.V, remaining)

        def apply(t):
            self._release = t
        try:
            result = self._run(f"excavate {name}", apply, 0.0, 1.0, first_step, min_step)
        finally:
            self._release_force, self._release = None, 0.0
        return result

    def excavated(self):
        """(ncells,) bool: the cells an ``excavate`` removed (the void's soft material)."""
        void = self._void_index()
        if void is None:
            return np.zeros(len(self._cells), bool)
        return self._cell_material == void

    def _void_index(self):
        """Index of the soft elastic material of excavated cells, None before `excavate`."""
        ref = max(m.E for m in self.materials)
        for k, m in enumerate(self.materials):
            if isinstance(m, Elastic) and m.E == ref * VOID_STIFFNESS:
                return k
        return None

    def _void_material(self):
        """Index of the void material (added on first use)."""
        k = self._void_index()
        if k is None:
            self.materials.append(Elastic(max(m.E for m in self.materials) * VOID_STIFFNESS,
                                          0.3))
            k = len(self.materials) - 1
        return k

    def _excavation_force(self, cells, pts):
        """f_exc of `excavate` (a new PETSc vector, every dof): the internal force of the total
        stress minus the weight of `cells` (quadrature points `pts`) at the current state."""
        if self._forms is None:
            self._build_forms()
        if self._exc_form is None:
            v = ufl.TestFunction(self.V)
            sig, rho = fem.Function(self._W4), fem.Function(self.rho.function_space)
            dxq = dx.quadrature_measure(self.mesh, self._qdeg)
            form = dx.compile_form(ufl.inner(sig, _eps_mandel(v)) * dxq
                                   - ufl.inner(rho * self._g_vec, v) * ufl.dx)
            self._exc_form = (form, sig, rho)
        form, sig, rho = self._exc_form
        total = np.zeros_like(self.sig_n)
        total[pts] = self.sig_n[pts]
        total[pts, :3] -= self.pore_pressure()[pts, None]
        sig.x.array.reshape(-1, 4)[self._b4] = total
        rho.x.array[:] = 0.0
        rho.x.array[cells] = self.rho.x.array[cells]
        return dx.assemble_vector_plain(dx.create_vector(form), form)

    def set_materials(self, materials):
        """Replace the materials, in the order given at construction (e.g. reduced strengths).

        A void material added by `excavate` is kept."""
        materials = list(materials)
        if len(materials) > len(self.materials):
            raise ValueError(f"{len(materials)} materials given, the model has "
                             f"{len(self.materials)}")
        self.materials = materials + self.materials[len(materials):]

    def reaction(self, where, component):
        """Total support force (N per m thickness) on the body from prescribed dofs at boundary
        facets where `where(x)`, component 0 (x) or 1 (y), at the last converged state."""
        fdim = self.mesh.topology.dim - 1
        facets = dmesh.locate_entities_boundary(self.mesh, fdim, where)
        dofs = fem.locate_dofs_topological(self.V.sub(component), fdim, facets)
        self._update_stress()
        plain = dx.assemble_vector_plain(self._b_plain, self._F)
        return float(self.mesh.comm.allreduce(np.sum(plain.array[dofs])))

    def elastic_displacement(self):
        """Largest nodal displacement (m) of the linear elastic response to the current loads
        (weight at the current g-level, tractions, pore pressure, prescribed displacements)
        from a stress-free state: the displacement scale `ssr` measures a mechanism against.
        The model's state is not changed."""
        if self._forms is None:
            self._build_forms()
        saved = (self.u.x.array.copy(), self._sig.x.array.copy(), self._tan.x.array.copy())
        tan = np.empty((len(self._point_material), 4, 4))
        for k, mat in enumerate(self.materials):
            tan[self._point_material == k] = rm.elastic_tangent(mat.E, mat.nu)
        self._tan.x.array.reshape(-1, 16)[self._b16] = tan.reshape(-1, 16)
        self._sig.x.array[:] = 0.0
        self.u.x.array[:] = 0.0
        dx.assemble_residual(self._b, self._F, self._J, self._bcs(), self.u.vector)
        dx.assemble_matrix(self._A, self._J, self._bcs())
        ok = dx.solve_linear(self._ksp, self._A, self._b, self._du.vector)
        scale = float(np.max(np.abs(self._du.x.array))) if ok else math.nan
        self.u.x.array[:], self._sig.x.array[:], self._tan.x.array[:] = saved
        self.u.x.scatter_forward()
        return scale

    def save_state(self):
        """A copy of the converged state (displacement, stresses, strains, yield flags, loads)."""
        return (self._snapshot(), self.g_level, self._load_scale, list(self.materials))

    def restore_state(self, state):
        """Go back to a state from `save_state` (e.g. before a limit search)."""
        self._saved, g_level, self._load_scale, self.materials = state
        self._saved = tuple(a.copy() for a in self._saved)
        self.materials = list(self.materials)
        self._restore()
        self.set_gravity(g_level)
        self._update_boundary_values()

    # ------------------------------------------------------------------ output
    def displacement_at(self, points):
        """Displacement (n, 2) in m at points (n, 2) (names of monitoring points allowed)."""
        pts = [self.mesh_data.points[p] if isinstance(p, str) else p for p in points]
        xyz, cells = dx.cells_containing(self.mesh, pts)
        if np.any(cells < 0):
            raise ValueError(f"points {np.asarray(pts)[cells < 0].tolist()} are outside the mesh")
        return np.asarray(self.u.eval(xyz, cells)).reshape(len(pts), -1)[:, :2]

    def cell_average(self, values):
        """Average per-point values (npts, ...) over each cell's quadrature points."""
        w = self._qwts / self._qwts.sum()
        v = values.reshape((len(self._cells), self._nq) + values.shape[1:])
        return np.einsum("p,cp...->c...", w, v)

    def stress(self, total=False):
        """Cell-averaged stress (ncells, 4): [xx, yy, zz, xy] in Pa, tension positive; effective
        stress where a pore pressure is set, unless total=True (effective - p)."""
        sig = self.sig_n.copy()
        if total:
            sig[:, :3] -= self.pore_pressure()[:, None]
        s = self.cell_average(sig)
        s[:, 3] /= math.sqrt(2.0)
        return s

    def yield_indicator(self, ever=True):
        """Fraction (0..1) of each cell's quadrature points yielding, as DG0 arrays.

        Returns dict with "shear" and "tension" (ncells,) arrays; ever=True uses the whole
        loading history, False only the last converged state.
        """
        mode = self.mode_ever if ever else self.mode
        return {"shear": self.cell_average((mode & rm.SHEAR > 0).astype(float)),
                "tension": self.cell_average((mode & rm.TENSION > 0).astype(float))}

    def triangles(self):
        """Vertex coordinates (nv, 2) and triangles (ncells, 3) for plotting."""
        geo = self.mesh.geometry
        nodes = geo.dofmap.array.reshape(-1, geo.dofmap.offsets[1] - geo.dofmap.offsets[0])
        return geo.x[:, :2], nodes[self._cells, :3]
