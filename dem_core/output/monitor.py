"""Measures of a running model: unbalanced-force ratio, energies, histories, the solve verdict.

Unbalanced-force ratio (dimensionless), over the free (not prescribed) velocity components of
active blocks::

    ratio = sum_i |f_unbalanced,i| / sum_i (|m_i g| + |applied_i| + sum_contacts of i |F_c|)

with f the net force of the last step before damping. It is ~1 for a block in free fall and
falls towards 0 as the model comes to equilibrium (Itasca's "mean ratio" in spirit).

Verdict of ``Model.solve`` (documented test, see ``verdict``): "equilibrium" when the ratio
reaches the target; "failed" when a set failure displacement is exceeded, or at the step limit
when the largest block displacement is still growing without slowing down (the increment over
the last fifth of the run is at least ``0.8`` of the increment over the fifth before, and larger
than ``creep``); otherwise "moving".

Early settling (``settle``, optional in ``Model.solve`` and the searches): a solve that has run
two windows of ``SETTLE_WINDOW`` x its step limit stops as "settled" once the displacement grew
by at most ``c / 2`` over the last window and at most ``c`` over the one before, the last
growth at most half the one before (plus ``c / 100``), and no new crack over both
(``settled``); ``c`` is ``creep`` scaled from a fifth of the step limit (the end test's window)
to the settling window, so the rates are the end test's (``settle_window``). A creep that at
least halves from window to window has at most the last window's growth still to go (a
geometric series), so the level stops within ``c / 2`` of the state it creeps towards; a steady
creep, however slow, is not settled. The crack condition holds back a level where fracture is
still spreading (issue 29 item 4; docs/performance.md,
"Fewer steps to an answer").
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from numba import njit

__all__ = ["unbalanced_ratio", "kinetic_energy", "strain_energy", "History", "verdict",
           "settled", "settle_window", "SolveResult"]


@njit(cache=True)
def unbalanced_ratio(force, mass, gravity, load, fixity, active, nc, block_a, block_b,
                     length, sn, ts, extra_num=0.0, extra_den=0.0):
    """sum |unbalanced force| / sum (contact forces + weight + load) over the free blocks;
    ``extra_num``, ``extra_den``: the same sums of other moving parts (support nodes:
    ``support.unbalanced``)."""
    nb = mass.shape[0]
    scale = np.zeros(nb)
    for k in range(nc):
        fc = length[k] * math.hypot(sn[k], ts[k])
        scale[block_a[k]] += fc
        scale[block_b[k]] += fc
    g = math.hypot(gravity[0], gravity[1])
    num = extra_num
    den = extra_den
    for i in range(nb):
        if not active[i] or (fixity[i] & 3) == 3:
            continue
        fx = 0.0 if fixity[i] & 1 else force[i, 0]
        fy = 0.0 if fixity[i] & 2 else force[i, 1]
        num += math.hypot(fx, fy)
        den += scale[i] + mass[i] * g + math.hypot(load[i, 0], load[i, 1])
    if den == 0.0:
        return 0.0
    return num / den


@njit(cache=True)
def kinetic_energy(vel, omega, mass, inertia, active):
    """Sum of 1/2 m v^2 + 1/2 I omega^2 with real masses, J/m (half-step velocities)."""
    e = 0.0
    for i in range(mass.shape[0]):
        if active[i]:
            e += 0.5 * (mass[i] * (vel[i, 0] ** 2 + vel[i, 1] ** 2) + inertia[i] * omega[i] ** 2)
    return e


@njit(cache=True)
def strain_energy(c):
    """Elastic energy stored in the contacts (a ``Contacts``), J/m: integral of
    (sn^2/kn + ts^2/ks) / 2 over the length each carries. A lone contact's stress is uniform over
    its length L: L (sn^2/kn + ts^2/ks) / 2; the two halves of an edge carry a linear field
    (``forces`` module docstring): (Le/6) (s1^2 + s1 s2 + s2^2) / kn and the same in shear, or,
    with one end open, the triangle over x0: x0 (s^2/kn + t^2/ks) / 6."""
    e = 0.0
    for k in range(c.count[0]):
        p = c.partner[k]
        if p > k:
            continue                        # an edge is counted at its second half
        sk, tk, kn, ks = c.sn[k], c.ts[k], c.kn[k], c.ks[k]
        if p < 0:
            e += 0.5 * c.length[k] * (sk * sk / kn + tk * tk / ks)
            continue
        sp, tp, le = c.sn[p], c.ts[p], c.length[k] + c.length[p]
        closed_k, closed_p = sk == c.sn_elastic[k], sp == c.sn_elastic[p]
        if closed_k and closed_p:
            e += le / 6.0 * ((sk * sk + sk * sp + sp * sp) / kn + (tk * tk + tk * tp + tp * tp)
                             / ks)
        elif closed_k and sk > 0.0:
            e += le * sk / (sk - c.sn_elastic[p]) * (sk * sk / kn + tk * tk / ks) / 6.0
        elif closed_p and sp > 0.0:
            e += le * sp / (sp - c.sn_elastic[k]) * (sp * sp / c.kn[p] + tp * tp / c.ks[p]) / 6.0
    return e


@dataclass
class History:
    """Histories recorded every ``every`` steps: one list per named column."""

    every: int = 100
    columns: dict = field(default_factory=dict)

    def record(self, row: dict):
        for k, v in row.items():
            self.columns.setdefault(k, []).append(v)

    def as_arrays(self) -> dict:
        return {k: np.asarray(v) for k, v in self.columns.items()}


@dataclass
class SolveResult:
    """What ``Model.solve`` found.

    verdict : "equilibrium", "settled" (stopped early by ``settled``), "moving" or "failed".
    steps : steps taken; ratio : the final unbalanced ratio; max_displacement : m, the largest
    block displacement during the solve; reason : one line that explains the verdict.
    """

    verdict: str
    steps: int
    ratio: float
    max_displacement: float
    reason: str

    def __bool__(self):
        return self.verdict == "equilibrium"


def verdict(steps, displacements, creep, slow_down=0.8):
    """'failed' if the displacement kept growing over the last two fifths (module docstring).

    Parameters
    ----------
    steps, displacements : sequences of the step count and the largest block displacement (m)
        at each check of the solve.
    creep : float, m. An increment below this is not movement.
    """
    s = np.asarray(steps, dtype=float)
    d = np.asarray(displacements, dtype=float)
    if s.size < 3:
        return "moving", "too few checks to judge"
    s_end = s[-1]
    d1 = np.interp(s_end * 0.6, s, d)
    d2 = np.interp(s_end * 0.8, s, d)
    inc1, inc2 = d2 - d1, d[-1] - d2
    if inc2 > creep and inc2 >= slow_down * inc1:
        return "failed", (f"displacement still growing: {inc2:.3g} m over the last fifth of the "
                          f"steps vs {inc1:.3g} m over the fifth before")
    return "moving", (f"not in equilibrium, but slowing: {inc2:.3g} m over the last fifth vs "
                      f"{inc1:.3g} m before")


SETTLED = "settled: no new crack and the displacement (nearly) still over two windows"
SETTLE_WINDOW = 0.1          # of the step limit


def settle_window(max_steps, creep) -> tuple:
    """(window in steps, creep over that window in m) of a solve of ``max_steps`` whose end
    test takes ``creep`` over a fifth of them (module docstring)."""
    window = max(1, int(SETTLE_WINDOW * max_steps))
    return window, creep * window / (0.2 * max_steps)


def settled(steps, displacements, cracks, window, creep) -> bool:
    """True when a solve may stop as "settled" (module docstring).

    Parameters
    ----------
    steps, displacements, cracks : the checks so far: step count, largest (or watched)
        displacement (m) and total crack count, each starting with the solve's start.
    window : steps, > 0; creep : m.
    """
    s = np.asarray(steps, dtype=float)
    if s[-1] < 2 * window:
        return False
    d = np.asarray(displacements, dtype=float)
    d1, d2 = np.interp([s[-1] - 2 * window, s[-1] - window], s, d)
    first = np.searchsorted(s, s[-1] - 2 * window, side="right") - 1   # the check at or before
    last, before = d[-1] - d2, d2 - d1
    # decaying: at least halving from window to window (a floor of a hundredth of the creep
    # for a run that has all but stopped), so what is left of the creep is at most ``last``
    return bool(last <= 0.5 * creep and before <= creep
                and last <= 0.5 * before + 0.01 * creep
                and cracks[-1] == cracks[max(first, 0)])
