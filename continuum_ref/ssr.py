"""Limit searches on a ContinuumModel: factor of safety by strength reduction, critical g-level.

Failure criterion (both searches)
---------------------------------
A state "fails" when the Newton iterations of `continuum_ref.newton` do not converge
(residual not below rtol x reaction force within max_iterations, NaN, or divergence) **or**
the converged displacement runs away: max |u| at any node exceeds `runaway` (m). The load is
advanced with step halving on failure (continuation from the last converged state, i.e. a
bisection between the last stable and the first failed value) until the step is below `tol`.
The limit is reported as the bracket [last stable, first failed] (narrower than 2 tol); its
lower end is the value.

Strength reduction convention (Mohr-Coulomb): c/F, tan(phi)/F, tan(psi)/F and tensile
strength/F (see `MohrCoulomb.reduced`); elastic materials are not reduced. Hoek-Brown has no
agreed reduction: convert it to equivalent Mohr-Coulomb first
(`hoek_brown.equivalent_mohr_coulomb`).
"""
import time
from dataclasses import dataclass

import numpy as np

from .materials import Elastic, MohrCoulomb

__all__ = ["LimitResult", "critical_g", "factor_of_safety"]


@dataclass
class LimitResult:
    """Result of a limit search.

    Attributes
    ----------
    value : float
        Last stable load parameter (critical g-level or factor of safety).
    first_failed : float or None
        First failed value (None if the search range ended stable).
    steps, newton_iterations : int
        Converged steps and their total Newton iterations.
    run_time : float
        Wall time (s).
    history : list of (parameter, max |u| in m)
        Converged states along the search (the displacement-versus-parameter curve).
    """

    value: float
    first_failed: float
    steps: int
    newton_iterations: int
    run_time: float
    history: list

    @property
    def found(self):
        return self.first_failed is not None


def _with_runaway(model, runaway):
    """Wrap the model's Newton attempt so that a runaway displacement counts as failure."""
    attempt = model._attempt

    def guarded():
        result = attempt()
        if result.converged and runaway is not None and np.max(np.abs(model.u.x.array)) > runaway:
            result.converged = False
        return result
    return guarded


def _search(model, label, apply, t0, t1, first_step, tol, runaway):
    from .newton import load_path
    start = time.perf_counter()
    if model._forms is None:
        model._build_forms()
    model._saved = model._snapshot()
    history = []

    def converged(t):
        history.append((t, float(np.max(np.abs(model.u.x.array)))))
        model._record(t, label)
    t, records, failed = load_path(apply, _with_runaway(model, runaway), model._commit,
                                   model._restore, t0, t1, first_step, tol,
                                   on_converged=converged)
    return LimitResult(t, failed, len(records), sum(r.iterations for r in records),
                       time.perf_counter() - start, history)


def critical_g(model, g_max, first_step=None, tol=0.05, runaway=None):
    """Raise gravity from the model's current level towards g_max until failure.

    Parameters
    ----------
    model : ContinuumModel
        At equilibrium at its current g-level (e.g. 1 g).
    g_max : float
        Upper end of the search (multiples of 9.81 m/s2).
    first_step : float, optional
        Initial g increment (default (g_max - g) / 10).
    tol : float
        Resolution of the limit (smallest g increment tried).
    runaway : float, optional
        Displacement (m) beyond which a converged state is called failed.
    """
    if not g_max > model.g_level:
        raise ValueError(f"g_max={g_max!r} must exceed the current g-level {model.g_level}")
    first_step = first_step or (g_max - model.g_level) / 10.0
    return _search(model, "g", model.set_gravity, model.g_level, g_max, first_step, tol, runaway)


def factor_of_safety(model, base_materials, f_max=10.0, f_start=1.0, first_step=0.25, tol=0.01,
                     runaway=None):
    """Shear strength reduction factor of safety at the model's current loads.

    Parameters
    ----------
    model : ContinuumModel
        At equilibrium with `base_materials` reduced by f_start (normally F = 1, the
        unreduced strength).
    base_materials : list
        The unreduced materials in the model's order (Mohr-Coulomb or Elastic).
    f_max, f_start, first_step, tol : float
        Search range, first increment of F and resolution.
    runaway : float, optional
        See the module docstring.
    """
    for m in base_materials:
        if not isinstance(m, (MohrCoulomb, Elastic)):
            raise TypeError(f"strength reduction needs Mohr-Coulomb or elastic materials, got "
                            f"{type(m).__name__}; convert Hoek-Brown with "
                            f"hoek_brown.equivalent_mohr_coulomb")

    def apply(f):
        model.set_materials([m.reduced(f) if isinstance(m, MohrCoulomb) else m
                             for m in base_materials])
    return _search(model, "F", apply, f_start, f_max, first_step, tol, runaway)
