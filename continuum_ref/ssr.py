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

Non-associated flow (psi < phi): two ways to a limit
----------------------------------------------------
``flow="davis"`` (Davis 1968; "Davis B" of Tschuchnigg, Schweiger & Sloan 2015, Computers and
Geotechnics 70, Part I and II): at each F the reduced strength c_F = c/F, tan(phi_F) =
tan(phi)/F, psi_F (as in `MohrCoulomb.reduced`) is replaced by its associated equivalent

    beta_F = cos(psi_F) cos(phi_F) / (1 - sin(psi_F) sin(phi_F)),
    c* = beta_F c_F,  tan(phi*) = beta_F tan(phi_F),  psi* = phi*  (`MohrCoulomb.davis`)

and Newton solves the associated problem, which has a unique limit. Bias: conservative. Along
a thin shear band of a psi < phi material the stresses obey tau = c* + sigma tan(phi*) (Davis
1968), so for rigid blocks sliding on thin bands the non-associated collapse load is the
associated one with (c*, phi*) (Drescher & Detournay 1993, Geotechnique 43(3)); for diffuse
flow it is an approximation on the safe side. With psi = 0 the F found is the associated F
times beta_F = cos(phi_F) (0.94 at phi = 30 deg, F = 1.5). "Davis A" (beta from the unreduced
phi and psi, then reduced by F) is lower still (beta = cos(phi) = 0.87). Our psi_F is
atan(tan(psi)/F) kept <= phi_F; Sysala et al. (2021, Int. J. Numer. Anal. Methods Geomech. 45)
put both variants in a variational setting.

``relaxation=RelaxationSettings(...)`` (native flow): each F step is solved by the
initial-stiffness iteration (`newton.relax`: elastic stiffness, Anderson mixing; the
viscoplastic path of Griffiths & Lane 1999, Geotechnique 49(3)) instead of Newton, so contained
yielding converges and the search goes further. It is not a mesh-independent method: on the
slope of the tests it ends in a mechanism at F = 1.570 (h = 1 m) and 1.557-1.564 (h = 0.5 m,
depending on the iteration budget) but stops without one at 1.53 (h = 0.25 m), at many times
the cost of Newton; the limit falls with h towards Davis' value, as a thin band of a psi < phi
material carries only the Davis strength. docs/continuum.md has the numbers and times.

Without either, a non-associated search that ends without a mechanism says so in
`LimitResult.note`.

