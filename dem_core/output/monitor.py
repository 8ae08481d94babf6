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
still spreading (docs/performance.md,
"Fewer steps to an answer").
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from numba import njit

from ..components import support
from ..contact.detection import block_containing
from ..deformable import component as zone_kernels
from ..deformable import held as zone_bc

__all__ = ["FAILED", "unbalanced_ratio", "kinetic_energy", "strain_energy", "History", "verdict",
           "settled", "settle_window", "SolveResult", "body_point", "point_motion", "model_ratio",
           "model_kinetic_energy", "model_strain_energy", "gravity_energy", "crack_log",
           "crack_counts", "diagnose", "history_row"]


@njit(cache=True)
def unbalanced_ratio(s, p, c, gravity, load, extra_num=0.0, extra_den=0.0):
    """sum |unbalanced force| / sum (contact forces + weight + load) over the free blocks
    (``s`` BlockState, ``p`` BlockProps, ``c`` Contacts, ``gravity`` (2,) m/s^2, ``load``
    (nb, 3) N/m); ``extra_num``, ``extra_den``: the same sums of other moving parts (support
    nodes: ``support.unbalanced``; zones: ``deformable.held.unbalanced``)."""
    mass, fixity, active, force = p.mass, p.fixity, p.active, s.force
    nb = mass.shape[0]
    scale = np.zeros(nb)
    for k in range(c.count[0]):
        fc = c.length[k] * math.hypot(c.sn[k], c.ts[k])
        scale[c.block_a[k]] += fc
        scale[c.block_b[k]] += fc
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

    verdict : "equilibrium", "settled" (stopped early by ``settled``), "moving" or "failed"
    (``judge="budget"``); "equilibrium", "failing" or "undecided" (``judge="response"``,
    ``workflow.response``).
    steps : steps taken; ratio : the final unbalanced ratio; max_displacement : m, the largest
    block displacement during the solve; reason : one line that explains the verdict;
    response_steps : the N_r the verdict was judged over (None with ``judge="budget"``).
    """

    verdict: str
    steps: int
    ratio: float
    max_displacement: float
    reason: str
    response_steps: int | None = None

    def __bool__(self):
        return self.verdict == "equilibrium"


FAILED = ("failed", "failing")      # the verdicts of a solve that did not stand


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


# ---------------------------------------------------------------- measures of a whole model
# Each takes the step's World record (``step.world``) and what else it reads; the driver
# (``Model``) calls them and never computes a measure itself.

def body_point(world, xy) -> tuple:
    """A history point at ``xy`` (m): (block containing it, its local coordinates (2,), the
    start (2,)), for ``point_motion``."""
    xy = np.asarray(xy, dtype=np.float64)
    s = world.state
    b = block_containing(world.props, s.pos, s.rot, xy)
    cos_t, sin_t = s.rot[b]
    dx, dy = xy - s.pos[b]
    return b, np.array([cos_t * dx + sin_t * dy, -sin_t * dx + cos_t * dy]), xy.copy()


def point_motion(world, point) -> tuple:
    """(ux, uy, vx, vy) of a history point now, m and m/s; ``point`` = (block, local point
    (2,), start (2,)). On a deformable block: the frame's motion plus its zones' there."""
    b, r, x0 = point
    s = world.state
    cos_t, sin_t = s.rot[b]
    rx, ry = r
    zvx = zvy = 0.0
    if not zone_kernels.is_empty(world.zones):
        ux, uy, zvx, zvy = zone_bc.point_motion(world.zones, b, r)
        rx, ry = rx + ux, ry + uy
    x = s.pos[b] + np.array([cos_t * rx - sin_t * ry, sin_t * rx + cos_t * ry])
    w = s.omega[b]
    v = s.vel[b] + w * np.array([-(x[1] - s.pos[b, 1]), x[0] - s.pos[b, 0]])
    v += np.array([cos_t * zvx - sin_t * zvy, sin_t * zvx + cos_t * zvy])
    return x[0] - x0[0], x[1] - x0[1], v[0], v[1]


def model_ratio(world, gravity, load, cables, liners) -> float:
    """The model's unbalanced ratio (``unbalanced_ratio``): blocks, support nodes and the
    deformable blocks' gridpoints (their unbalanced non-rigid forces), so a model is in
    equilibrium when its frames, its zones and its support are."""
    num, den = support.unbalanced(cables, liners, gravity)
    if not zone_kernels.is_empty(world.zones):
        zn, zd = zone_bc.unbalanced(world.zones, world.props.active, gravity)
        num, den = num + zn, den + zd
    return unbalanced_ratio(world.state, world.props, world.contacts, gravity, load, num, den)


def model_kinetic_energy(world) -> float:
    """J/m: the blocks' (real masses), plus the zones' motion in their frames."""
    s, p = world.state, world.props
    ke = kinetic_energy(s.vel, s.omega, p.mass, p.inertia, p.active)
    if not zone_kernels.is_empty(world.zones):
        ke += zone_kernels.kinetic_energy(world.zones)
    return ke


def model_strain_energy(world) -> float:
    """J/m: the contact springs', plus the deformable blocks' zones'."""
    w = strain_energy(world.contacts)
    if not zone_kernels.is_empty(world.zones):
        w += zone_kernels.strain_energy(world.zones)
    return w


