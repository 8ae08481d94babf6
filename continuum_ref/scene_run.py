"""Run a scene's stage list in the continuum: the same file as the DEM, its "continuum" section
giving the mesh size and each region's rock mass (``dem_core.workflow.scene.check_continuum``).

``run_scene(scene)`` meshes the scene's regions (``from_scene.mesh_from_scene``: joints are
not meshed, the rock mass smears them), applies its boundaries and monitoring points, and runs
each stage as below; one ``ContinuumStageRecord`` per stage. Units: m, Pa, kg/m^3, degrees;
g-levels in multiples of 9.81 m/s^2.

- "gravity": gravity raised (or lowered) to ``g_level`` with load stepping
  (``ContinuumModel.solve_gravity``); the direction must be straight down. After an in-situ
  stage set at 0 g: gravity set, the field equilibrated, displacements zeroed.
- "raise_gravity": critical g, gravity raised towards ``max(g_levels)`` until a limit
  (``ssr.critical_g``; resolution ``refine_to`` or 0.05 g, ``failure_displacement`` (m) as the
  runaway displacement; first and largest step the section's ``search_step["g"]``, else a
  tenth of the range); from 0 g, gravity is first solved at ``g_levels[0]``.
- "insitu": the stress field at every quadrature point (``from_scene.apply_insitu``),
  equilibrated by one Newton solve under the current gravity, displacements zeroed.
- "excavate": the cells of a region or geometry group (or of a scene group
  ``{"region": name}``) removed by the excavation-load method (``ContinuumModel.excavate``).
- "water": the table's pore pressure (effective stress), stepped in on a model under gravity
  (``from_scene.apply_water``); a surface of None drains it. ``on`` is not used: the pore
  pressure acts in the whole mass.
- "solve": one Newton solve at the current loads (the continuum is static: every stage ends
  in equilibrium or fails).
- "factor_of_safety": strength reduction of every Mohr-Coulomb region from F = 1 to
  ``max(f_levels)`` (``ssr.factor_of_safety``; resolution ``refine_to`` or 0.0025; first and
  largest step the section's ``search_step["F"]``, else 0.25; ``flow`` "native" or "davis"); the stage's contact ``materials`` are not used. A Hoek-Brown region
  enters as its equivalent Mohr-Coulomb, which needs ``sigma3_max`` (Pa) in its entry.
- "change_material" and "strength_schedule": a change of the DEM's contact material reaches
  the regions whose continuum material is derived from the contact materials (kind
  ``dem_rock_mass``, ``rock_mass.dem_rock_mass``): the material is derived again from the
  changed ones, then the model equilibrated. A schedule lowers the property continuously from
  its present value towards ``min(values)`` until no equilibrium (the load path of
  ``ssr``: a limit with a mechanism, resolution ``refine_to`` or 1 % of the range); its
  value is the last stable one, and the model is left there. A change that reaches no region
  (every region has a material of its own, or the changed material is not one a region is
  derived from) is refused before anything is meshed.

Every other kind (cycle, prescribe_velocity, release, servo, load, displace, cable, liner) is
refused before anything is meshed, naming it (``check_continuum_stages``): they act on blocks
or contacts the continuum does not have.
"""
from __future__ import annotations

import fnmatch
import time
from dataclasses import dataclass, field, replace

import numpy as np

from .materials import Elastic, HoekBrown, MohrCoulomb

__all__ = ["run_scene", "build_continuum", "region_materials", "material_from_dict",
           "material_entry",
           "check_continuum_stages", "check_boundaries", "ContinuumStageRecord", "CONTINUUM_STAGES",
           "max_displacement"]

CONTINUUM_STAGES = ("gravity", "raise_gravity", "insitu", "excavate", "water", "solve",
                    "factor_of_safety", "change_material", "strength_schedule")
MATERIAL_STAGES = ("change_material", "strength_schedule")   # through dem_rock_mass regions
SCHEDULE_TOL = 0.01        # of the schedule's range, without refine_to
DEFAULT_G_TOL = 0.05       # g, resolution of a critical-g search without refine_to
DEFAULT_F_TOL = 0.0025     # resolution of a factor of safety without refine_to
DEFAULT_F_STEP = 0.25      # first and largest F step without the section's search_step
STOPS = ("failed", "limit")


