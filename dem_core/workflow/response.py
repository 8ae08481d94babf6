"""The physics verdict of a solve (``SolveSettings(judge="response")``): "equilibrium",
"failing" or "undecided", judged over windows of the model's measured response time, so that
no step budget is in the answer.

**Response time N_r** (steps; ``measure_response``). From a snapshot of the model, every
intact contact is made elastic with no limit (its peak tensile strength and cohesion raised,
as FLAC raises them before ``solve fos``), a broken one keeps its residual law, and an open
contact is closed at zero stress where it is: the present structure, cracks and all, with no
new failure, so a model that is failing still has a response time and a cracked slope has the
response time of its cracked state. Gravity is then raised by ``LOAD_STEP`` (5 %) at once and
the model is cycled with its own damping. At test
points n_j (``FIRST`` checks, then each ``GROWTH`` = 1.25 times the one before) it has come to
rest when the largest movement of a judged block (or watched point) since the test point
before, ``max_i |x_i(n_j) - x_i(n_j-1)|``, is at most ``AT_REST`` (5 %) of the largest
movement since the load step, at two test points in a row; N_r is the second. The model is
then returned to the snapshot, bit for bit. For a response that approaches its end as
``1 - exp(-n / tau)`` the test passes from n = 2.7 tau, so one window of N_r steps takes a
load step's response to within about 5 % of its end. A model without gravity gets a step of
1 % of 9.81 m/s^2 downwards. This is the quantity FLAC's ``solve fos`` measures before its
search, with the strengths raised as here (Dawson, Roth & Drescher 1999, "Slope stability
analysis by strength reduction", Geotechnique 49(6), 835-840): the steps a model needs to
come to rest after a change of load. It is kept with the model (``Model.response_steps``, saved
in its file): a judged solve measures it at its start when the model has none (an excavation
clears it), and a search measures it before its first level and again after each level that
stood, so that each level is judged over the response time of the structure the level
before left, cracks, open joints and all (on the Adhikary slope
at 6 mm: 3,000 steps at rest before the ramp, 9,400 after the 3,100 cracks of 40 g).
A model whose last judged solve did not end at rest (``Model.in_motion``: "failing" or
"undecided", a stage list that goes on after a failure) keeps the N_r it has across an
excavation: a mechanism under way has no response time to measure (its sliding, toppling
and loose blocks never pass the rest test: on the Lornex slope after a failing mining solve
the measurement stops at its 400,000-step cap with the intact contacts strong, with every
touching crack held as well, and as the difference between the loaded model and the same
model run without the load step), so the next solve is judged over the response time of the
structure before it failed, until a solve comes to rest.

What is judged: the watched points, or else everything that moves (the active blocks'
centroids, the cables' and liners' nodes, the deformable blocks' gridpoints: a liner over an
opening sags while every block it spans is held).

**Verdict.** The solve runs in windows, checked every ``check`` steps. The first
``EVEN`` (3) windows are N_r steps long; after that a window is ``SPAN_GROWTH`` (2) times the
one before, up to ``LONGEST`` (8) N_r, when the window before slowed down (``v_k < v_k-1``,
below), and as long as it otherwise (``next_span``). N_r is the response to a load step of
the structure held as it is, and the motion after an excavation or a crack burst can decay
over many of them (joint slip settling over ~36 N_r on the common-toppling slope after its
lifts): a motion that is slowing is sampled on a growing time scale until it has either died
out or kept its speed, while one that keeps or gains speed is judged on windows as short as
before. With ``L_k`` window k's length, ``move_k`` the largest
movement of a judged block (or point) from window k-1 to window k, each window's position
being its mean over the window's checks (the start for k = 1), ``v_k = move_k N_r / D_k``
that movement per N_r (the window's speed; ``D_k = (L_k-1 + L_k) / 2`` steps lie between the
two means, ``D_1 = L_1``), and ``R_k`` the mean unbalanced ratio (``output.monitor``) over its
checks:

- "equilibrium": the ratio falls to ``ratio`` at a check while the judged blocks (points)
  move slowly: at the fastest one's present speed it would move at most ``creep`` in N_r
  steps (a block sliding steadily at its limit has no unbalanced force, but it is not at
  rest); or, from the second window on, at the end of a window in which no bond broke and
  the ratio itself decayed (the mean of the window's second half of checks at most
  ``RATIO_FALL`` = 1/2 of its first half's), ``move_k <= move_k-1 / 2`` (a movement that at
  least halves every window, each at least as long as the one before, has at most ``move_k``
  still to go, a geometric series, so the model comes to rest within that of where it is) or
  ``v_k <= min(creep, v_k-1)`` (a speed below ``creep`` per N_r that is not growing). The
  ratio must decay because a slowing movement alone is not rest: a block pulled past its
  yielding bolt slides at a near-constant 6e-5 m per N_r, below creep, with the ratio steady
  at 3e-3 (a ratio coming to rest falls by 15-20 times a window of N_r); or, from the second
  window on, with no bond broken in the window, at most ``STILL`` (1 %) of ``creep`` per N_r
  over two windows in a row, whatever the ratio does: standing still (the unbalanced force is
  then in what is not judged: on the Adhikary slope at 6 mm with edge elements, T = 1.4 MPa
  at 40 g, A and B moved 4e-8 m per N_r over two windows, 2e-4 of creep, while the ratio
  stayed at 4e-5, where no other rule could end the level before its cap; the block past its
  yielding bolt, at 3 % of its creep, is not still);
- "failing": the judged displacement since the solve began passes ``failure_displacement``;
  or a mechanism, seen twice: from the third window on, Dawson's test over two windows,
  ``v > creep`` and ``v_j >= 0.8 v_j-1`` (the velocity does not decay) while
  ``R_j >= 0.9 R_j-1`` (the ratio stops falling: the test of Dawson et al. 1999), for j = k
  and k - 1; and once it has held at step n_1, it holds again at the end of a window at
  least ``CONFIRM`` n_1 = 2 n_1 steps into the solve, the windows growing meanwhile
  (``next_span``). Two windows, because a large load step (a first level from rest, a crack
  burst) can take the slope through a longer transient than the elastic N_r: on the Adhikary
  slope at 6 mm, 0 to 40 g in one step moves point A 2.26 mm over 6,400 steps, accelerating
  for the first 5,000, and stops dead (N_r = 3,000). Seen twice, because slip that
  redistributes a load step can accelerate for many N_r and then arrest: on the cross-jointed
  field slope a strength step to F = 1.0625 slides the wedge 1.6 cm, accelerating over five
  windows of N_r = 900 steps, and to F = 1.0875 6.8 cm over 30,000 steps at a steady speed,
  and both then stop dead (ratio 5e-12), while F = 1.1 slides 6.7 m off the slope. A motion
  that has lasted as long again as it took to show is judged on its own time scale, whatever
  that is, as the growing windows judge a slowing one. A *slow* mechanism, at most ``creep``
  per N_r but faster than ``STILL`` of it, is the same test on three windows of the longest
  length (``LONGEST`` N_r each): a motion below creep that keeps its speed over 24 N_r while
  the ratio stays up is a mechanism, as the ratio test of FLAC (which has no speed floor)
  calls it; it is judged on the longest time scale only, so that a motion still settling has
  been seen on windows that grew while it slowed (the block past its yielding bolt, 3 % of
  creep with the ratio at 3e-3, slowing by about a tenth a window: "failing" at window 13,
  first seen at window 8; the common-toppling slope after lift 12, 4-7 mm per N_r against a
  creep of 5.9 mm, bonds breaking in most windows: first seen at window 17, again at 29);
- "undecided": neither within ``windows`` windows (40: at most 289 N_r). It is never
  counted as standing.

Within the even windows the rules are those of equal windows (``v_k`` is ``move_k``), so a
verdict reached by window 3 does not depend on the growth.

Why mean positions: a block oscillating about a stable position has a mean that stays put,
while a mechanism's mean moves on by its velocity times N_r; a window's end points alone would
read an oscillation's phase. What the test cannot tell apart: a motion that slows by less than
a fifth per window (a block thrown along a plane, sliding to a stop over many response
times) is "failing" while it lasts, as it is under the ratio test of FLAC; the growing windows
shorten what it can be: one that has decayed by e over ``tau`` steps slows by more than a fifth
between windows once they are about ``tau / 2`` long.

``creep`` (m per N_r) defaults to 1e-3 of the median block radius, for blocks and watched
points alike, and is never less than ``REST`` = 1e-6 of it: below that a movement is round-off
(a watched point at rest drifts by 1e-12 m a window, and a creep of 0 would call that a
mechanism and never let a fast block count as slow).
The verdict does not depend on the cap: a model that decides does so at the same window
whatever ``windows`` is (tests/test_response_verdict.py).
"""
from __future__ import annotations

