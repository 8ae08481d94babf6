"""Newton iterations and load stepping with step cutting (independent of DOLFINx).

The model supplies three callables; this module only decides when to stop and how to step.

Convergence of one Newton solve: ||R_free|| <= rtol * max(||reactions||, ||R_0||) + atol,
where R_free is the residual at free dofs and the reactions (residual at constrained dofs) give
the force scale of the problem (they balance gravity, tractions and prescribed displacements).
**Non-convergence** (what `load_path` answers with a smaller step): the criterion above is not
met within `max_iterations`, or the residual becomes NaN, or it grows beyond `divergence` times
its initial value, or (if `stall` > 0) it is still above its initial value after `stall`
iterations (a fail-fast rule for limit searches, where most failing attempts wander at
1e3-1e4 times their initial residual for all `max_iterations`). Whether non-convergence at the
smallest step is a *limit* is decided by the caller (`continuum_ref.ssr`).

Line search (when the caller can scale a correction, `scale_step`): a full Newton correction
that does not lower the residual norm, ||R(u - du)|| > (1 - 1e-4) ||R(u)||, is halved up to
`line_search` times (u - du/2, u - du/4, ...) and the trial with the smallest residual is kept.
Corrections that still carry prescribed boundary values are always taken in full (the lifting
imposes them exactly). Off by default: on the non-associated (psi = 0) slope of
tests/test_continuum_ssr.py, where a full correction made the residual jump by 1e2-1e4, it
turned divergence into stagnation without moving the limit, and with psi = phi it made the
searches 2-6 times slower. Reference: Dennis & Schnabel (1996), Numerical Methods for
Unconstrained Optimization and Nonlinear Equations, ch. 6.

Relaxation (`relax`, for non-associated strength reduction): the initial-stiffness iteration
u_{k+1} = u_k - K_e^{-1} R(u_k) with the *elastic* stiffness K_e (factorised once), which is
the viscoplastic pseudo-time path of Zienkiewicz & Cormeau (1974) with the largest stable step
as Griffiths & Lane (1999) use it for slopes, accelerated by Anderson mixing (Anderson 1965;
Walker & Ni 2011, SIAM J. Numer. Anal. 49). K_e is positive definite, so every iterate is
defined where the consistent tangent of psi < phi flow is indefinite and Newton jumps. It
converges linearly: same convergence test as Newton with a looser default rtol (1e-4), and
non-convergence means max_iterations without it, a NaN, or divergence.
"""
from dataclasses import dataclass, field

import numpy as np

__all__ = ["NewtonSettings", "NewtonResult", "newton", "RelaxationSettings", "relax",
           "StepRecord", "load_path"]


@dataclass
class NewtonSettings:
    """Tolerances: see the module docstring. Units of atol: N (per metre of thickness)."""

    rtol: float = 1e-8
    atol: float = 1e-10
    max_iterations: int = 25
    divergence: float = 1e8
    line_search: int = 0            # halvings tried (0: full Newton steps)
    stall: int = 0                  # fail if the residual is still above its start value
                                    # after this many iterations (0: off)


@dataclass
class NewtonResult:
    converged: bool
    iterations: int
    residuals: list = field(default_factory=list)


def newton(residual, solve_and_update, settings, scale_step=None):
    """Run Newton iterations.

    Parameters
    ----------
    residual : callable () -> (norm, reaction_norm, pending)
        Updates stresses from the current displacement and assembles the residual; `pending`
        is True while prescribed boundary values are not yet imposed (forces another step).
    solve_and_update : callable () -> None
        Assembles the tangent, solves for the correction and updates the displacement.
    settings : NewtonSettings
    scale_step : callable (alpha) -> None, optional
        Replaces the last full correction by alpha times it (enables the line search).
    """
    history = []
    ref = None
    r, reaction, pending = residual()
    for it in range(settings.max_iterations + 1):
        history.append(r)
        if not np.isfinite(r):
            return NewtonResult(False, it, history)
        ref = reaction if ref is None else max(ref, reaction)
        if not pending and r <= settings.rtol * ref + settings.atol:
            return NewtonResult(True, it, history)
        if r > settings.divergence * max(history[0], settings.atol) or (
                0 < settings.stall <= it and r > history[0]):
            return NewtonResult(False, it, history)
        if it == settings.max_iterations:
            break
        solve_and_update()
        r_full = residual()
        search = scale_step is not None and settings.line_search > 0 and not pending
        r, reaction, pending = _line_search(residual, scale_step, r, r_full,
                                            settings.line_search) if search else r_full
    return NewtonResult(False, settings.max_iterations, history)


