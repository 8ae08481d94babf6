"""The flaw/joint contact law: Coulomb slip with a tension cut-off and residual strength.

Thesis eqs 3.1-3.5 (CASES.md), compression positive, total-displacement form:

    sn = -kn u_n                                   (u_n > 0 is opening)
    if sn < -T:  tensile failure -> sn = 0, ts = 0, T and c drop to residual
    ts = -ks (u_s - u_p)
    tau_max = max(0, c + sn tan(phi))
    if |ts| > tau_max: ts = sign(ts) tau_max, u_p = u_s + ts/ks (slip); an intact contact has
                       failed in shear: T and c drop to residual, friction stays (phi_res).

A contact that has failed (or was never bonded) uses the residual T, c and friction. Only a
bond (peak T or c above the residual) can fail; a joint with T = c = 0 just opens or slips. The stress
at the step of a shear failure is the peak limit; the residual applies from the next step. A
glued (unbreakable) material is elastic with no limit. ``strength`` rows are
[T, c, tan phi, T_res, c_res, tan phi_res, breakable] (``MaterialTable.strength_array``).
"""
from __future__ import annotations

from numba import njit

__all__ = ["coulomb_law"]


@njit(cache=True, inline="always")
def coulomb_law(u_n, u_s, u_p, kn, ks, strength, m, broken):
    """One contact: returns (sn, ts, u_p, event).

    event: 0 elastic, 1 failed in tension now, 2 failed in shear now (slipping), 3 slipping
    (residual), 4 open (separated, no stress).

    Parameters
    ----------
    u_n, u_s, u_p : float, m. Opening, total and plastic shear displacement.
    kn, ks : float, Pa/m.
    strength : (nm, 7) float64 table; m : the contact's material row.
    broken : int. 0 intact (peak strength), otherwise residual strength.
    """
    sn = -kn * u_n
    ts = -ks * (u_s - u_p)
    if strength[m, 6] == 0.0:                     # glued: elastic, no limit
        return sn, ts, u_p, 0
    if broken == 0:
        T, c, tanphi = strength[m, 0], strength[m, 1], strength[m, 2]
        # only a bond (strength above residual) can fail; a zero-strength joint just slips/opens
        bond = T > strength[m, 3] or c > strength[m, 4]
    else:
        T, c, tanphi = strength[m, 3], strength[m, 4], strength[m, 5]
        bond = False
    if sn < -T:                                    # tension cut-off (separation)
        return 0.0, 0.0, u_s, 1 if bond else 4
    tau_max = c + sn * tanphi
    if tau_max < 0.0:
        tau_max = 0.0
    if abs(ts) > tau_max:
        ts = tau_max if ts > 0.0 else -tau_max
        u_p = u_s + ts / ks
        return sn, ts, u_p, 2 if bond else 3
    return sn, ts, u_p, 0
