"""Stages: what happens to a scene, as records, and the one runner that executes them.

A stage is a small frozen record; ``run_stages(model, stages)`` runs them in order on a DEM
``Model`` and records, per stage, its steps, verdict, the displacement of every monitoring
point and the crack counts (``StageRecord``). The centrifuge g-ramp is one stage kind
(``RaiseGravity``, executed by ``gravity_ramp.raise_gravity``), not a second driver.

| kind (file) | record | does |
|---|---|---|
| "gravity" | ``Gravity(g_level, direction)`` | sets gravity (g-level x 9.81 m/s^2) |
| "solve" | ``Solve(ratio, max_steps, failure_displacement, settle, creep, watch)`` | cycles to equilibrium |
| "cycle" | ``Cycle(steps)`` | a fixed number of steps |
| "raise_gravity" | ``RaiseGravity(g_levels, ...)`` | centrifuge ramp to failure |
| "excavate" | ``Excavate(group)`` | removes a group's blocks |
| "change_material" | ``ChangeMaterial(material, changes)`` | a strength (or stiffness) change |
| "prescribe_velocity" | ``PrescribeVelocity(group, vx, vy, omega)`` | velocity boundary (m/s) |
| "release" | ``Release(group)`` | frees a group's prescribed velocities and its servo |
| "servo" | ``loading.ServoLoad(group, stress, length, direction, ...)`` | a constant force, settled |
| "load" | ``loading.Load(group, rate, direction, read_on, length, ...)`` | a displacement-controlled load past its peak |
| "insitu" | ``insitu.InSitu(sxx, syy, sxy, gxx, gyy, gxy, k, surface)`` | every contact starts with the traction of a stress field |
| "water" | ``water.WaterTable(surface, unit_weight, on)`` | puts a water table on the model (surface None: drains it) |
| "displace" | ``loading.Displace(group, vx, vy, displacement, ...)`` | moves a group until it has moved a distance, then releases it |
| "factor_of_safety" | ``strength.FactorOfSafety(materials, f_levels, refine_to, tension, ...)`` | strength-reduction factor of safety |
| "strength_schedule" | ``strength.StrengthSchedule(material, property, values, refine_to, ...)`` | lowers a strength until failure |
| "cable" | ``support.Cable(collar, end, area, E, yield_tension, grout_stiffness, ...)`` | installs a grouted cable or bolt |
| "liner" | ``support.Liner(group, thickness, E, tensile_yield, ...)`` | installs a shotcrete liner on a group's exposed faces |
"""
from __future__ import annotations

import dataclasses
import math
import time
from dataclasses import dataclass, field

import numpy as np

from ..settings import DEFAULT_SOLVE, SolveSettings
from . import plausibility
from .insitu import InSitu, model_top
from .loading import Displace, Load, ServoLoad
from ..contact.materials import Material
from .strength import FactorOfSafety, StrengthSchedule, search_verdict
from ..components.support import Cable, Liner, check_in_rock, liner_faces
from .water import WaterTable

__all__ = ["Gravity", "Solve", "Cycle", "RaiseGravity", "Excavate", "ChangeMaterial",
           "PrescribeVelocity", "Release", "ServoLoad", "Load", "InSitu", "Displace",
           "FactorOfSafety", "StrengthSchedule", "WaterTable", "Cable", "Liner", "StageRecord",
           "run_stages", "stops", "stop_after", "stop_note", "moved_most", "STOPS", "AFTER_FAILURE",
           "check_stages", "stage_from_dict", "stage_to_dict", "stage_table", "STAGE_KINDS"]


def _group_known(i, kind, group, known):
    if group not in known:
        raise ValueError(f"stage {i} ({kind}) names unknown group {group!r}; groups are "
                         f"{sorted(known)}")


@dataclass(frozen=True)
class Gravity:
    g_level: float = 1.0
    direction: tuple = (0.0, -1.0)

    def check(self, i, groups, materials):
        d = [float(v) for v in self.direction]
        if not (math.isfinite(self.g_level) and self.g_level >= 0 and len(d) == 2
                and all(math.isfinite(v) for v in d) and math.hypot(*d) > 0):
            raise ValueError(f"stage {i} (gravity): g_level {self.g_level!r} must be >= 0 and "
                             f"direction {self.direction!r} a non-zero 2-vector")
        plausibility.check_g_level(self.g_level, f"stage {i} (gravity)")

    def run(self, model):
        model.set_gravity(self.g_level, direction=self.direction)
        return 0, "set", {}