@dataclass
class ContinuumStageRecord:
    """What one stage did in the continuum.

    index, kind : the stage's place in the scene and its kind. verdict : "set",
    "equilibrium", "failed" (no convergence), "limit" (a search found one: ``value`` is F or
    g), "stable" (a search reached the end of its range) or "no limit" (a search stopped
    without a mechanism: a solver failure, not a limit). value : F or the last stable g of a
    search, else None. first_failed : the search's first failed F or g, else None.
    max_displacement : largest nodal |u| (m) since the last reset (an in-situ stage zeroes
    it). points : monitoring point -> (ux, uy) m. seconds : wall time (s). note : the search's
    verdict in words, or the reason of a failure. detail : steps, Newton iterations.
    """

    index: int
    kind: str
    verdict: str
    value: float | None
    first_failed: float | None
    max_displacement: float
    points: dict
    seconds: float
    note: str = ""
    detail: dict = field(default_factory=dict)


# ---------------------------------------------------------------------- materials
def material_from_dict(d: dict):
    """(material, strength-reduction material) of a file entry ``{"kind": ..., fields}``
    (``dem_core.workflow.scene.CONTINUUM_MATERIALS``): Elastic, MohrCoulomb or HoekBrown (from
    gsi, mi, sci, D with Em of Hoek et al. 2002 unless E is given, or from mb, s, a, E); the
    second is the material itself, or for Hoek-Brown its equivalent Mohr-Coulomb at
    ``sigma3_max`` (Pa) with ``dilation`` (degrees), None without sigma3_max."""
    d = {k: v for k, v in d.items() if v is not None}
    kind = d.pop("kind")
    if kind == "elastic":
        mat = Elastic(float(d["E"]), float(d["nu"]))
        return mat, mat
    if kind == "mohr_coulomb":
        mat = MohrCoulomb(**{k: float(v) for k, v in d.items()})
        return mat, mat
    if kind != "hoek_brown":
        raise ValueError(f"unknown continuum material kind {kind!r}")
    s3max, dilation = d.pop("sigma3_max", None), d.pop("dilation", None)
    if "gsi" in d:
        mat = HoekBrown.from_gsi(d["gsi"], d["mi"], d["sci"], D=d.get("D", 0.0),
                                 E=d.get("E"), nu=d.get("nu", 0.3))
    else:
        mat = HoekBrown(E=d["E"], nu=d.get("nu", 0.3), sci=d["sci"], mb=d["mb"], s=d["s"],
                        a=d["a"])
    fos = None if s3max is None else mat.equivalent_mohr_coulomb(float(s3max), dilation)
    return mat, fos


def material_entry(material) -> dict:
    """The scene-file entry of a continuum material (``material_from_dict``'s inverse for
    Elastic and MohrCoulomb): {"kind": ..., its fields}."""
    import dataclasses

    kinds = {Elastic: "elastic", MohrCoulomb: "mohr_coulomb"}
    if type(material) not in kinds:
        raise ValueError(f"no scene-file entry for a {type(material).__name__}; give Elastic "
                         f"or MohrCoulomb, or write the entry (kinds: docs/scenes.md)")
    return {"kind": kinds[type(material)], **dataclasses.asdict(material)}


def region_materials(scene, spec) -> tuple:
    """({region: material}, {region: strength-reduction material or None}) in region order.
    ``spec``: region name or fnmatch pattern -> a material (``continuum_ref.materials``) or
    its file entry (a ``dem_rock_mass`` entry: ``rock_mass.dem_rock_mass`` of the region);
    a region takes its own name's entry, else the first pattern matching it.
    ValueError naming a region without one, or a bad entry."""
    mats, fos = {}, {}
    for r in scene.geometry.regions:
        key = _key(r.name, spec)
        if key is None:
            raise ValueError(f"continuum: region {r.name!r} has no material "
                             f"(materials: {sorted(spec)})")
        entry = spec[key]
        try:
            if _is_derived(entry):
                entry = _derive(scene, r.name, entry, scene.materials)
            mats[r.name], fos[r.name] = (material_from_dict(entry) if isinstance(entry, dict)
                                         else (entry, entry))
        except (ValueError, TypeError, KeyError) as e:
            raise ValueError(f"continuum: materials[{key!r}]: {e}") from None
        if isinstance(entry, HoekBrown):
            fos[r.name] = None
    return mats, fos