def gravity_energy(world, gravity) -> float:
    """Potential of gravity relative to the initial positions, J/m (the blocks' frames and
    the deformable blocks' gridpoints in them)."""
    s, p, z = world.state, world.props, world.zones
    a = p.active > 0
    du = s.pos[a] - s.pos0[a]
    e = float(-(p.mass[a] * (du @ gravity)).sum())
    if not zone_kernels.is_empty(z):     # the zones' own displacement (a held block's)
        owner = np.repeat(np.arange(p.mass.shape[0]), np.diff(z.point_offsets))
        live = a[owner]
        cos_t, sin_t = s.rot[owner].T
        u = z.x - z.x0
        ux, uy = cos_t * u[:, 0] - sin_t * u[:, 1], sin_t * u[:, 0] + cos_t * u[:, 1]
        e -= float((z.mass * (ux * gravity[0] + uy * gravity[1]))[live].sum())
    return e


# the energy account's terms a history keeps (``output.energy``), as columns "energy_<term>"
ENERGY_COLUMNS = ("external", "strain", "fracture", "friction", "damping", "balance")


def history_row(step, time, ratio, kinetic, cracks, motions, energy=None) -> dict:
    """One row of the histories: step, time (s), unbalanced ratio, kinetic energy (J/m), the
    crack counts, each point's ux, uy (m), vx, vy (m/s) (``motions``: name -> tuple) and the
    energy account's terms (``energy``: ``energy_account``'s dict; J/m)."""
    row = {"step": step, "time": time, "ratio": ratio, "kinetic_energy": kinetic}
    row.update({f"cracks_{k}": v for k, v in cracks.items()})
    if energy is not None:
        row.update({f"energy_{k}": energy[k] for k in ENERGY_COLUMNS})
    for name, (ux, uy, vx, vy) in motions.items():
        row.update({f"{name}.ux": ux, f"{name}.uy": uy, f"{name}.vx": vx, f"{name}.vy": vy})
    return row


def crack_log(cracks, names) -> dict:
    """Every bond failure so far (a ``CrackLog``): time (s), x, y (m), mode (1 tension,
    2 shear), blocks, material name (``names``: the material table's)."""
    n = min(int(cracks.count[0]), cracks.rows.shape[0])
    r = cracks.rows[:n]
    return {"time": r[:, 0].copy(), "x": r[:, 1].copy(), "y": r[:, 2].copy(),
            "mode": r[:, 3].astype(np.int8), "block_a": r[:, 4].astype(np.int64),
            "block_b": r[:, 5].astype(np.int64),
            "material": [names[int(m)] for m in r[:, 6]]}


