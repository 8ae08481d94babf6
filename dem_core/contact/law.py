"""The flaw/joint contact law: incremental Coulomb slip with a tension cut-off and residual
strength (thesis section 3.4, eqs 3.1-3.5), compression positive.

Each contact keeps its stresses and updates them from the increments of its normal opening
``du_n`` and shear displacement ``du_s`` (m) over the step::

    sn_e <- sn_e - kn du_n                    elastic normal stress (u_n > 0 is opening)
    ts   <- ts   - ks du_s                    trial shear stress
    if sn_e < -T:  separated: sn = ts = 0     an intact bond has failed in tension: T and c drop
                                              to residual; sn_e keeps counting the opening, so
                                              the contact carries load again only once closed
    tau_max = max(0, c + sn_e tan(phi))
    if |ts| > tau_max:  ts = sign(ts) tau_max  slip; an intact bond has failed in shear: T and c
                                              drop to residual, friction stays (phi_res)

A contact that has failed (or was never bonded) uses the residual T, c and friction. Only a
bond (peak T or c above the residual) can fail; a joint with T = c = 0 just opens or slips. The
stress at the step of a shear failure is the peak limit; the residual applies from the next
step. A glued (unbreakable) material is elastic with no limit.

Because stresses are state, a contact can start with any stress (an initial stress field) and
a change of strength or stiffness between stages moves no stress: stiffness acts on increments
only. With constant stiffness and no initial stress, sn_e = -kn u_n as in a total law.
``strength`` rows are [T, c, tan phi, T_res, c_res, tan phi_res, breakable, softening shape,
w_c, s_c] (``MaterialTable.strength_array``).

A bond with a fracture energy (softening shape > 0) does not drop at its peak: it softens
(``softening_law``, ``softening.py``) through the contact's damage variable kappa, and fails
(broken, logged as a crack) only once fully softened. Every event's plastic work per unit
area is returned, J/m^2: fracture, the work of softening, or for a brittle bond the energy
its springs let go when it fails (in tension T^2 / 2kn + ts^2 / 2ks, in shear
(tau_peak - tau_res)^2 / 2ks, which its next steps' slip releases); friction, the work of slip
against the friction limit. An elastic step returns none. With these the model's energy account
closes (``output.energy``).
"""
from __future__ import annotations

from numba import njit

from .materials import (COL_BREAKABLE, COL_COHESION, COL_CRITICAL_OPENING, COL_CRITICAL_SLIP,
                        COL_RESIDUAL_COHESION, COL_RESIDUAL_TAN_FRICTION,
                        COL_RESIDUAL_TENSILE_STRENGTH, COL_SOFTENING, COL_TAN_FRICTION,
                        COL_TENSILE_STRENGTH)
from .softening import return_to_envelope, shape_value

__all__ = ["coulomb_law", "softening_law"]

# events returned by coulomb_law; SOFTENING: on the softening branch, not yet fully softened
ELASTIC, TENSION_FAILURE, SHEAR_FAILURE, SLIP, OPEN, SOFTENING = 0, 1, 2, 3, 4, 5


@njit(cache=True, inline="always")
def coulomb_law(du_n, du_s, sn_e, ts, kn, ks, strength, m, broken, kappa):
    """One contact over one step: returns (sn, ts, sn_e, slip, event, kappa, w_fracture,
    w_friction).

    Parameters
    ----------
    du_n, du_s : float, m. Increments of opening and shear displacement.
    sn_e, ts : float, Pa. Elastic normal stress and shear stress at the last step.
    kn, ks : float, Pa/m.
    strength : (nm, 10) float64 table (``MaterialTable.strength_array``, columns
        ``materials.COL_*``); m : the contact's material row.
    broken : int. 0 intact (peak strength), otherwise residual strength.
    kappa : float. The damage variable of a softening bond (``softening.py``), else 0.

    Returns
    -------
    sn, ts : transmitted stresses, Pa. sn_e : the new elastic normal stress, Pa.
    slip : plastic shear displacement of this step, m. event : 0 elastic, 1 failed in tension
    now, 2 failed in shear now (slipping), 3 slipping (residual), 4 open (separated), 5
    softening. kappa : the new damage variable. w_fracture, w_friction : plastic work of the
    step per unit area, J/m^2 (softening; slip against friction).
    """
    # a softening bond takes its own law once damaged, or when it first yields (its elastic
    # steps at the peak envelope are the brittle law's, and cost no more)
    soft = broken == 0 and strength[m, COL_SOFTENING] != 0.0
    if soft and kappa > 0.0:
        return softening_law(du_n, du_s, sn_e, ts, kn, ks, strength, m, kappa)
    sn_e0 = sn_e
    sn_e = sn_e - kn * du_n
    trial = ts - ks * du_s
    if strength[m, COL_BREAKABLE] == 0.0:         # glued: elastic, no limit
        return sn_e, trial, sn_e, 0.0, ELASTIC, kappa, 0.0, 0.0
    if broken == 0:
        T = strength[m, COL_TENSILE_STRENGTH]
        c = strength[m, COL_COHESION]
        tanphi = strength[m, COL_TAN_FRICTION]
        # only a bond (strength above residual) can fail; a zero-strength joint just slips/opens
        bond = (T > strength[m, COL_RESIDUAL_TENSILE_STRENGTH]
                or c > strength[m, COL_RESIDUAL_COHESION])
    else:
        T = strength[m, COL_RESIDUAL_TENSILE_STRENGTH]
        c = strength[m, COL_RESIDUAL_COHESION]
        tanphi = strength[m, COL_RESIDUAL_TAN_FRICTION]
        bond = False
    if sn_e < -T:                                  # tension cut-off (separation)
        if soft:
            return softening_law(du_n, du_s, sn_e0, ts, kn, ks, strength, m, kappa)
        if bond:                   # the springs let go their energy at the cut-off
            return 0.0, 0.0, sn_e, du_s - ts / ks, TENSION_FAILURE, kappa, \
                0.5 * (T * T / kn + ts * ts / ks), 0.0
        # the shear spring's energy goes with it: the slip a friction limit falling to zero
        # with the normal stress would have made within the step
        return 0.0, 0.0, sn_e, du_s - ts / ks, OPEN, kappa, 0.0, 0.5 * ts * ts / ks
    tau_max = c + sn_e * tanphi
    if tau_max < 0.0:
        tau_max = 0.0
    if abs(trial) > tau_max:
        if soft:
            return softening_law(du_n, du_s, sn_e0, ts, kn, ks, strength, m, kappa)
        t = tau_max if trial > 0.0 else -tau_max
        slip = (t - trial) / ks
        if bond:           # the drop to the residual, released by the next steps' slip
            tau_r = max(0.0, strength[m, COL_RESIDUAL_COHESION]
                        + sn_e * strength[m, COL_RESIDUAL_TAN_FRICTION])
            drop = max(0.0, tau_max - tau_r)
            return sn_e, t, sn_e, slip, SHEAR_FAILURE, kappa, 0.5 * drop * drop / ks, \
                abs(t * slip)
        return sn_e, t, sn_e, slip, SLIP, kappa, 0.0, abs(t * slip)
    return sn_e, trial, sn_e, 0.0, ELASTIC, kappa, 0.0, 0.0