from dataclasses import replace

import numpy as np

from ..contact.materials import material_table
from ..output import monitor

__all__ = ["measure_response", "judge", "next_span", "LOAD_STEP", "AT_REST", "GROWTH",
           "FIRST", "MOST", "EVEN", "SPAN_GROWTH", "LONGEST", "RATIO_FALL",
           "CONFIRM", "STILL"]

LOAD_STEP = 0.05        # the gravity step of the measurement, of the model's gravity
AT_REST = 0.05          # movement since the last test point / movement since the load step
GROWTH = 1.25           # test points grow geometrically
FIRST = 5               # checks before the first test point
MOST = 400_000          # steps: a model that has not come to rest by then has this N_r
SMALL_G = 0.0981        # m/s^2: the step of a model without gravity
STRONG = 1e20           # Pa: the peak strengths of the measurement (no intact contact fails)
REST = 1e-6             # of the median block radius: the least creep (movement below is noise)
EVEN = 3                # windows of N_r before they may grow (a mechanism shows over three)
SPAN_GROWTH = 2         # a window after a slowing one is this many times as long ...
LONGEST = 8             # ... up to this many N_r
RATIO_FALL = 0.5        # rest by movement needs the ratio to halve within the window
CONFIRM = 2             # a mechanism holds again after this many times the steps it took
STILL = 0.01            # of creep: two windows this slow are at rest whatever the ratio does


