"""The solve: cycle a model in chunks until it is in equilibrium, has failed, has settled or
has used its step budget, and say which (``Model.solve``, the ``Solve`` stage and every level
of a search run it).

Checked every ``check_every`` steps (default: the history interval, at least 100):

- "equilibrium": the unbalanced ratio (``output.monitor.unbalanced_ratio``) <= ``ratio``;
- "failed": the displacement judged passed ``failure_displacement``;
- "settled" (with ``settle``): the motion has died out and no bond broke over two windows
  (``monitor.settled``);
- at ``max_steps``: "failed" if the displacement is still growing without slowing down, else
  "moving" (``monitor.verdict``).

That is ``judge="budget"``; with ``judge="response"`` the verdict is "equilibrium", "failing"
or "undecided", judged over windows of the model's response time (``workflow.response``).

The displacement judged is the largest of the active blocks' since the solve began, or of the
history points ``watch`` (so a loose block at a boundary does not count as the failure of the
slope). ``creep`` (m): increments below it are not movement in the end test; default 1e-3 of
the median block radius for blocks, 0 for watched points.
"""
from __future__ import annotations

import numpy as np

from ..output import monitor
from . import response

__all__ = ["solve", "response_steps"]


def solve(model, settings, check_every=None, trace=None) -> monitor.SolveResult:
    """Solve ``model`` (a ``Model``, run through its public verbs) with the validated
    ``settings.SolveSettings``; ``trace``: optional (steps, displacements) lists, each starting
    with 0, the checks are appended to (still readable after a ``ModelUnstable``)."""
    st = settings
    missing = [n for n in st.watch if n not in model.points]
    if missing:
        raise ValueError(f"no history point(s) {missing}; add them with add_history_point")
    if not np.any(model.props.active):
        raise ValueError("solve: no block is left (every block was excavated): there is "
                         "nothing to solve, and no verdict to give")
    model.restart_kinetic_interval()        # a new load step: the checks start sparse again
    check = int(check_every or max(model.history.every, 100))
    creep = st.creep if st.creep is not None else (
        0.0 if st.watch else 1e-3 * float(np.median(model.props.radius)))
    moved = _mover(model, st.watch)
    what = "a watched point" if st.watch else "a block"
    steps, disp = trace if trace is not None else ([0], [0.0])
    if st.judge == "response":
        return response.judge(model, st, response_steps(model, st, check), check, moved,
                              (steps, disp))
    cracks = [int(model.cracks.count[0])]
    done, r = 0, float("inf")
    while done < st.max_steps:
        k = min(check, st.max_steps - done)
        model.cycle(k)
        done += k
        r, d = model.unbalanced_ratio(), moved()
        steps.append(done)
        disp.append(d)
        if r <= st.ratio:
            return monitor.SolveResult("equilibrium", done, r, max(disp),
                                       f"ratio {r:.3g} <= {st.ratio:.3g}")
        fd = st.failure_displacement
        if fd is not None and d > fd:
            return monitor.SolveResult("failed", done, r, d, f"{what} moved {d:.3g} m > {fd} m")
        cracks.append(int(model.cracks.count[0]))
        window = monitor.settle_window(st.max_steps, creep)
        if st.settle and monitor.settled(steps, disp, cracks, *window):
            return monitor.SolveResult("settled", done, r, max(disp), monitor.SETTLED)
    v, why = monitor.verdict(steps, disp, creep)
    return monitor.SolveResult(v, done, r, max(disp), why)


def response_steps(model, settings, check) -> int:
    """N_r for a judged solve: the settings', else the model's, else measured now and kept
    with the model (``response.measure_response``), at least two checks."""
    n_r = settings.response_steps or model.response_steps
    if n_r is None:
        n_r = model.measure_response(settings.watch)
    return max(int(n_r), 2 * check)


def _mover(model, watch):
    """A function giving the displacement (m) judged since now: the largest of the active
    blocks' centroids, or of the watched history points."""
    if watch:
        start = np.array([model.point_motion(n)[:2] for n in watch])
        return lambda: float(np.hypot(*(np.array([model.point_motion(n)[:2] for n in watch])
                                        - start).T).max())
    start, act = model.state.pos.copy(), model.props.active > 0
    return lambda: (float(np.hypot(*(model.state.pos[act] - start[act]).T).max())
                    if act.any() else 0.0)