# Over 60 lines: the two returns (tension, then Coulomb at the normal stress found) share the
# softened strengths and must be read together
@njit(cache=True, inline="always")
def softening_law(du_n, du_s, sn_e, ts, kn, ks, strength, m, kappa):
    """A softening bond over one step (``coulomb_law``'s returns; ``softening.py``): the trial
    returned to the tension envelope T(kappa), then to Coulomb c(kappa) + sn tan phi(kappa),
    kappa implicit in each; fully softened (kappa = 1), the rest of the step takes the
    residual law and the event is the failure of the mode that finished it."""
    shape = int(strength[m, COL_SOFTENING])
    T_r = strength[m, COL_RESIDUAL_TENSILE_STRENGTH]
    c_r = strength[m, COL_RESIDUAL_COHESION]
    tan_r = strength[m, COL_RESIDUAL_TAN_FRICTION]
    dT = strength[m, COL_TENSILE_STRENGTH] - T_r
    dc = strength[m, COL_COHESION] - c_r
    dtan = strength[m, COL_TAN_FRICTION] - tan_r
    sn_e = sn_e - kn * du_n
    trial = ts - ks * du_s
    event = ELASTIC
    w_frac = 0.0
    w_fric = 0.0
    T_now = T_r + dT * shape_value(shape, kappa)
    if -sn_e > T_now:                                           # tension
        w_c = strength[m, COL_CRITICAL_OPENING]
        kappa, delta, work = return_to_envelope(-sn_e, kn, w_c, kappa, T_r, dT, shape)
        sn_e += kn * delta
        w_frac += work
        event = SOFTENING
        if kappa >= 1.0 and sn_e < -T_r:      # fully open: separated, the springs let go
            T_sep = T_r if w_c > 0.0 else T_now        # (w_c = 0: a brittle mode drops)
            w_frac += 0.5 * (T_sep * T_sep / kn + ts * ts / ks)
            return 0.0, 0.0, sn_e, du_s - ts / ks, TENSION_FAILURE, 1.0, w_frac, 0.0
    A = c_r + sn_e * tan_r
    B = dc + sn_e * dtan
    f = shape_value(shape, kappa)
    t = trial
    if kappa < 1.0 and abs(trial) > max(0.0, A + B * f):        # Coulomb, softening
        kappa, delta, work = return_to_envelope(abs(trial), ks,
                                                strength[m, COL_CRITICAL_SLIP], kappa, A, B,
                                                shape)
        env = max(0.0, A + B * shape_value(shape, kappa))
        t = env if trial > 0.0 else -env
        friction = sn_e * tan_r * delta if sn_e > 0.0 else 0.0
        w_fric += friction
        w_frac += max(0.0, work - friction)
        event = SOFTENING
        if kappa >= 1.0:                      # finished in shear: the rest on the residual law
            rest = abs(trial) - ks * delta
            tau = max(0.0, A)
            mag = min(rest, tau)
            t = mag if trial > 0.0 else -mag
            w_fric += tau * max(0.0, rest - tau) / ks
            w_frac += 0.5 * max(0.0, rest - tau) ** 2 / ks     # (a brittle mode's drop)
            return sn_e, t, sn_e, (t - trial) / ks, SHEAR_FAILURE, 1.0, w_frac, w_fric
    if kappa >= 1.0:                          # finished in tension at the cut-off (rare)
        tau = max(0.0, A)
        if abs(trial) > tau:
            t = tau if trial > 0.0 else -tau
            w_fric += abs(t * (t - trial)) / ks
        event = TENSION_FAILURE
    return sn_e, t, sn_e, (t - trial) / ks, event, kappa, w_frac, w_fric