def _moving(model, which):
    """Everything that moves (k, 2): the active blocks' centroids, the cables' and liners'
    nodes and the active blocks' gridpoints; ``which``: "pos" positions (m) or "vel"
    velocities (m/s)."""
    z, active = model.zone_state, model.props.active > 0
    live = np.repeat(active, np.diff(z.point_offsets)) if z.point_offsets.shape[0] else (
        np.zeros(z.x.shape[0], bool))
    pos = which == "pos"
    return np.concatenate([
        (model.state.pos if pos else model.state.vel)[active][:, :2],
        model.cables.node_pos if pos else model.cables.node_vel,
        model.liners.node_pos if pos else model.liners.node_vel,
        (z.x if pos else z.v)[live]])


def positions(model, watch):
    """The judged positions (k, 2), m: the watched points' displacements, or everything that
    moves (a liner's nodes sag while the blocks it spans are held)."""
    if watch:
        return np.array([model.point_motion(n)[:2] for n in watch], dtype=float)
    return _moving(model, "pos")


def fastest(model, watch) -> float:
    """The largest speed (m/s) of the watched points or of everything that moves."""
    if watch:
        return max(float(np.hypot(*model.point_motion(n)[2:])) for n in watch)
    v = _moving(model, "vel")
    return float(np.hypot(*v.T).max()) if v.size else 0.0


def _largest(a, b) -> float:
    return float(np.hypot(*(a - b).T).max()) if a.size else 0.0


def measure_response(model, watch=(), check=None) -> int:
    """The model's response time N_r, steps (module docstring); the model is left as it was.
    ``watch``: history points judged instead of the blocks; ``check``: steps between checks
    (default the history interval, at least 100)."""
    check = int(check or max(model.history.every, 100))
    snap = model.snapshot()
    try:
        _elastic(model)
        g = np.asarray(model.gravity, dtype=float)
        model.gravity = g * (1 + LOAD_STEP) if np.hypot(*g) > 0 else g + (0.0, -SMALL_G)
        start = positions(model, watch)
        last, done, point, quiet = start, 0, FIRST * check, 0
        while done < MOST:
            model.cycle(point - done)
            done = point
            now = positions(model, watch)
            total, recent = _largest(now, start), _largest(now, last)
            quiet = quiet + 1 if recent <= AT_REST * total else 0
            if quiet == 2:
                break
            last = now
            point = min(MOST, check * int(np.ceil(GROWTH * point / check)))
    finally:
        model.restore(snap)
    return int(done)