def derived_materials(scene, spec, contact_materials) -> dict:
    """{region: material} of the regions whose ``spec`` entry is a ``dem_rock_mass``, derived
    from ``contact_materials`` (name or pattern -> ``Material``)."""
    entries = {r.name: spec.get(_key(r.name, spec)) for r in scene.geometry.regions}
    return {name: _derive(scene, name, entry, contact_materials)
            for name, entry in entries.items() if _is_derived(entry)}


def _key(region, spec):
    """The ``spec`` key of ``region``: its own name, else the first pattern matching it."""
    return region if region in spec else next(
        (k for k in spec if fnmatch.fnmatchcase(region, k)), None)


def _is_derived(entry) -> bool:
    return isinstance(entry, dict) and entry.get("kind") == "dem_rock_mass"


def _derive(scene, region, entry, contact_materials):
    """The rock mass of a ``dem_rock_mass`` ``entry`` (``rock_mass.dem_rock_mass``)."""
    from .rock_mass import dem_rock_mass

    return dem_rock_mass(scene, region, entry["bound"], float(entry.get("dilation") or 0.0),
                         contact_materials)


def changed_materials(scene, material, changes, contact_materials=None, spec=None) -> tuple:
    """(contact materials after ``changes`` of ``material``, {region: derived material} of
    the ``dem_rock_mass`` regions the change moves); ``contact_materials`` default the
    scene's, ``spec`` (region -> continuum entry) the scene's continuum materials. ValueError
    naming the material when it is not one of the contact materials."""
    from dataclasses import replace

    mats = dict(scene.materials if contact_materials is None else contact_materials)
    if material not in mats:
        raise ValueError(f"material {material!r} is not one of the scene's {sorted(mats)}")
    spec = spec if spec is not None else (scene.continuum or {}).get("materials") or {}
    before = derived_materials(scene, spec, mats)
    mats[material] = replace(mats[material], **changes)
    after = derived_materials(scene, spec, mats)
    return mats, {r: m for r, m in after.items() if m != before[r]}


# ---------------------------------------------------------------------- checks
def _mesh_names(scene) -> set:
    """The names a mesh of the scene has cells for: regions, geometry groups, region groups."""
    g = scene.geometry
    names = {r.name for r in g.regions} | set(g.groups)
    for r in g.regions:
        names |= set(r.groups)
    return names


def excavated_name(scene, group: str) -> str:
    """The mesh name a scene group stands for: itself when the mesh has it, the region of a
    scene group ``{"region": name}``; ValueError naming the group otherwise."""
    names = _mesh_names(scene)
    seen = group
    while group not in names:
        sel = scene.groups.get(group)
        if not (isinstance(sel, dict) and "region" in sel):
            raise ValueError(f"excavate {seen!r}: the continuum removes the cells of a region "
                             f"or geometry group (or a scene group {{\"region\": name}}); "
                             f"{seen!r} is " + (f"the selector {sel!r}" if sel else "unknown")
                             + f"; mesh names: {sorted(names)}")
        group = sel["region"]
    return group


def check_boundaries(scene) -> None:
    """ValueError naming a scene boundary the mesh cannot take: its group must be made of box
    sides (``from_scene.side_sets``: touching, union, minus)."""
    from .from_scene import side_sets

    for b in scene.boundaries:
        if b.x or b.y:
            side_sets(scene, b.group)


