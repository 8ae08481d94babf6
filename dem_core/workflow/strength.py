"""Strength searches as stages: the factor of safety by strength reduction, and a strength
schedule that lowers one property until the model fails.

Both are ``limit.search_failure`` (the g-ramp's engine: the same verdict, failure test,
bisection and closing steps) with a strength as the load parameter. A strength change moves no
stress (the incremental law, ``law.py``), so each level starts from the equilibrium of the one
before; the engine solves it to equilibrium or to the failure verdict.

Strength reduction (kind "factor_of_safety"), as 3DEC's and ``continuum_ref.ssr``'s: the chosen
materials' cohesion and friction are divided by F,

    c_F = c / F,    tan(phi_F) = tan(phi) / F          (peak and residual values)
    T_F = T / F                                         (only with ``tension=True``)

and F is raised through ``f_levels``; the factor of safety is the largest F that stands (the
last stable level), bracketed by the first that fails to within ``refine_to``. Reference:
Dawson, Roth & Drescher (1999) for the method; Itasca 3DEC manual, "factor of safety".

Strength schedule (kind "strength_schedule"): one property of one material (``tensile_strength``
or ``cohesion`` in Pa, ``friction`` in degrees) set to each of ``values`` in turn (each lower
than the one before and than the material's own value), solved each time; with ``refine_to``
the value at failure is bisected. The thesis's weathering of Checkerboard Creek is such a
schedule (ch. 7).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from ..settings import DEFAULT_SOLVE, SolveSettings
from .limit import LimitRecord, check_levels, search_failure

__all__ = ["search_verdict", "reduced_strength", "FactorOfSafety", "StrengthSchedule"]

SCHEDULED = ("tensile_strength", "cohesion", "friction")


def reduced_strength(material, factor, tension=False) -> dict:
    """The strength fields of ``material`` (``materials.Material``) divided by ``factor``
    (module docstring): a dict for ``Model.set_material``."""
    def phi(deg):
        return math.degrees(math.atan(math.tan(math.radians(deg)) / factor))
    out = {"cohesion": material.cohesion / factor, "friction": phi(material.friction),
           "residual_cohesion": material.residual_cohesion / factor}
    if material.residual_friction is not None:
        out["residual_friction"] = phi(material.residual_friction)
    if tension:
        out["tensile_strength"] = material.tensile_strength / factor
        out["residual_tensile_strength"] = material.residual_tensile_strength / factor
    return out


def _check_search(where, stage):
    """The stage's SolveSettings and its ``refine_to`` checked (ValueError naming ``where``)."""
    SolveSettings.of(stage).validated(where)
    refine_to = stage.refine_to
    if refine_to is not None and not (math.isfinite(refine_to) and refine_to > 0):
        raise ValueError(f"{where}: refine_to {refine_to!r} must be > 0")


def _known_materials(where, names, materials):
    if not names:
        raise ValueError(f"{where}: name at least one material")
    for n in names:
        if n not in materials:
            raise ValueError(f"{where} names unknown material {n!r}; materials are "
                             f"{sorted(materials)}")


def search_verdict(rec) -> str:
    """A search stage's verdict from its ``LimitRecord``: "failed" (a failure level was found),
    "unstable", "undecided" (it stopped at an undecided level) or "stood"."""
    if rec.failure_level is not None:
        return "failed"
    return "unstable" if rec.unstable else "undecided" if rec.undecided_level is not None \
        else "stood"


def _detail(rec, last_key, first_key, what) -> tuple:
    verdict = search_verdict(rec)
    return int(sum(rec.steps)), verdict, {last_key: rec.last_stable_level,
                                          first_key: rec.failure_level,
                                          what: list(rec.level),
                                          "verdicts": list(rec.verdict), "search": rec}