def _elastic(model):
    """Every intact contact elastic with no limit (its peak tensile strength and cohesion
    raised to ``STRONG``), a broken one on its residual law as it is, open contacts closed at
    zero elastic stress (the snapshot restores all three)."""
    strong = {k: replace(m, tensile_strength=STRONG, cohesion=STRONG)
              for k, m in model.materials.items()}
    model.table = material_table(model.table.names, strong, model.unbreakable)
    c = model.contacts
    n = c.count[0]
    np.maximum(c.sn_elastic[:n], 0.0, out=c.sn_elastic[:n])


def next_span(k: int, n_r: int, span: int, before: list, confirming=False) -> int:
    """Steps of window ``k`` (1-based): N_r for the first ``EVEN``; after that ``SPAN_GROWTH``
    times ``span`` (window k-1's), at most ``LONGEST`` N_r, when window k-1 was slower than
    window k-2 (``before``: their (move, speed, ratio)) or a mechanism waits to be confirmed
    (``confirming``), else ``span`` (module docstring). A window is never
    shorter than the one before."""
    if k <= EVEN:
        return n_r
    if confirming or before[-1][1] < before[-2][1]:
        return min(LONGEST * n_r, SPAN_GROWTH * span)
    return span


def judge(model, st, n_r, check, moved, trace) -> monitor.SolveResult:
    """Run windows (``next_span``: N_r = ``n_r`` steps, growing after one that slowed;
    checked every ``check``) until the verdict (module docstring). ``st``: the solve's
    ``SolveSettings``; ``moved()``: the judged displacement since the solve began (m);
    ``trace``: (steps, displacements) lists the checks append to. Sets ``model.in_motion``:
    whether the verdict is other than "equilibrium" (an excavation then keeps N_r)."""
    res = _windows(model, st, n_r, check, moved, trace)
    model.in_motion = res.verdict != "equilibrium"
    return res


def _windows(model, st, n_r, check, moved, trace) -> monitor.SolveResult:
    """``judge``'s windows and their verdict."""
    size = float(np.median(model.props.radius))
    creep = max(st.creep if st.creep is not None else 1e-3 * size, REST * size)
    what = "a watched point" if st.watch else "a block"
    steps, disp = trace
    fd = st.failure_displacement
    done, r, before = 0, float("inf"), []     # (move, speed, mean ratio) of each window
    centre = positions(model, st.watch)              # mean position over the window before
    spans = []                                       # steps of each window
    fired = None                  # steps at which the mechanism test first held
    for k in range(1, st.windows + 1):
        cracks0, ratios, total = _cracks(model), [], np.zeros_like(centre)
        span = next_span(k, n_r, spans[-1] if spans else n_r, before, fired is not None)
        spans.append(span)
        end = done + span
        while done < end:
            n = min(check, end - done)
            model.cycle(n)
            done += n
            r, d = model.unbalanced_ratio(), moved()
            steps.append(done)
            disp.append(d)
            ratios.append(r)
            total += positions(model, st.watch)
            if r <= st.ratio and (v := fastest(model, st.watch)) * model.dt * n_r <= creep:
                return _result("equilibrium", done, r, disp, n_r, f"ratio {r:.3g} <= "
                               f"{st.ratio:.3g}, fastest speed {v:.3g} m/s")
            if fd is not None and d > fd:
                return _result("failing", done, r, disp, n_r, f"{what} moved {d:.3g} m > "
                               f"{fd} m")
        mean = total / len(ratios)
        move, mean_r = _largest(mean, centre), float(np.mean(ratios))
        # the means of windows k-1 and k are (L_k-1 + L_k) / 2 apart in steps (window 1's
        # movement, from the start, counted over its own length as before)
        gap = span if k == 1 else (spans[-2] + span) / 2
        now = (move, move * n_r / gap, mean_r)
        verdict = _window_verdict(k, now, _cracks(model) - cracks0, before, creep, n_r, what,
                                  spans, _ratio_falls(ratios))
        if verdict is not None and verdict[0] == "equilibrium":
            return _result(verdict[0], done, r, disp, n_r, verdict[1])
        if verdict is not None and fired is not None and done >= CONFIRM * fired:
            return _result("failing", done, r, disp, n_r, f"{verdict[1]}; first seen at "
                           f"{fired} steps")
        if verdict is not None and fired is None:
            fired = done                  # a mechanism only if it holds as long again
        before.append(now)
        centre = mean
    if fired is not None:
        return _result("undecided", done, r, disp, n_r, f"a mechanism first seen at {fired} "
                       f"steps not seen again after {st.windows} windows ({done} steps), nor "
                       f"at rest")
    return _result("undecided", done, r, disp, n_r, f"neither at rest nor a mechanism after "
                   f"{st.windows} windows ({done} steps, N_r = {n_r}; last window: {what} moved "
                   f"{before[-1][0]:.3g} m)")