@dataclass(frozen=True)
class Solve:
    """Cycle to equilibrium (``Model.solve``, ``workflow.solve``) with the ``SolveSettings``
    of its fields; ``settle``: stop early as "settled" once the largest displacement has
    stopped growing and no bond broke (``monitor.settled``); ``watch``: judge these history
    points' displacement instead of every block's."""
    ratio: float = DEFAULT_SOLVE.ratio           # the solve's SolveSettings (settings.py)
    max_steps: int | None = DEFAULT_SOLVE.max_steps
    failure_displacement: float | None = DEFAULT_SOLVE.failure_displacement
    settle: bool = DEFAULT_SOLVE.settle
    judge: str | None = DEFAULT_SOLVE.judge
    response_steps: int | None = DEFAULT_SOLVE.response_steps
    windows: int = DEFAULT_SOLVE.windows
    creep: float | None = DEFAULT_SOLVE.creep
    watch: tuple = DEFAULT_SOLVE.watch

    def check(self, i, groups, materials):
        SolveSettings.of(self).validated(f"stage {i} (solve)")

    def run(self, model):
        r = model.solve(SolveSettings.of(self))
        return r.steps, r.verdict, {"ratio": r.ratio, "reason": r.reason}


@dataclass(frozen=True)
class Cycle:
    steps: int

    def check(self, i, groups, materials):
        if not (isinstance(self.steps, int) and self.steps > 0):
            raise ValueError(f"stage {i} (cycle): steps must be an integer > 0, got "
                             f"{self.steps!r}")

    def run(self, model):
        model.cycle(self.steps)
        return self.steps, "done", {}


@dataclass(frozen=True)
class RaiseGravity:
    g_levels: tuple
    ratio: float = DEFAULT_SOLVE.ratio           # each level's SolveSettings (settings.py)
    max_steps: int | None = DEFAULT_SOLVE.max_steps
    failure_displacement: float | None = DEFAULT_SOLVE.failure_displacement
    creep: float | None = DEFAULT_SOLVE.creep
    watch: tuple = DEFAULT_SOLVE.watch
    refine_to: float | None = None
    settle: bool = DEFAULT_SOLVE.settle
    judge: str | None = DEFAULT_SOLVE.judge
    response_steps: int | None = DEFAULT_SOLVE.response_steps
    windows: int = DEFAULT_SOLVE.windows

    def check(self, i, groups, materials):
        g = [float(v) for v in self.g_levels]
        if not g or not all(math.isfinite(v) and v > 0 for v in g) or sorted(g) != g:
            raise ValueError(f"stage {i} (raise_gravity): g_levels must be increasing and > 0, "
                             f"got {self.g_levels!r}")
        plausibility.check_g_level(g[-1], f"stage {i} (raise_gravity)")
        SolveSettings.of(self).validated(f"stage {i} (raise_gravity)")

    def run(self, model, on_level=None, resume=None):
        """Raise gravity through ``g_levels`` (``gravity_ramp.raise_gravity``). ``on_level``:
        optional callable(model, record) after each level; ``resume``: the RampRecord of this
        ramp stopped after a resumable level (``LimitRecord.resumable``), ``model`` being the
        state it left: the ramp goes on from there to the result it would have had."""
        from .gravity_ramp import RampRecord, raise_gravity
        missing = [w for w in self.watch if w not in model.points]
        if missing:
            raise ValueError(f"raise_gravity watches unknown monitoring point(s) {missing}")
        start = 0.0 if resume is None else resume.level[-1]
        levels = [float(g) for g in self.g_levels if g > start]
        rec = resume if resume is not None else RampRecord()
        if levels:
            rec = raise_gravity(model, levels, SolveSettings.of(self), refine_to=self.refine_to,
                                on_level=on_level, record=rec, start=start)
        verdict = search_verdict(rec)
        return int(sum(rec.steps)), verdict, {"failure_g": rec.failure_g,
                                              "last_stable_g": rec.last_stable_g,
                                              "g": list(rec.g), "verdicts": list(rec.verdict),
                                              "ramp": rec}