@dataclass(frozen=True)
class FactorOfSafety:
    """Strength-reduction factor of safety of ``materials`` (module docstring). ``f_levels``:
    increasing F > 0 to try; ``refine_to``: bracket width in F; ``tension``: reduce T too;
    the other fields as ``limit.search_failure``. Detail: ``factor_of_safety`` (the last F that
    stood; None if the first failed), ``first_failed``, ``F``, ``verdicts``, ``search``."""

    materials: tuple
    f_levels: tuple = (1.0, 1.25, 1.5, 2.0, 2.5, 3.0, 4.0)
    refine_to: float | None = 0.02
    tension: bool = False
    ratio: float = DEFAULT_SOLVE.ratio           # the level's SolveSettings (settings.py)
    max_steps: int | None = DEFAULT_SOLVE.max_steps
    failure_displacement: float | None = DEFAULT_SOLVE.failure_displacement
    creep: float | None = DEFAULT_SOLVE.creep
    watch: tuple = DEFAULT_SOLVE.watch
    settle: bool = DEFAULT_SOLVE.settle
    judge: str | None = DEFAULT_SOLVE.judge
    response_steps: int | None = DEFAULT_SOLVE.response_steps
    windows: int = DEFAULT_SOLVE.windows

    def check(self, i, groups, materials):
        where = f"stage {i} (factor_of_safety)"
        _known_materials(where, self.materials, materials)
        check_levels(self.f_levels, f"{where}: f_levels")
        if list(self.f_levels) != sorted(self.f_levels):
            raise ValueError(f"{where}: f_levels must increase, got {list(self.f_levels)}")
        _check_search(where, self)

    def run(self, model, on_level=None):
        """Run the search; ``on_level``: optional callable(model, record) after each level."""
        base = {n: model.materials[n] for n in self.materials}

        def apply(m, f_from, f):
            for n, mat in base.items():
                m.set_material(n, **reduced_strength(mat, f, self.tension))
        rec = search_failure(model, self.f_levels, apply, SolveSettings.of(self),
                             record=LimitRecord("F"), refine_to=self.refine_to,
                             on_level=on_level)
        return _detail(rec, "factor_of_safety", "first_failed", "F")


@dataclass(frozen=True)
class StrengthSchedule:
    """Lower ``property`` (one of SCHEDULED) of ``material`` through ``values`` (module
    docstring). Detail: ``last_stable_value``, ``failure_value``, ``values``, ``verdicts``,
    ``search``."""

    material: str
    property: str
    values: tuple
    refine_to: float | None = None
    ratio: float = DEFAULT_SOLVE.ratio           # the level's SolveSettings (settings.py)
    max_steps: int | None = DEFAULT_SOLVE.max_steps
    failure_displacement: float | None = DEFAULT_SOLVE.failure_displacement
    creep: float | None = DEFAULT_SOLVE.creep
    watch: tuple = DEFAULT_SOLVE.watch
    settle: bool = DEFAULT_SOLVE.settle
    judge: str | None = DEFAULT_SOLVE.judge
    response_steps: int | None = DEFAULT_SOLVE.response_steps
    windows: int = DEFAULT_SOLVE.windows

    def check(self, i, groups, materials):
        where = f"stage {i} (strength_schedule)"
        _known_materials(where, [self.material], materials)
        if self.property not in SCHEDULED:
            raise ValueError(f"{where}: property {self.property!r} must be one of {SCHEDULED}")
        v = check_levels(self.values, f"{where}: values", positive=False)
        now = getattr(materials[self.material], self.property)
        if not (v[0] < now and (len(v) == 1 or v[1] < v[0])) or v.min() < 0:
            raise ValueError(f"{where}: a schedule must lower {self.property} of "
                             f"{self.material!r} (now {now!r}) through decreasing values >= 0, "
                             f"got {list(self.values)}")
        _check_search(where, self)

    def run(self, model, on_level=None):
        """Run the search; ``on_level``: optional callable(model, record) after each level."""
        now = getattr(model.materials[self.material], self.property)
        rec = search_failure(model, self.values,
                             lambda m, a, b: m.set_material(self.material, **{self.property: b}),
                             SolveSettings.of(self), record=LimitRecord(self.property),
                             refine_to=self.refine_to, start=now, on_level=on_level)
        return _detail(rec, "last_stable_value", "failure_value", "values")