def _ratio_falls(ratios) -> bool:
    """Whether the unbalanced ratio decays within a window: the mean of its second half of
    checks at most ``RATIO_FALL`` of the first half's (module docstring)."""
    h = len(ratios) // 2
    if h == 0:
        return True
    return float(np.mean(ratios[h:])) <= RATIO_FALL * float(np.mean(ratios[:h]))


def _window_verdict(k, now, broke, before, creep, n_r, what, spans, falls=True):
    """(verdict, reason) at the end of window ``k``, or None to go on (module docstring).
    ``now`` and each of ``before`` (the windows before): (move m, speed m per N_r, mean
    ratio); ``spans``: the steps of windows 1..k."""
    if not before:
        return None
    move, v, mean_r = now
    move1, v1, ratio1 = before[-1]
    if broke == 0 and falls and (move <= 0.5 * move1 or v <= min(creep, v1)):
        return "equilibrium", (f"coming to rest: {what} moved {move:.3g} m over window {k} "
                               f"against {move1:.3g} m before ({_spans(spans[-2:], n_r)}, creep "
                               f"{creep:.3g} m per N_r), the ratio decaying, no bond broke")
    if broke == 0 and max(v, v1) <= STILL * creep:
        return "equilibrium", (f"standing still: {what} moved {v1:.3g} and {v:.3g} m per N_r "
                               f"over windows {k - 1} and {k} ({_spans(spans[-2:], n_r)}), at "
                               f"most {STILL:g} of the creep {creep:.3g} m per N_r, no bond "
                               f"broke (the ratio {mean_r:.3g})")
    if len(before) < 2:
        return None
    move2, v2, ratio2 = before[-2]
    # a slow motion (below creep, not standing still) is judged on the longest windows only
    slow = (min(v, v1, v2) > STILL * creep and len(spans) >= 3
            and min(spans[-3:]) >= LONGEST * n_r)
    if ((min(v, v1) > creep or slow) and v >= 0.8 * v1 and v1 >= 0.8 * v2
            and mean_r >= 0.9 * ratio1 and ratio1 >= 0.9 * ratio2):
        kind = "a mechanism" if min(v, v1) > creep else "a slow mechanism"
        return "failing", (f"{kind}: {what} moved {move2:.3g}, {move1:.3g} and "
                           f"{move:.3g} m over windows {k - 2}..{k} ({_spans(spans[-3:], n_r)}) "
                           f"and the mean ratio stopped falling ({ratio2:.3g}, {ratio1:.3g}, "
                           f"{mean_r:.3g})")
    return None


def _spans(spans, n_r) -> str:
    """Window lengths for a reason: "N_r = 1900 steps" when they are all N_r, else e.g.
    "2, 4 and 8 N_r, N_r = 1900 steps"."""
    n = [f"{x / n_r:g}" for x in spans]
    if set(n) == {"1"}:
        return f"N_r = {n_r} steps"
    return f"{', '.join(n[:-1])} and {n[-1]} N_r, N_r = {n_r} steps"


def _cracks(model) -> int:
    return int(model.cracks.count[0])


def _result(verdict, done, r, disp, n_r, reason) -> monitor.SolveResult:
    return monitor.SolveResult(verdict, done, r, max(disp), reason, n_r)