def crack_counts(cracks) -> dict:
    """{"tension": n, "shear": n}: the bond failures so far by mode."""
    mode = cracks.rows[:int(cracks.count[0]), 3]
    return {"tension": int((mode == 1).sum()), "shear": int((mode == 2).sum())}


# a block whose contacts overlap by more than this fraction of its width is squeezed
SQUEEZED = 0.1


def diagnose(world, area, b, clock) -> str:
    """Why block ``b`` went unstable, and the fix (the ``ModelUnstable`` message).
    ``area``: (nb,) block areas, m^2; ``clock``: dict of step, time, dt, critical_dt and
    fixed_dt (None unless the user fixed the step)."""
    c, s, p = world.contacts, world.state, world.props
    mine = np.flatnonzero((c.block_a[:c.n] == b) | (c.block_b[:c.n] == b))
    kmax = float(c.kn[mine].max()) if mine.size else 0.0
    width = float(area[b]) / (2.0 * float(p.radius[b]))
    cause = _sliver(area, b) + _squeezed(c, mine, width) + _overstressed(c, mine, width)
    fixed = clock["fixed_dt"]
    if fixed is not None and fixed > clock["critical_dt"]:
        cause.append(f"the fixed dt {fixed:.3g} s exceeds the critical step "
                     f"{clock['critical_dt']:.3g} s: let the model choose dt")
    if mine.size and c.ks[mine].max() > 10 * c.kn[mine].min():
        cause.append("a large ks/kn ratio: lower the safety factor")
    cause = cause or [f"the time step {clock['dt']:.3g} s is too large for the stiffness "
                      f"(kn up to {kmax:.3g} Pa/m): lower safety; or a load far too large "
                      "for the contacts (a g-level, an applied force or stress: check its "
                      "value and unit)"]
    return (f"unstable at step {clock['step']}, t = {clock['time']:.6g} s: block {b} "
            f"(centroid {s.pos[b].round(6).tolist()}, {mine.size} contacts, "
            f"velocity {s.vel[b].tolist()}) moved too far in one step or became "
            f"NaN. Likely cause: {'; '.join(cause)}.")


def _sliver(area, b) -> list:
    a, med = float(area[b]), float(np.median(area))
    if a < 1e-3 * med:
        return [f"a sliver (area {a:.3g} m^2 vs median {med:.3g}): merge it or use "
                "mass_scaling=True"]
    return []


def _overstressed(c, mine, width) -> list:
    """A contact stress that would close its contact by more than the block's ``width`` (m):
    sn / kn beyond it (an in-situ stress or load far too large for the contacts)."""
    if not mine.size:
        return []
    closure = c.sn[mine] / c.kn[mine]
    k = int(np.argmax(closure))
    if not closure[k] > width:
        return []
    return [f"a contact stress of {float(c.sn[mine][k]):.3g} Pa, which would close a contact "
            f"of kn {float(c.kn[mine][k]):.3g} Pa/m by {float(closure[k]):.3g} m, more than "
            f"the block's width ({width:.3g} m): the stress (an in-situ stress or a load) is "
            "far too large for the contacts, or kn far too small"]


def _squeezed(c, mine, width) -> list:
    """A thin block wedged at a joint crossing: its contacts overlap by much of its width
    (``width`` = area / (2 radius))."""
    overlap = float(-c.un[mine].min()) if mine.size else 0.0
    if overlap <= SQUEEZED * width:
        return []
    return [f"a squeezed block: its contacts overlap by up to {overlap * 1e3:.3g} mm, "
            f"{overlap / width:.2g} of its width ({width:.3g} m = area / (2 radius)), at "
            f"normal stresses up to {float(c.sn[mine].max()) / 1e6:.3g} MPa; the contacts "
            "are far too soft for that stress (a thin block wedged at a joint crossing): "
            "stiffen those contacts, or excavate such blocks (e.g. area / radius^2 < 0.3) "
            "before loading"]