def check_continuum_stages(scene, fos_materials=None, spec=None) -> None:
    """ValueError, before anything is meshed, naming every stage the continuum cannot run
    (module docstring) or cannot run as given: gravity not straight down, an excavated group
    the mesh has no cells for, a factor of safety of a Hoek-Brown region without
    sigma3_max (``fos_materials``: region -> strength-reduction material or None), a
    material change that reaches no region (``spec``: region -> continuum entry, default the
    scene's continuum materials)."""
    from dem_core.workflow.stages import Excavate, FactorOfSafety, Gravity, stage_to_dict

    bad = [(i, stage_to_dict(st)["kind"]) for i, st in enumerate(scene.stages)
           if stage_to_dict(st)["kind"] not in CONTINUUM_STAGES]
    if bad:
        raise ValueError(
            "the continuum cannot run stage" + ("s " if len(bad) > 1 else " ")
            + ", ".join(f"{i} ({k})" for i, k in bad)
            + f"; it runs {', '.join(CONTINUUM_STAGES)} (docs/scenes.md, \"The continuum\")")
    for i, st in enumerate(scene.stages):
        where = f"stage {i} ({stage_to_dict(st)['kind']})"
        if isinstance(st, Gravity):
            dx, dy = (float(v) for v in st.direction)
            if dx != 0.0 or dy >= 0.0:
                raise ValueError(f"{where}: the continuum's gravity acts straight down; "
                                 f"direction {tuple(st.direction)} is refused")
        elif isinstance(st, Excavate):
            try:
                excavated_name(scene, st.group)
            except ValueError as e:
                raise ValueError(f"{where}: {e}") from None
        elif stage_to_dict(st)["kind"] in MATERIAL_STAGES:
            _check_material_stage(scene, st, where, spec)
        elif isinstance(st, FactorOfSafety) and fos_materials is not None:
            missing = [r for r, m in fos_materials.items() if m is None]
            if missing:
                raise ValueError(f"{where}: Hoek-Brown region(s) {missing} need sigma3_max "
                                 f"(Pa) in their continuum material for a strength reduction "
                                 f"(their equivalent Mohr-Coulomb)")


def _check_material_stage(scene, st, where, spec) -> None:
    """A change_material or strength_schedule stage must move a ``dem_rock_mass`` region."""
    changes = (dict(st.changes) if hasattr(st, "changes")
               else {st.property: min(float(v) for v in st.values)})
    try:
        _, moved = changed_materials(scene, st.material, changes, spec=spec)
    except (ValueError, TypeError) as e:
        raise ValueError(f"{where}: {e}") from None
    if not moved:
        raise ValueError(f"{where}: changing {st.material!r} reaches no continuum region: a "
                         f"contact material's change reaches only the regions whose continuum "
                         f"material is derived from the contact materials (kind "
                         f"\"dem_rock_mass\"), and only through the materials they are "
                         f"derived from")


# ---------------------------------------------------------------------- running
def build_continuum(scene, h, materials):
    """The ContinuumModel of ``scene`` at mesh size ``h`` (m) with ``materials`` ({region:
    material}): mesh with the scene's points (graded from h to the section's ``refine``
    h_far when it has one: ``mesh.refine_near``), density ``scene.density`` (kg/m^3), the
    scene's boundaries (``from_scene.apply_boundaries``)."""
    from .from_scene import apply_boundaries, mesh_from_scene, scene_bounds
    from .mesh import refine_near
    from .model import ContinuumModel

    refine = (scene.continuum or {}).get("refine")
    if refine:
        field = refine_near(refine["points"], h, refine["h_far"], refine["d_near"],
                            refine["d_far"])
        mesh = mesh_from_scene(scene, refine["h_far"], size_field=field)
    else:
        mesh = mesh_from_scene(scene, h)
    model = ContinuumModel(mesh, dict(materials), scene.density)
    apply_boundaries(model, scene, scene_bounds(scene))
    return model


def max_displacement(model) -> float:
    """Largest nodal |u| of ``model`` (m)."""
    u = model.u.x.array.reshape(-1, 2)
    return float(np.max(np.hypot(u[:, 0], u[:, 1]))) if len(u) else 0.0