def _line_search(residual, scale_step, r0, full, halvings):
    """Backtrack on the residual norm from a full correction (module docstring)."""
    if np.isfinite(full[0]) and full[0] <= (1.0 - 1e-4) * r0:
        return full
    best, best_alpha, alpha = full, 1.0, 1.0
    for _ in range(halvings):
        alpha *= 0.5
        scale_step(alpha)
        trial = residual()
        if np.isfinite(trial[0]) and not trial[0] >= best[0]:
            best, best_alpha = trial, alpha
        if best_alpha == alpha and trial[0] <= (1.0 - 1e-4 * alpha) * r0:
            return trial
    if best_alpha != alpha:
        scale_step(best_alpha)
        best = residual()
    return best


@dataclass(frozen=True)
class RelaxationSettings:
    """Settings of `relax` (module docstring). Units of atol: N (per metre of thickness).

    rtol : convergence when ||R|| <= rtol * max(||reactions||) + atol.
    max_iterations : the budget of one attempt (its end is a non-convergence).
    depth : number of previous iterates that Anderson mixing combines (0: plain iteration).
    """

    rtol: float = 1e-4
    atol: float = 1e-10
    max_iterations: int = 300
    depth: int = 8
    divergence: float = 1e8

    def __post_init__(self):
        if not (0 < self.rtol < 1 and self.atol >= 0 and self.max_iterations >= 1
                and self.depth >= 0 and self.divergence > 1):
            raise ValueError(f"invalid RelaxationSettings {self}")


def relax(residual, correction, get_x, set_x, settings):
    """Anderson-accelerated fixed-stiffness iteration x <- x + g(x), g = -K^{-1} R(x).

    Parameters
    ----------
    residual : callable () -> (norm, reaction_norm, pending), as in `newton`
    correction : callable () -> array
        K^{-1} R at the current x (the correction `newton` would subtract, with a fixed K).
    get_x, set_x : callables
        Copy of the unknowns (array) and their replacement.
    settings : RelaxationSettings

    Anderson mixing (type II): with the last m+1 iterates x_i and steps g_i,
    gamma = argmin ||g_k - dG gamma||, x_{k+1} = x_k + g_k - (dX + dG) gamma, where the
    columns of dX, dG are differences of successive x_i, g_i. A pending step (boundary values
    not yet imposed) is taken in full and restarts the mixing.
    """
    xs, gs, history, ref = [], [], [], None
    for it in range(settings.max_iterations + 1):
        r, reaction, pending = residual()
        history.append(r)
        ref = reaction if ref is None else max(ref, reaction)
        if not np.isfinite(r) or r > settings.divergence * max(history[0], settings.atol):
            return NewtonResult(False, it, history)
        if not pending and r <= settings.rtol * ref + settings.atol:
            return NewtonResult(True, it, history)
        if it == settings.max_iterations:
            break
        x, g = get_x(), -correction()
        if not np.all(np.isfinite(g)):
            return NewtonResult(False, it, history)
        xs, gs = ([], []) if pending else (xs + [x], gs + [g])
        xs, gs = xs[-(settings.depth + 1):], gs[-(settings.depth + 1):]
        set_x(x + g if len(xs) < 2 else _anderson(xs, gs))
    return NewtonResult(False, settings.max_iterations, history)


def _anderson(xs, gs):
    """Anderson type-II update from iterates xs and fixed-point steps gs (lists, newest last)."""
    dX = np.stack([b - a for a, b in zip(xs[:-1], xs[1:])], axis=1)
    dG = np.stack([b - a for a, b in zip(gs[:-1], gs[1:])], axis=1)
    gamma = np.linalg.lstsq(dG, gs[-1], rcond=None)[0]
    return xs[-1] + gs[-1] - (dX + dG) @ gamma


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
