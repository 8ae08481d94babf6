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
``strength`` rows are [T, c, tan phi, T_res, c_res, tan phi_res, breakable]
(``MaterialTable.strength_array``).
"""
from __future__ import annotations

from numba import njit

from .materials import (COL_BREAKABLE, COL_COHESION, COL_RESIDUAL_COHESION,
                        COL_RESIDUAL_TAN_FRICTION, COL_RESIDUAL_TENSILE_STRENGTH,
                        COL_TAN_FRICTION, COL_TENSILE_STRENGTH)

__all__ = ["coulomb_law"]

# events returned by coulomb_law
ELASTIC, TENSION_FAILURE, SHEAR_FAILURE, SLIP, OPEN = 0, 1, 2, 3, 4


@njit(cache=True, inline="always")
def coulomb_law(du_n, du_s, sn_e, ts, kn, ks, strength, m, broken):
    """One contact over one step: returns (sn, ts, sn_e, slip, event).

    Parameters
    ----------
    du_n, du_s : float, m. Increments of opening and shear displacement.
    sn_e, ts : float, Pa. Elastic normal stress and shear stress at the last step.
    kn, ks : float, Pa/m.
    strength : (nm, 7) float64 table (``MaterialTable.strength_array``, columns
        ``materials.COL_*``); m : the contact's material row.
    broken : int. 0 intact (peak strength), otherwise residual strength.

    Returns
    -------
    sn, ts : transmitted stresses, Pa. sn_e : the new elastic normal stress, Pa.
    slip : plastic shear displacement of this step, m. event : 0 elastic, 1 failed in tension
    now, 2 failed in shear now (slipping), 3 slipping (residual), 4 open (separated).
    """
    sn_e = sn_e - kn * du_n
    trial = ts - ks * du_s
    if strength[m, COL_BREAKABLE] == 0.0:         # glued: elastic, no limit
        return sn_e, trial, sn_e, 0.0, ELASTIC
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
        return 0.0, 0.0, sn_e, du_s - ts / ks, TENSION_FAILURE if bond else OPEN
    tau_max = c + sn_e * tanphi
    if tau_max < 0.0:
        tau_max = 0.0
    if abs(trial) > tau_max:
        t = tau_max if trial > 0.0 else -tau_max
        return sn_e, t, sn_e, (t - trial) / ks, SHEAR_FAILURE if bond else SLIP
    return sn_e, trial, sn_e, 0.0, ELASTIC
