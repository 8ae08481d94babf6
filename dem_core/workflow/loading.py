"""Loading paths as stages: a servo-held force and a displacement-controlled load.

These are the lab's loading paths (platen compression and tension, the direct-shear box) as
stage records any scene can use (``dem_core.workflow.stages``):

| kind | record | does |
|---|---|---|
| "servo" | ``ServoLoad(group, stress, length, direction, v_max, ...)`` | presses a group along a direction with a constant force, cycles until it is reached |
| "load" | ``Load(group, rate, direction, read_on, length, ...)`` | moves a group at a constant rate and records the reaction until the peak is passed |
| "displace" | ``Displace(group, displacement, direction, rate)`` | moves a group at a constant rate until it has moved ``displacement``, then releases it |

Rates are displacements per time step (m/step): with mass scaling the time step, not the
physical density, sets the inertia, so a rate per step is what makes a run quasi-static (halve it
and the peak should not move). The velocity is re-set from the current time step every
``chunk`` steps.

Reaction convention (``Load``): on each ``read_on`` group, the force the rest of the model exerts
on it along the loading direction, taken against the motion on the moving group and with it on
any other group (a fixed platen is pushed forward), averaged over the groups and divided by
``length`` (m): a stress in Pa, compression (resisting the motion) positive. ``across`` is the
same mean of the force component along the direction turned +90 deg, over ``length`` (the normal
stress on a shear box moved along +x).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["Load", "ServoLoad", "Displace", "reaction"]


def _unit(v, what):
    d = np.asarray(v, dtype=np.float64)
    if d.shape != (2,) or not np.all(np.isfinite(d)) or math.hypot(*d) == 0:
        raise ValueError(f"{what} {v!r} must be a non-zero 2-vector")
    return d / math.hypot(*d)


def _known(i, kind, names, known):
    for g in names:
        if g not in known:
            raise ValueError(f"stage {i} ({kind}) names unknown group {g!r}; groups are "
                             f"{sorted(known)}")


def _group_force(model, group) -> np.ndarray:
    """Force (N/m) on a group's blocks in the last step; for blocks whose motion is prescribed
    and that carry no gravity or applied load, the contact force on them."""
    return model.state.force[model.group(group), :2].sum(axis=0)


def reaction(model, moving, read_on, direction) -> tuple:
    """(along, across) force (N/m) on ``read_on`` groups, mean over groups (module docstring)."""
    d = _unit(direction, "direction")
    along = across = 0.0
    for g in read_on:
        f = _group_force(model, g)
        sign = -1.0 if g == moving else 1.0
        along += sign * (f[0] * d[0] + f[1] * d[1])
        across += sign * (f[1] * d[0] - f[0] * d[1])
    n = len(read_on)
    return along / n, across / n


def _mean_along(model, group, d):
    p = model.state.pos[model.group(group)]
    return float(p[:, 0].mean()) * d[0] + float(p[:, 1].mean()) * d[1]


@dataclass(frozen=True)
class ServoLoad:
    """Press ``group`` along ``direction`` with the force ``stress x length`` (N/m), holding it
    across the direction and in rotation, then cycle (``chunk`` steps at a time, at most
    ``max_steps``) until the reaction is within ``settle_tol`` of the target and the unbalanced
    ratio is below ``settle_ratio`` (consolidation). ``v_max`` (m/step) caps the servo's speed.
    The servo stays on for the stages after it (``Release`` ends it)."""

    group: str
    stress: float
    length: float
    direction: tuple = (0.0, -1.0)
    v_max: float | None = None
    settle_tol: float = 0.02
    settle_ratio: float = 1e-3
    max_steps: int = 40_000
    chunk: int = 200

    def check(self, i, groups, materials):
        _known(i, "servo", [self.group], groups)
        _unit(self.direction, f"stage {i} (servo): direction")
        if not (math.isfinite(self.stress) and self.stress >= 0 and self.length > 0):
            raise ValueError(f"stage {i} (servo): stress {self.stress!r} Pa must be >= 0 and "
                             f"length {self.length!r} m > 0")
        if self.v_max is not None and not self.v_max > 0:
            raise ValueError(f"stage {i} (servo): v_max {self.v_max!r} m/step must be > 0")
        if not (self.settle_tol > 0 and self.settle_ratio > 0 and self.max_steps > 0
                and self.chunk > 0):
            raise ValueError(f"stage {i} (servo): settle_tol, settle_ratio, max_steps, chunk "
                             "must be > 0")

    def run(self, model):
        d = _unit(self.direction, "servo direction")
        model.set_velocity(self.group, vx=0.0 if d[0] == 0 else None,
                           vy=0.0 if d[1] == 0 else None, omega=0.0)
        target = self.stress * self.length
        v_max = None if self.v_max is None else self.v_max / model.dt
        model.servo(self.group, target, direction=tuple(d), v_max=v_max)
        steps = 0
        while steps < self.max_steps:
            model.cycle(self.chunk)
            steps += self.chunk
            f = _group_force(model, self.group)
            pressed = -(f[0] * d[0] + f[1] * d[1])
            if (abs(pressed - target) <= self.settle_tol * max(target, 1.0)
                    and model.unbalanced_ratio() < self.settle_ratio):
                return steps, "settled", {"force": float(pressed), "target": target}
        return steps, "not settled", {"force": float(pressed), "target": target}


@dataclass(frozen=True)
class Load:
    """Move ``group`` along ``direction`` at ``rate`` m/step (no rotation, no motion across)
    and record, every ``chunk`` steps: model time, the group's displacement along the direction
    (m), the reaction (Pa, module docstring) and ``across`` (Pa), and the change (m) of the
    separation of the two ``gauge`` groups along ``gauge_direction`` (a lateral gauge).

    Stops when the displacement exceeds ``max_displacement`` (m, None: no limit), or once a positive peak has
    been passed: the reaction fell below ``post_peak`` x peak with the displacement beyond
    ``past_peak`` x its value at the peak. Verdict "peak passed" or "max displacement".
    """

    group: str
    rate: float
    direction: tuple = (0.0, -1.0)
    read_on: tuple = ()
    length: float = 1.0
    max_displacement: float | None = None
    post_peak: float = 0.7
    past_peak: float = 0.0
    gauge: tuple = ()
    gauge_direction: tuple = (1.0, 0.0)
    chunk: int = 200

    def check(self, i, groups, materials):
        _known(i, "load", [self.group, *self.read_on, *self.gauge], groups)
        _unit(self.direction, f"stage {i} (load): direction")
        _unit(self.gauge_direction, f"stage {i} (load): gauge_direction")
        if not (math.isfinite(self.rate) and self.rate > 0 and self.length > 0
                and (self.max_displacement is None or self.max_displacement > 0)
                and 0 <= self.post_peak < 1
                and self.past_peak >= 0 and self.chunk > 0):
            raise ValueError(f"stage {i} (load): rate {self.rate!r} m/step, length "
                             f"{self.length!r} m, max_displacement {self.max_displacement!r} m "
                             f"and chunk must be > 0, post_peak {self.post_peak!r} in [0, 1)")
        if len(self.gauge) not in (0, 2):
            raise ValueError(f"stage {i} (load): gauge must name two groups, got {self.gauge!r}")

    def run(self, model):
        d = _unit(self.direction, "load direction")
        read_on = tuple(self.read_on) or (self.group,)
        gd = _unit(self.gauge_direction, "gauge direction")

        def gauge():
            if not self.gauge:
                return 0.0
            return _mean_along(model, self.gauge[1], gd) - _mean_along(model, self.gauge[0], gd)

        x0, g0 = _mean_along(model, self.group, d), gauge()
        along, across = reaction(model, self.group, read_on, d)
        rec = {k: [v] for k, v in (("time", model.time), ("displacement", 0.0),
                                   ("reaction", along / self.length),
                                   ("across", across / self.length), ("gauge", 0.0))}
        steps = 0
        while True:
            v = self.rate / model.dt              # dt may change after contact searches
            model.set_velocity(self.group, vx=v * d[0], vy=v * d[1], omega=0.0)
            model.cycle(self.chunk)
            steps += self.chunk
            along, across = reaction(model, self.group, read_on, d)
            rec["time"].append(model.time)
            rec["displacement"].append(_mean_along(model, self.group, d) - x0)
            rec["reaction"].append(along / self.length)
            rec["across"].append(across / self.length)
            rec["gauge"].append(gauge() - g0)
            y, x = rec["reaction"], rec["displacement"]
            i = int(np.argmax(y))
            if self.max_displacement is not None and x[-1] > self.max_displacement:
                verdict = "max displacement"
                break
            if y[i] > 0 and y[-1] < self.post_peak * y[i] and x[-1] > self.past_peak * x[i]:
                verdict = "peak passed"
                break
        out = {k: np.asarray(v) for k, v in rec.items()}
        i = int(np.argmax(out["reaction"]))
        out.update(peak=float(out["reaction"][i]), displacement_at_peak=float(
            out["displacement"][i]))
        return steps, verdict, out


@dataclass(frozen=True)
class Displace:
    """Move ``group`` along ``direction`` at ``rate`` m/step (no rotation, no motion across)
    until its mean displacement along the direction reaches ``displacement`` (m), then free it
    (``Model.free``): a boundary pulled back by a set distance and let go, e.g. the thesis's
    weathered zone at the toe of Checkerboard Creek (ch. 7). Stops after ``max_steps`` with the
    verdict "not reached". Detail: the displacement reached (m)."""

    group: str
    displacement: float
    direction: tuple = (0.0, -1.0)
    rate: float = 1e-7
    max_steps: int = 1_000_000
    chunk: int = 200

    def check(self, i, groups, materials):
        _known(i, "displace", [self.group], groups)
        _unit(self.direction, f"stage {i} (displace): direction")
        if not (math.isfinite(self.displacement) and self.displacement > 0
                and math.isfinite(self.rate) and self.rate > 0 and self.max_steps > 0
                and self.chunk > 0):
            raise ValueError(f"stage {i} (displace): displacement {self.displacement!r} m, "
                             f"rate {self.rate!r} m/step, max_steps and chunk must be > 0")

    def run(self, model):
        d = _unit(self.direction, "displace direction")
        x0, moved, steps = _mean_along(model, self.group, d), 0.0, 0
        while moved < self.displacement and steps < self.max_steps:
            # the last chunk is shortened so the group stops at the displacement
            left = math.ceil((self.displacement - moved) / self.rate)
            k = int(min(self.chunk, left, self.max_steps - steps))
            v = self.rate / model.dt              # dt may change after contact searches
            model.set_velocity(self.group, vx=v * d[0], vy=v * d[1], omega=0.0)
            model.cycle(k)
            steps += k
            moved = _mean_along(model, self.group, d) - x0
        model.set_velocity(self.group, vx=0.0, vy=0.0, omega=0.0)
        model.free(self.group)
        verdict = "displaced" if moved >= self.displacement * (1 - 1e-9) else "not reached"
        return steps, verdict, {"displacement": float(moved)}