Strength reduction convention (Mohr-Coulomb): c/F, tan(phi)/F, tan(psi)/F and tensile
strength/F (see `MohrCoulomb.reduced`) of the effective strength where a pore pressure is set;
elastic materials are not reduced. Hoek-Brown has no agreed reduction: the rock mass is
replaced by its equivalent Mohr-Coulomb (`HoekBrown.equivalent_mohr_coulomb`: Hoek et al. 2002
fit over st < sigma3 < sigma3_max, cut-off at st, a dilation of your choice) and reduced by
the same rule, with ``flow="davis"`` or ``relaxation`` as above when psi < phi.
"""
import math
import time
from dataclasses import dataclass, replace

import numpy as np

from .materials import Elastic, HoekBrown, MohrCoulomb
from .newton import RelaxationSettings

__all__ = ["LimitResult", "RelaxationSettings", "critical_g", "factor_of_safety"]

STALL_ITERATIONS = 8   # NewtonSettings.stall during strength reduction (if 0 in the settings)
FLOWS = ("native", "davis")


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
        Converged steps and their total Newton (or relaxation) iterations.
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
    note : str
        The verdict in words (a limit, stable to the end of the range, or why no limit).
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
    note: str = ""

    @property
    def found(self):
        """True if the search ended in a limit (non-convergence with a mechanism)."""
        return self.first_failed is not None and self.mechanism


def _with_runaway(model, attempt, runaway, flag):
    """Wrap a Newton (or relaxation) attempt so that a runaway displacement counts as failure."""
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
            stall=0, attempt=None):
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
        t, records, failed = load_path(apply, _with_runaway(model, attempt or model._attempt,
                                                            runaway, ran_away),
                                       model._commit, model._restore, t0, t1, first_step, tol,
                                       on_converged=converged)
    finally:
        model.newton_settings = settings
    ratio = _upturn(states, u_el / lambda_ref)
    mechanism = failed is not None and (bool(ran_away) or ratio >= upturn)
    return LimitResult(t, failed, len(records), sum(r.iterations for r in records),
                       time.perf_counter() - start, history, mechanism, ratio, u_el)


def _verdict(result, label, upturn, hint=""):
    """`LimitResult.note`: what the search ended in, in words."""
    if result.first_failed is None:
        return f"stable up to {label} = {result.value:.4g} (the end of the search range)"
    if result.mechanism:
        return (f"limit at {label} = {result.value:.4g}: no convergence at "
                f"{result.first_failed:.4g} with a mechanism (upturn {result.upturn:.3g})")
    return (f"no limit: the solver stopped converging at {label} = {result.first_failed:.4g} "
            f"without a mechanism (upturn {result.upturn:.3g} < {upturn:g}); a solver "
            f"failure, not a limit" + hint)


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
    result = _search(model, "g", model.set_gravity, model.g_level, g_max, first_step, tol,
                     runaway, model.g_level, upturn)
    result.note = _verdict(result, "g", upturn)
    return result


def factor_of_safety(model, base_materials, f_max=10.0, f_start=1.0, first_step=0.25,
                     tol=0.0025, runaway=None, upturn=10.0, flow="native", relaxation=None):
    """Shear strength reduction factor of safety at the model's current loads.

    Parameters
    ----------
    model : ContinuumModel
        At equilibrium with `base_materials` reduced by f_start (normally F = 1, the
        unreduced strength).
    base_materials : list
        The unreduced materials in the model's order (Mohr-Coulomb or Elastic). A Hoek-Brown
        rock mass enters as `HoekBrown.equivalent_mohr_coulomb(sigma3_max, dilation)` (c and
        phi of the Hoek et al. 2002 fit, cut-off at s sci / mb) and is reduced by the
        Mohr-Coulomb rule below; the Hoek-Brown constants themselves are not reduced.
    f_max, f_start, first_step, tol : float
        Search range, first increment of F and the smallest step (the resolution; small
        enough that the last converged state is near the limit, where the mechanism shows).
    runaway : float, optional
        See the module docstring.
    upturn : float
        Mechanism threshold (module docstring).
    flow : "native" or "davis"
        "native": c/F, tan(phi)/F, tan(psi)/F, T/F with each material's own dilation.
        "davis": the same, then the associated equivalent of Davis (1968) of the reduced
        values, c* = beta_F c/F, tan(phi*) = beta_F tan(phi)/F, beta_F = cos(psi_F)
        cos(phi_F) / (1 - sin(psi_F) sin(phi_F)) (module docstring: conservative); the model
        is first brought to equilibrium with it at f_start.
    relaxation : RelaxationSettings, optional
        Solve each step by the initial-stiffness relaxation (`newton.relax`) instead of
        Newton; for native non-associated flow (module docstring).

    Returns
    -------
    LimitResult
        `value` is the factor of safety when `found` (a mechanism formed); `note` says what
        the search ended in.
    """
    _check_materials(base_materials, flow)

    def apply(f):
        model.set_materials([_reduce(m, f, flow) for m in base_materials])
    attempt = model._attempt if relaxation is None else (
        lambda: model._attempt_relaxed(relaxation))
    if flow == "davis" and not _settle(model, apply, f_start, attempt):
        return LimitResult(f_start, f_start, 0, 0, 0.0, [], note=(
            f"no limit: the Davis materials at F = {f_start:g} are not in equilibrium with the "
            f"model's loads; start the search lower (f_start)"))
    result = _search(model, "F", apply, f_start, f_max, first_step, tol, runaway, 1.0, upturn,
                     STALL_ITERATIONS, attempt)
    result.note = _verdict(result, "F", upturn, _hint(base_materials, flow, relaxation))
    return result


def _settle(model, apply, f, attempt):
    """Bring the model to equilibrium with the materials of `apply(f)`; False (and the model
    as it was, materials included) if that does not converge."""
    if model._forms is None:
        model._build_forms()
    before = list(model.materials)
    model._saved = model._snapshot()
    apply(f)
    if attempt().converged:
        model._commit()
        return True
    model._restore()
    model.set_materials(before)
    return False


def _reduce(material, f, flow):
    """A base material at strength-reduction factor f under `flow` (module docstring)."""
    if not isinstance(material, MohrCoulomb):
        return material
    reduced = material.reduced(f)
    return reduced.davis() if flow == "davis" else reduced


def _check_materials(base_materials, flow):
    """Refuse an unknown flow and materials strength reduction cannot reduce."""
    if flow not in FLOWS:
        raise ValueError(f"flow={flow!r}: one of {FLOWS}")
    for m in base_materials:
        if isinstance(m, HoekBrown):
            raise TypeError("strength reduction of a Hoek-Brown rock mass goes through its "
                            "equivalent Mohr-Coulomb: HoekBrown.equivalent_mohr_coulomb("
                            "sigma3_max, dilation)")
        if not isinstance(m, (MohrCoulomb, Elastic)):
            raise TypeError(f"strength reduction needs Mohr-Coulomb or elastic materials, got "
                            f"{type(m).__name__}")


def _hint(base_materials, flow, relaxation):
    """Why a native non-associated Newton search may end without a mechanism, if it may."""
    if flow != "native" or relaxation is not None or not any(
            isinstance(m, MohrCoulomb) and m.psi < m.friction for m in base_materials):
        return ""
    return ("; with non-associated flow (psi < phi) Newton fails in contained yielding: "
            "flow='davis' finds the (conservative) Davis limit, relaxation=RelaxationSettings()"
            " follows the native path further (continuum_ref.ssr)")
