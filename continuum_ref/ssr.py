"""Limit searches on a ContinuumModel: factor of safety by strength reduction, critical g-level.

Failure criterion (both searches)
---------------------------------
The load parameter lambda (F or g) is advanced from its start with step cutting
(`newton.load_path`): a step whose Newton iterations do not converge (residual not below
rtol x reaction force within max_iterations, NaN, or divergence; `continuum_ref.newton`) is
undone and halved, so the search narrows a bracket [last converged, first failed]. It ends when
the step falls below `tol` (the smallest step). During a strength reduction Newton also gives
up when its residual is still above its start value after 8 iterations (`NewtonSettings.stall`;
most failing attempts otherwise wander at 1e3-1e4 times that value for all their iterations:
this took about a quarter off the run time; `critical_g` keeps the model's settings so that
the centrifuge comparisons are unchanged). Non-convergence at the smallest step is called
**failure (a limit)** only if it comes with a mechanism:

    d max|u - u_0| / d lambda  >=  upturn x u_el / lambda_ref        (default upturn = 10)

over the last converged step, where u_0 is the displacement at the start of the search, u_el
the largest displacement of the *linear elastic* response to the same loads
(`ContinuumModel.elastic_displacement`) and lambda_ref the start value of a g-search (so u_el /
lambda_ref is the elastic-range slope and the test reads "the displacement grows at least ten
times faster than in the elastic range") or 1 for F (an F step of 0.01 must add 10 % of u_el).
A converged state whose max |u| exceeds `runaway` (m, optional) is a mechanism as well. If Newton
fails at the smallest step without a mechanism, the result says so (`mechanism` False,
`found` False): a solver failure, not a factor of safety.

Why a plain non-convergence is not enough: with non-associated flow (psi < phi) perfectly
plastic Mohr-Coulomb is not stable in Hill's sense (second-order work can be negative at any
yielding point), and a zone of contained yielding under the slope (the soil below the crest,
where the horizontal stress is low) makes Newton fail there with no displacement growth. On the
slope of tests/test_continuum_ssr.py with psi = 0 this happens at F = 1.54, 1.36 and 1.31 for
h = 1, 0.5 and 0.25 m (Bishop 1.60): the old search took these for the factor of safety. With
associated flow the same searches end in a mechanism at F = 1.641, 1.622, 1.607.
docs/continuum.md has the numbers; the mesh dependence of non-associated strength reduction is
known (Tschuchnigg et al. 2015, Computers and Geotechnics 70; Sysala et al. 2021, Int. J. Numer.
Anal. Methods Geomech. 45).

Strength reduction convention (Mohr-Coulomb): c/F, tan(phi)/F, tan(psi)/F and tensile
strength/F (see `MohrCoulomb.reduced`) of the effective strength where a pore pressure is set;
elastic materials are not reduced. Hoek-Brown has no agreed reduction: convert it to equivalent
Mohr-Coulomb first (`hoek_brown.equivalent_mohr_coulomb`).
"""
import math
import time
from dataclasses import dataclass, replace

import numpy as np

from .materials import Elastic, MohrCoulomb

__all__ = ["LimitResult", "critical_g", "factor_of_safety"]

STALL_ITERATIONS = 8   # NewtonSettings.stall during strength reduction (if 0 in the settings)


@dataclass
class LimitResult:
    """Result of a limit search.

    Attributes
    ----------
    value : float
        Last stable load parameter (critical g-level or factor of safety).
    first_failed : float or None
        Smallest value that did not converge at the smallest step (None if the search range
        ended stable).
    steps, newton_iterations : int
        Converged steps and their total Newton iterations.
    run_time : float
        Wall time (s).
    history : list of (parameter, max |u| in m)
        Converged states along the search (the displacement-versus-parameter curve).
    mechanism : bool
        True if the non-convergence came with a mechanism (module docstring).
    upturn : float
        d max|u - u_0| / d lambda over the last converged step divided by u_el / lambda_ref.
    elastic_displacement : float
        u_el (m).
    """

    value: float
    first_failed: float
    steps: int
    newton_iterations: int
    run_time: float
    history: list
    mechanism: bool = False
    upturn: float = math.nan
    elastic_displacement: float = math.nan

    @property
    def found(self):
        """True if the search ended in a limit (non-convergence with a mechanism)."""
        return self.first_failed is not None and self.mechanism