@dataclass(frozen=True)
class Excavate:
    group: str

    def check(self, i, groups, materials):
        _group_known(i, "excavate", self.group, groups)

    def run(self, model):
        idx = model.group(self.group)
        left = int(model.props.active[idx].sum())
        if left == 0:
            raise ValueError(f"excavate: group {self.group!r} has no blocks left ("
                             f"{'it is empty' if idx.size == 0 else 'already excavated'})")
        model.remove(self.group)
        return 0, "removed", {"blocks": left}


@dataclass(frozen=True)
class ChangeMaterial:
    material: str
    changes: dict = field(default_factory=dict)

    def check(self, i, groups, materials):
        if self.material not in materials:
            raise ValueError(f"stage {i} (change_material) names unknown material "
                             f"{self.material!r}; materials are {sorted(materials)}")
        fields = {f.name for f in dataclasses.fields(Material)}
        bad = set(self.changes) - fields
        if bad or not self.changes:
            raise ValueError(f"stage {i} (change_material): changes {sorted(self.changes)} must "
                             f"be Material fields {sorted(fields)}")
        where = f"stage {i} (change_material {self.material!r})"
        changed = dataclasses.replace(materials[self.material], **self.changes).validated(where)
        plausibility.check_stiffness({self.material: changed}, f"{where}: materials")

    def run(self, model):
        model.set_material(self.material, **self.changes)
        return 0, "changed", {}


@dataclass(frozen=True)
class PrescribeVelocity:
    group: str
    vx: float | None = None
    vy: float | None = None
    omega: float | None = 0.0

    def check(self, i, groups, materials):
        _group_known(i, "prescribe_velocity", self.group, groups)
        for v in (self.vx, self.vy, self.omega):
            if v is not None and not math.isfinite(v):
                raise ValueError(f"stage {i} (prescribe_velocity): velocity {v!r} not finite")

    def run(self, model):
        model.set_velocity(self.group, self.vx, self.vy, self.omega)
        return 0, "set", {}


@dataclass(frozen=True)
class Release:
    group: str

    def check(self, i, groups, materials):
        _group_known(i, "release", self.group, groups)

    def run(self, model):
        model.free(self.group)
        return 0, "released", {}


STAGE_KINDS = {"gravity": Gravity, "solve": Solve, "cycle": Cycle,
               "raise_gravity": RaiseGravity, "excavate": Excavate,
               "change_material": ChangeMaterial, "prescribe_velocity": PrescribeVelocity,
               "release": Release, "servo": ServoLoad, "load": Load,
               "insitu": InSitu, "displace": Displace, "factor_of_safety": FactorOfSafety,
               "strength_schedule": StrengthSchedule, "water": WaterTable,
               "cable": Cable, "liner": Liner}
_KIND_OF = {cls: kind for kind, cls in STAGE_KINDS.items()}
_SEARCHES = (RaiseGravity, FactorOfSafety, StrengthSchedule)    # run(model, on_level=...)


def stage_to_dict(stage) -> dict:
    """The stage as a file record: {"kind": ..., fields...}."""
    return {"kind": _KIND_OF[type(stage)], **dataclasses.asdict(stage)}


def stage_from_dict(d: dict, i: int = 0):
    """A stage record from its file form; ValueError naming an unknown kind or field."""
    d = dict(d)
    kind = d.pop("kind", None)
    if kind not in STAGE_KINDS:
        raise ValueError(f"stage {i}: unknown kind {kind!r}; kinds are {sorted(STAGE_KINDS)}")
    cls = STAGE_KINDS[kind]
    allowed = {f.name for f in dataclasses.fields(cls)}
    if set(d) - allowed:
        raise ValueError(f"stage {i} ({kind}): unknown key(s) {sorted(set(d) - allowed)}; "
                         f"allowed {sorted(allowed)}")
    for key in ("direction", "g_levels", "watch", "read_on", "gauge", "gauge_direction",
                "materials", "f_levels", "values", "collar", "end"):
        if key in d:
            d[key] = tuple(d[key])
    for key in ("surface", "within"):
        if isinstance(d.get(key), list):
            d[key] = tuple(tuple(p) for p in d[key])
    try:
        return cls(**d)
    except TypeError as e:
        raise ValueError(f"stage {i} ({kind}): {e}") from None


