"""A run's results as one short hash: two runs with the same hash ended in the same bits.

``state_hash(model)`` covers a model's final state; ``results_hash(numbers)`` a case's
results (``comparisons.results.write_results``: its methods, errors and curves, wall-clock
times left out). Both are the first 16 hex digits of a SHA-256, with nothing rounded: one bit
of difference anywhere gives another hash (docs/output.md, "Same input, same bits").

What ``state_hash`` reads, in this order (each array as its dtype, shape and raw bytes,
C order):

1. ``model.state`` (``BlockState``), its fields in their order: positions, rotations,
   velocities, forces, start and last-search poses, the energy account;
2. ``model.contacts`` (``Contacts``), its fields in their order, the live rows only
   (``count[0]``): geometry, stiffness, material, stresses, displacements, states, damage, work;
3. ``model.cracks`` (``CrackLog``): the rows kept so far and the count;
4. the clock: ``time``, ``step``, ``dt`` (float64, int64, float64; a missing ``dt`` as NaN).

Not read: the props (fixed at the build, but for the inertial masses the step sets), the
histories, and the gridpoints of deformable blocks, cables and liners (what they do reaches
the blocks' forces and poses, which are read).
"""
from __future__ import annotations

import hashlib
import json
import math

import numpy as np

__all__ = ["state_hash", "state_arrays", "results_hash", "is_wall_clock", "HEX_DIGITS"]

HEX_DIGITS = 16         # of the SHA-256: 64 bits, enough to tell two runs apart


def state_hash(model) -> str:
    """16 hex digits of the SHA-256 of ``model``'s final state (module docstring: what is
    read and in which order). ``model``: a ``dem_core.Model`` (only its bundles are read)."""
    h = hashlib.sha256()
    for a in state_arrays(model):
        _add(h, a)
    return h.hexdigest()[:HEX_DIGITS]


def state_arrays(model) -> list:
    """The arrays ``state_hash`` reads, in its order (module docstring)."""
    out = [np.asarray(v) for v in model.state]
    c = model.contacts
    n = int(c.count[0])
    out += [np.asarray(getattr(c, f))[:n] for f in c._fields if f != "count"]
    out.append(np.asarray(c.count))
    kept = min(int(model.cracks.count[0]), model.cracks.rows.shape[0])
    out += [model.cracks.rows[:kept], np.asarray(model.cracks.count)]
    dt = math.nan if model.dt is None else float(model.dt)
    out += [np.array([model.time], np.float64), np.array([model.step], np.int64),
            np.array([dt], np.float64)]
    return out


def _add(h, a) -> None:
    a = np.ascontiguousarray(a)
    h.update(f"{a.dtype.str}{a.shape}".encode())
    h.update(a.tobytes())


def results_hash(value) -> str:
    """16 hex digits of the SHA-256 of ``value`` (a case's numbers: a mapping of JSON-like
    values, numpy arrays and scalars) as canonical JSON: keys sorted, no spaces, every float
    written exactly (``repr``: the shortest text that reads back to the same bits), NaN and
    infinities as JSON's NaN and Infinity, tuples and arrays as lists, numpy scalars as Python
    numbers. Wall-clock entries are left out (``is_wall_clock``): they differ between any two
    runs. ``comparisons.results.write_results`` passes a case's methods, errors and curves."""
    text = json.dumps(_canonical(value), sort_keys=True, separators=(",", ":"),
                      allow_nan=True)
    return hashlib.sha256(text.encode()).hexdigest()[:HEX_DIGITS]


def is_wall_clock(name) -> bool:
    """Whether a key (or a curve's column) holds a wall-clock time, not a result: "seconds",
    "written" or any name with "runtime" in it ("runtime_s", "ucs_runtime_s", ...)."""
    name = str(name)
    return name in ("seconds", "written") or "runtime" in name


def _canonical(value):
    """``value`` as plain JSON types, wall-clock keys dropped, nothing rounded."""
    if isinstance(value, dict):
        return {str(k): _canonical(v) for k, v in value.items() if not is_wall_clock(k)}
    if isinstance(value, (list, tuple)):
        return [_canonical(v) for v in value]
    if isinstance(value, np.ndarray):
        return _canonical(value.tolist())
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, float):
        return float(value)                 # np.float64 and float alike
    if value is None or isinstance(value, (str, int, bool)):
        return value
    raise TypeError(f"results_hash: a {type(value).__name__} is not a number, text or a "
                    f"list or mapping of them: {value!r}")