def _with_runaway(model, runaway, flag):
    """Wrap the model's Newton attempt so that a runaway displacement counts as failure."""
    attempt = model._attempt

    def guarded():
        result = attempt()
        if result.converged and runaway is not None and np.max(np.abs(model.u.x.array)) > runaway:
            result.converged = False
            flag.append(True)
        return result
    return guarded


def _upturn(states, rate_scale):
    """Slope of max|u - u_0| against lambda over the last converged step, / rate_scale."""
    if len(states) < 2 or not rate_scale > 0:
        return math.nan
    (t0, d0), (t1, d1) = states[-2], states[-1]
    return abs(d1 - d0) / abs(t1 - t0) / rate_scale


def _search(model, label, apply, t0, t1, first_step, tol, runaway, lambda_ref, upturn,
            stall=0):
    from .newton import load_path
    start = time.perf_counter()
    if model._forms is None:
        model._build_forms()
    model._saved = model._snapshot()
    u_el = model.elastic_displacement()
    u0 = model.u.x.array.copy()
    history, states, ran_away = [], [(t0, 0.0)], []

    def converged(t):
        history.append((t, float(np.max(np.abs(model.u.x.array)))))
        states.append((t, float(np.max(np.abs(model.u.x.array - u0)))))
        model._record(t, label)
    settings = model.newton_settings
    model.newton_settings = replace(settings, stall=settings.stall or stall)
    try:
        t, records, failed = load_path(apply, _with_runaway(model, runaway, ran_away),
                                       model._commit, model._restore, t0, t1, first_step, tol,
                                       on_converged=converged)
    finally:
        model.newton_settings = settings
    ratio = _upturn(states, u_el / lambda_ref)
    mechanism = failed is not None and (bool(ran_away) or ratio >= upturn)
    return LimitResult(t, failed, len(records), sum(r.iterations for r in records),
                       time.perf_counter() - start, history, mechanism, ratio, u_el)


def critical_g(model, g_max, first_step=None, tol=0.05, runaway=None, upturn=10.0):
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
    upturn : float
        Mechanism threshold (module docstring).
    """
    if not g_max > model.g_level:
        raise ValueError(f"g_max={g_max!r} must exceed the current g-level {model.g_level}")
    if not model.g_level > 0:
        raise ValueError("critical_g starts from a model at equilibrium under gravity (g > 0)")
    first_step = first_step or (g_max - model.g_level) / 10.0
    return _search(model, "g", model.set_gravity, model.g_level, g_max, first_step, tol, runaway,
                   model.g_level, upturn)


def factor_of_safety(model, base_materials, f_max=10.0, f_start=1.0, first_step=0.25,
                     tol=0.0025, runaway=None, upturn=10.0):
    """Shear strength reduction factor of safety at the model's current loads.

    Parameters
    ----------
    model : ContinuumModel
        At equilibrium with `base_materials` reduced by f_start (normally F = 1, the
        unreduced strength).
    base_materials : list
        The unreduced materials in the model's order (Mohr-Coulomb or Elastic).
    f_max, f_start, first_step, tol : float
        Search range, first increment of F and the smallest step (the resolution; small
        enough that the last converged state is near the limit, where the mechanism shows).
    runaway : float, optional
        See the module docstring.
    upturn : float
        Mechanism threshold (module docstring).

    Returns
    -------
    LimitResult
        `value` is the factor of safety when `found` (a mechanism formed).
    """
    for m in base_materials:
        if not isinstance(m, (MohrCoulomb, Elastic)):
            raise TypeError(f"strength reduction needs Mohr-Coulomb or elastic materials, got "
                            f"{type(m).__name__}; convert Hoek-Brown with "
                            f"hoek_brown.equivalent_mohr_coulomb")

    def apply(f):
        model.set_materials([m.reduced(f) if isinstance(m, MohrCoulomb) else m
                             for m in base_materials])
    return _search(model, "F", apply, f_start, f_max, first_step, tol, runaway, 1.0, upturn,
                   STALL_ITERATIONS)