@dataclass
class StageRecord:
    """What one stage did: its kind, steps, verdict, model time at its end (s), the
    displacement (ux, uy, m) of each monitoring point at its end, the crack counts so far,
    wall-clock seconds, and kind-specific ``detail`` (a g-ramp's failure_g, last_stable_g, g,
    verdicts, and "ramp": its whole ``gravity_ramp.RampRecord``)."""

    index: int
    kind: str
    steps: int
    verdict: str
    time: float
    points: dict
    cracks: dict
    seconds: float
    detail: dict


def check_stages(stages, groups, materials) -> None:
    """Check every stage (``stage.check``) and the sequence: a group excavated twice is
    refused (ValueError naming the stage and group) before any compute."""
    gone = {}
    for i, st in enumerate(stages):
        st.check(i, groups, materials)
        if isinstance(st, Excavate):
            if st.group in gone:
                raise ValueError(f"stage {i} (excavate): group {st.group!r} was already "
                                 f"excavated by stage {gone[st.group]}")
            gone[st.group] = i


def check_on_model(stages, model, first=0) -> None:
    """What the stages need of the built model, before its first step (ValueError naming the
    stage, numbered from ``first``): every watched point is a monitoring point, every
    excavated group has blocks when it is excavated and leaves some, every cable starts and
    ends in rock, every liner's group has one chain of exposed faces when it is installed (the
    excavations before it applied), and no gravity or in-situ stress presses the contacts
    together by more than a block's size (``plausibility.check_gravity_closure``,
    ``check_stress_closure``). Movement before a stage is not foreseen: a cable is checked on
    the model as built, and again when it runs."""
    active = model.props.active.copy()
    for i, st in enumerate(stages, start=first):
        where = f"stage {i} ({_KIND_OF[type(st)]})"
        missing = [p for p in getattr(st, "watch", ()) if p not in model.points]
        if missing:
            raise ValueError(f"{where}: watch names no monitoring point {missing}; points are "
                             f"{sorted(model.points)}")
        _check_one_on_model(st, model, active, where)


def _check_one_on_model(st, model, active, where) -> None:
    """``check_on_model`` for one stage; ``active`` (nb,) the blocks left by the excavations
    before it (an excavation updates it)."""
    if isinstance(st, Excavate):
        idx = model.group(st.group)
        if not active[idx].any():
            raise ValueError(f"{where}: group {st.group!r} has no blocks" + (
                " left (excavated by an earlier stage)" if len(idx) else ""))
        active[idx] = 0
        if not active.any():
            raise ValueError(f"{where}: group {st.group!r} holds every block left: nothing "
                             "would remain to compute (a solve would report an equilibrium "
                             "of nothing)")
    elif isinstance(st, (Cable, Liner)):
        try:
            if isinstance(st, Cable):
                check_in_rock(model, st)
            else:
                liner_faces(model.blocks, active, model.group(st.group), st)
        except ValueError as e:
            why = str(e).removeprefix("cable: ").removeprefix("liner: ")
            raise ValueError(f"{where}: {why}") from None
    elif isinstance(st, (Gravity, RaiseGravity)):
        g = st.g_level if isinstance(st, Gravity) else max(st.g_levels)
        plausibility.check_gravity_closure(model, float(g), where)
    elif isinstance(st, InSitu):
        top = None if st.surface is not None else model_top(model)
        plausibility.check_stress_closure(model, st, where, top)


def stage_table(records, points=None) -> str:
    """A markdown table of the monitoring points' displacements (mm) at the end of each stage
    (``StageRecord``s), with each stage's kind, verdict and steps: the stage-by-stage
    displacement table of a staged excavation."""
    points = list(points if points is not None else (records[0].points if records else {}))
    head = "| stage | kind | verdict | steps | " + " | ".join(
        f"{p} ux, uy (mm)" for p in points) + " |"
    rows = [head, "|" + "---|" * (4 + len(points))]
    for r in records:
        cells = [f"{1e3 * r.points[p][0]:.2f}, {1e3 * r.points[p][1]:.2f}" for p in points]
        rows.append(f"| {r.index} | {r.kind} | {r.verdict} | {r.steps} | " + " | ".join(cells)
                    + " |")
    return "\n".join(rows)


