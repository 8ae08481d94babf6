"""Newton iterations and load stepping with step cutting (independent of DOLFINx).

The model supplies three callables; this module only decides when to stop and how to step.

Convergence of one Newton solve: ||R_free|| <= rtol * max(||reactions||, ||R_0||) + atol,
where R_free is the residual at free dofs and the reactions (residual at constrained dofs) give
the force scale of the problem (they balance gravity, tractions and prescribed displacements).
**Non-convergence** (the documented failure signal used by `ssr`): the criterion above is not met
within `max_iterations`, or the residual becomes NaN, or it grows beyond `divergence` times its
initial value.
"""
from dataclasses import dataclass, field

import numpy as np

__all__ = ["NewtonSettings", "NewtonResult", "newton", "StepRecord", "load_path"]


@dataclass
class NewtonSettings:
    """Tolerances: see the module docstring. Units of atol: N (per metre of thickness)."""

    rtol: float = 1e-8
    atol: float = 1e-10
    max_iterations: int = 25
    divergence: float = 1e8


@dataclass
class NewtonResult:
    converged: bool
    iterations: int
    residuals: list = field(default_factory=list)


def newton(residual, solve_and_update, settings):
    """Run Newton iterations.

    Parameters
    ----------
    residual : callable () -> (norm, reaction_norm, pending)
        Updates stresses from the current displacement and assembles the residual; `pending`
        is True while prescribed boundary values are not yet imposed (forces another step).
    solve_and_update : callable () -> None
        Assembles the tangent, solves for the correction and updates the displacement.
    settings : NewtonSettings
    """
    history = []
    ref = None
    for it in range(settings.max_iterations + 1):
        r, reaction, pending = residual()
        history.append(r)
        if not np.isfinite(r):
            return NewtonResult(False, it, history)
        ref = reaction if ref is None else max(ref, reaction)
        if not pending and r <= settings.rtol * ref + settings.atol:
            return NewtonResult(True, it, history)
        if r > settings.divergence * max(history[0], settings.atol):
            return NewtonResult(False, it, history)
        if it == settings.max_iterations:
            break
        solve_and_update()
    return NewtonResult(False, settings.max_iterations, history)


@dataclass
class StepRecord:
    """One converged load step: load parameter t and Newton iterations used."""

    t: float
    iterations: int


def load_path(apply_load, attempt, save, restore, t_start, t_end, first_step, min_step,
              grow=1.5, on_converged=None):
    """Advance a load parameter from t_start to t_end with step cutting.

    Each step: apply_load(t); attempt() -> NewtonResult. On success the state is saved and
    the step grows by `grow` (up to first_step); on failure the state is restored and the step
    halved. Stops when t_end is reached or the step falls below min_step.

    Returns
    -------
    (t_reached, records, failed_at)
        failed_at is the smallest load parameter that did not converge (None if t_end reached).
    """
    if first_step <= 0 or min_step <= 0:
        raise ValueError(f"first_step={first_step} and min_step={min_step} must be > 0")
    t, dt, records = t_start, first_step, []
    direction = 1.0 if t_end >= t_start else -1.0
    while direction * (t_end - t) > 1e-14 * max(1.0, abs(t_end)):
        t_try = t + direction * min(dt, abs(t_end - t))
        apply_load(t_try)
        result = attempt()
        if result.converged:
            save()
            t = t_try
            records.append(StepRecord(t, result.iterations))
            if on_converged is not None:
                on_converged(t)
            dt = min(first_step, dt * grow)
        else:
            restore()
            apply_load(t)
            dt *= 0.5
            if dt < min_step:
                return t, records, t_try
    return t, records, None