def run_scene(scene, h=None, materials=None, flow=None, progress=None, on_stage=None) -> list:
    """Run ``scene``'s stages in the continuum (module docstring); a list of
    ``ContinuumStageRecord``, one per stage run.

    h : mesh size (m); default the scene's ``continuum["h"]``. materials : region name or
    pattern -> material or file entry; default the scene's ``continuum["materials"]``. flow :
    "native" or "davis" for a factor of safety (``ssr.factor_of_safety``); default the
    scene's ``continuum["flow"]``, else "native". progress : optional callable(str) after
    each stage. on_stage : optional callable(model, record) after each stage, with the model
    at the stage's end (e.g. to draw it: ``continuum_ref.plot.stage_figure``). Every stage is checked before the mesh is built (ValueError naming it). With
    ``scene.after_failure`` "stop", the run ends after a stage that failed or a search that
    found its limit.
    """
    section = scene.continuum or {}
    h = section.get("h") if h is None else h
    spec = section.get("materials") if materials is None else materials
    flow = flow or section.get("flow", "native")
    if h is None or spec is None:
        raise ValueError(f"scene {scene.name!r} has no \"continuum\" section (mesh size h and "
                         f"region materials): give h and materials")
    mats, fos = region_materials(scene, spec)
    check_boundaries(scene)
    check_continuum_stages(scene, fos, spec)
    model = build_continuum(scene, h, mats)
    runner = _Runner(model, scene, mats, fos, flow, spec)
    records = []
    for i, st in enumerate(scene.stages):
        rec = runner.run(i, st)
        records.append(rec)
        if on_stage is not None:
            on_stage(model, rec)
        if progress is not None:
            progress(f"continuum stage {i} {rec.kind}: {rec.verdict}"
                     + (f" {rec.value:.4g}" if rec.value is not None else "")
                     + f", {rec.seconds:.1f} s")
        if scene.after_failure == "stop" and rec.verdict in STOPS and i + 1 < len(scene.stages):
            break
    return records