STOPS = ("failed", "failing", "undecided", "unstable")     # a stage verdict that ends a run
AFTER_FAILURE = ("stop", "continue")


def stops(record) -> bool:
    """Whether a stage that ended so leaves the model failed, or not known to stand: a solve
    (or a load) "failed", "failing" or "undecided", a search that found its failure level (the
    model is left in the failed state) or stopped undecided, a blow-up."""
    return record.verdict in STOPS


def stop_note(record, stages, moved) -> str:
    """The line a run stopped by ``record`` ends with: which stage, its verdict and level, the
    blocks that moved most in it (``moved``: their indices and displacements, m), and which
    stages did not run."""
    i, d = record.index, record.detail
    level = next((f" at {k} = {d[k]:.4g}" for k in ("failure_g", "first_failed",
                                                    "failure_value") if d.get(k) is not None),
                 "")
    blocks = ", ".join(f"{b} ({u:.3g} m)" for b, u in moved)
    left = (f"stages {i + 1}..{len(stages) - 1} not run" if len(stages) > i + 2 else
            f"stage {i + 1} not run")
    return (f"stage {i} ({record.kind}) ended {record.verdict}{level}; moved most in it: "
            f"blocks {blocks or 'none'}; {left} (after_failure: \"continue\" runs them)")


def moved_most(model, before, n=5) -> list:
    """The ``n`` active blocks that moved most since positions ``before`` (nb, 2):
    [(block, displacement m)], largest first."""
    u = np.hypot(*(model.state.pos - before).T) * (model.props.active > 0)
    top = np.argsort(-u, kind="stable")[:n]
    return [(int(b), float(u[b])) for b in top if u[b] > 0]


def stop_after(record, stages, model, before, after_failure="stop") -> bool:
    """Whether the run ends after ``record`` (the stage at ``record.index`` of ``stages``,
    the blocks at ``before`` (nb, 2) when it began): with ``after_failure`` "stop", a stage
    that ``stops`` with stages left; its ``detail["stopped"]`` then holds the ``stop_note``."""
    if after_failure != "stop" or not stops(record) or record.index + 1 >= len(stages):
        return False
    record.detail["stopped"] = stop_note(record, stages, moved_most(model, before))
    return True


def run_stages(model, stages, progress=None, on_level=None, after_failure="stop") -> list:
    """Run ``stages`` in order on ``model``; returns one StageRecord per stage run.
    ``progress``: optional callable(str), after each stage. ``on_level``: optional
    callable(index, stage, model, record) after each level of a search stage
    (``raise_gravity``, ``factor_of_safety``, ``strength_schedule``; ``record`` its
    ``limit.LimitRecord`` so far). ``after_failure``: "stop" ends the run after a stage that
    ``stops``, when stages are left (``stop_after``: its record's ``detail["stopped"]`` says
    which stage, at which level, which blocks moved most and which stages did not run);
    "continue" runs every stage. A stage that
    raises stops the run; the records of the finished stages are in the exception's
    ``records`` attribute. The stages are checked first (``check_stages``) against the model's
    groups and materials."""
    if after_failure not in AFTER_FAILURE:
        raise ValueError(f"after_failure must be one of {AFTER_FAILURE}, got {after_failure!r}")
    check_stages(stages, set(model.blocks.groups), model.materials)
    check_on_model(stages, model)
    records = []
    for i, st in enumerate(stages):
        t0, before = time.perf_counter(), model.state.pos.copy()
        try:
            if on_level is not None and isinstance(st, _SEARCHES):
                steps, verdict, detail = st.run(
                    model, on_level=lambda m, rec, i=i, st=st: on_level(i, st, m, rec))
            else:
                steps, verdict, detail = st.run(model)
        except Exception as e:
            e.records = records
            raise
        pts = {n: tuple(float(v) for v in model.point_motion(n)[:2]) for n in model.points}
        rec = StageRecord(i, _KIND_OF[type(st)], int(steps), verdict, float(model.time), pts,
                          model.crack_counts(), time.perf_counter() - t0, detail)
        records.append(rec)
        if progress is not None:
            progress(f"stage {i} {rec.kind}: {verdict}, {steps} steps, {rec.seconds:.1f} s")
        if stop_after(rec, stages, model, before, after_failure):
            if progress is not None:
                progress(rec.detail["stopped"])
            break
    return records