class _Runner:
    """Runs one stage at a time on a ContinuumModel (``run_scene``)."""

    def __init__(self, model, scene, materials, fos_materials, flow, spec):
        self.model, self.scene, self.flow, self.spec = model, scene, flow, spec
        self.regions = list(materials)                 # the model's material order
        self.mats, self.fos_by_region = dict(materials), dict(fos_materials)
        self.contact_materials = dict(scene.materials)  # as the stages change them
        self.search_step = dict((scene.continuum or {}).get("search_step") or {})
        self.insitu_pending = False        # a field set at 0 g, equilibrated by gravity
        self._trial = None                 # a schedule's contact materials at its last level

    @property
    def fos(self):
        return [self.fos_by_region[r] for r in self.regions]

    def _set_derived(self, derived):
        """Give the model the regions' materials, those in ``derived`` replaced."""
        self.mats.update(derived)
        self.fos_by_region.update(derived)
        self.model.set_materials([self.mats[r] for r in self.regions])

    def run(self, i, st):
        from dem_core.workflow.stages import stage_to_dict

        kind = stage_to_dict(st)["kind"]
        t0 = time.perf_counter()
        verdict, value, failed, note, detail = getattr(self, "_" + kind)(st)
        m = self.model
        pts = {}
        if self.scene.points:
            u = m.displacement_at(list(self.scene.points))
            pts = {n: (float(a), float(b)) for n, (a, b) in zip(self.scene.points, u)}
        return ContinuumStageRecord(i, kind, verdict, value, failed, max_displacement(m), pts,
                                    time.perf_counter() - t0, note, detail)

    @staticmethod
    def _solved(result, note=""):
        verdict = "equilibrium" if result.converged else "failed"
        if not result.converged:
            note = note or (f"no convergence at load {result.failed_at!r} (last converged "
                            f"{result.load_reached:.4g})")
        return verdict, None, None, note, {"steps": result.steps,
                                           "newton_iterations": result.newton_iterations}

    def _settle_field(self):
        result = self.model.equilibrate()
        if result.converged:
            self.model.reset_displacement()
        return self._solved(result)

    def _gravity(self, st):
        if self.insitu_pending:
            self.insitu_pending = False
            self.model.set_gravity(float(st.g_level))
            return self._settle_field()
        return self._solved(self.model.solve_gravity(float(st.g_level)))

    def _insitu(self, st):
        from .from_scene import apply_insitu

        apply_insitu(self.model, self.scene, st)
        if self.model.g_level == 0.0:
            self.insitu_pending = True
            return "set", None, None, "equilibrated by the next gravity stage", {}
        return self._settle_field()

    def _excavate(self, st):
        return self._solved(self.model.excavate(excavated_name(self.scene, st.group)))

    def _water(self, st):
        from .from_scene import apply_water

        if self.model.g_level == 0.0:
            apply_water(self.model, st, solve=False)
            return "set", None, None, "", {}
        return self._solved(apply_water(self.model, st, solve=True))

    def _solve(self, st):
        return self._solved(self.model.equilibrate())

    def _raise_gravity(self, st):
        from .ssr import critical_g

        m, levels = self.model, [float(g) for g in st.g_levels]
        if m.g_level == 0.0:
            first = m.solve_gravity(levels[0])
            if not first.converged:
                return self._solved(first)
        if levels[-1] <= m.g_level:
            return "stable", m.g_level, None, f"already at {m.g_level:g} g", {}
        limit = critical_g(m, levels[-1], first_step=self.search_step.get("g"),
                           tol=st.refine_to or DEFAULT_G_TOL,
                           runaway=st.failure_displacement)
        return self._limit(limit)

    def _factor_of_safety(self, st):
        from .ssr import factor_of_safety

        m = self.model
        if any(isinstance(x, HoekBrown) for x in m.materials):
            m.set_materials(self.fos)              # the equivalent Mohr-Coulomb at F = 1
            settled = m.equilibrate()
            if not settled.converged:
                return self._solved(settled, "the equivalent Mohr-Coulomb rock mass is not in "
                                             "equilibrium at F = 1")
        f_max = max(float(f) for f in st.f_levels)
        if not f_max > 1.0:
            return "failed", None, None, f"f_levels {list(st.f_levels)} end at or below 1", {}
        limit = factor_of_safety(m, self.fos, f_max=f_max, f_start=1.0,
                                 first_step=self.search_step.get("F", DEFAULT_F_STEP),
                                 tol=st.refine_to or DEFAULT_F_TOL,
                                 runaway=st.failure_displacement, flow=self.flow)
        return self._limit(limit)

    def _change_material(self, st):
        self.contact_materials, moved = changed_materials(
            self.scene, st.material, dict(st.changes), self.contact_materials, self.spec)
        self._set_derived(moved)
        verdict, value, failed, note, detail = self._solved(self.model.equilibrate())
        return verdict, value, failed, note or f"regions {sorted(moved)} derived again", detail

    def _strength_schedule(self, st):
        from .ssr import _search, _verdict

        now = float(getattr(self.contact_materials[st.material], st.property))
        low = min(float(v) for v in st.values)
        span = low - now                                # < 0: the schedule lowers it

        def value(t):                                   # t in [0, 1] along the schedule
            return now + t * span

        def apply(t):
            mats, moved = changed_materials(self.scene, st.material, {st.property: value(t)},
                                            self.contact_materials, self.spec)
            self._set_derived(moved)
            self._trial = mats
        tol = (st.refine_to or SCHEDULE_TOL * abs(span)) / abs(span)
        first = max(tol, min(1.0, (now - float(st.values[0])) / abs(span)))
        limit = _search(self.model, st.property, apply, 0.0, 1.0, first, tol,
                        st.failure_displacement, 1.0, 10.0)
        apply(limit.value)                              # the model's state: the last stable
        self.contact_materials = self._trial
        limit = replace(limit, value=value(limit.value), first_failed=None if (
            limit.first_failed is None) else value(limit.first_failed))
        limit.note = _verdict(limit, f"{st.material} {st.property}", 10.0)
        return self._limit(limit)

    @staticmethod
    def _limit(limit):
        verdict = ("limit" if limit.found else "stable" if limit.first_failed is None
                   else "no limit")
        value = limit.value if verdict != "no limit" else None
        return verdict, value, limit.first_failed, limit.note, {
            "steps": limit.steps, "newton_iterations": limit.newton_iterations,
            "last_converged": limit.value, "upturn": limit.upturn}
