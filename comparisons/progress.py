"""Progress of long runs: the case's own lines, and where each sweep member is.

``Progress(label)`` (the command line makes one per run) prints ``[label elapsed] message``
lines on stderr, and shows the statuses its sweep members report: where the terminal allows
(the stream is a TTY and TERM is not "dumb") one line per running member, rewritten in place
below the messages and removed when the member finishes; otherwise (a log, CI, a pipe) each
status as a plain line::

    [longtan  62.2 s] member 2/2 T=4.81: g = 80 (level 2/10), 60000 steps, elapsed 62.0 s, left ~4 min 08 s

A member reports with ``report(stage, steps, left=None, elapsed=None)``; the centrifuge g-ramp
does after every level (``centrifuge.ramp_run``, estimate from ``ramp_status``), a lab test
after every stage (``stage_reporter``). ``sweep.run_sweep`` tells a member who it is and sends
its reports on: in the same process straight to the ``Progress``; from a local process pool
through a multiprocessing queue that a thread of the parent drains; under MPI (workers on other
nodes, no shared memory) as plain lines on the worker's stderr, which mpirun forwards. Outside
a sweep ``report`` does nothing, and a report that cannot be delivered is dropped: progress never
stops a run.
"""
from __future__ import annotations

import math
import os
import shutil
import sys
import threading
import time
from contextlib import contextmanager
from dataclasses import dataclass

__all__ = ["Progress", "Status", "report", "ramp_status", "stage_reporter", "duration"]


@dataclass(frozen=True)
class Status:
    """Where member ``index`` (0-based) of ``n`` (``label``, e.g. "T=1.1") is: ``stage`` in
    words (e.g. "g = 70 (level 7/30)"), ``steps`` run so far, ``elapsed`` s since it started
    (with the earlier part of a resumed run), ``left`` s estimated (None: unknown)."""

    index: int
    n: int
    label: str
    stage: str
    steps: int
    elapsed: float
    left: float | None = None

    def line(self) -> str:
        who = f"member {self.index + 1}/{self.n}" + (f" {self.label}" if self.label else "")
        left = "left unknown" if self.left is None else f"left ~{duration(self.left)}"
        return (f"{who}: {self.stage}, {self.steps} steps, elapsed {duration(self.elapsed)}, "
                f"{left}")


def duration(seconds: float) -> str:
    """"41.2 s", "12 min 05 s", "2 h 03 min"."""
    s = max(0.0, float(seconds))
    if s < 60:
        return f"{s:.1f} s"
    if s < 3600:
        return f"{int(s // 60)} min {int(s % 60):02d} s"
    return f"{int(s // 3600)} h {int(s % 3600 // 60):02d} min"


class Progress:
    """Print ``[label elapsed] message`` lines and the members' statuses (module docstring) on
    ``stream`` (default stderr); ``quiet=True`` silences both (tests); ``live`` forces (True)
    or forbids (False) the updating lines, default: whether the stream is a terminal."""

    def __init__(self, label: str, quiet: bool = False, stream=None, live: bool | None = None):
        self.label = label
        self.quiet = quiet
        self.stream = stream or sys.stderr
        self.live = _is_terminal(self.stream) if live is None else bool(live)
        self.t0 = time.perf_counter()
        self._lines = {}                    # member index -> its status line (live)
        self._finished = set()              # members done: a late report is ignored
        self._shown = 0                     # status lines on the screen now
        self._lock = threading.Lock()       # the pool's reports come from a thread

    def __call__(self, message: str) -> None:
        if self.quiet:
            return
        with self._lock:
            self._erase()
            self._write(f"{self._prefix()} {message}\n")
            self._draw()

    def member(self, status: Status) -> None:
        """Show a member's status: its line updated (live) or a plain line."""
        if self.quiet:
            return
        with self._lock:
            if not self.live:       # a log keeps every report, even one that arrives after
                self._write(f"{self._prefix()} {status.line()}\n")     # the member's result
                return
            if status.index in self._finished:
                return
            self._lines[status.index] = status.line()
            self._erase()
            self._draw()

    def new_sweep(self) -> None:
        """A new sweep starts: its members are numbered from 1 again (``sweep.run_sweep``)."""
        with self._lock:
            self._finished.clear()
            self._lines.clear()

    def finish(self, index: int) -> None:
        """Member ``index`` is done: its line goes (on a live board its later reports are
        ignored; a report from a pool's queue can arrive after the member's result)."""
        with self._lock:
            self._finished.add(index)
            if self._lines.pop(index, None) is not None and not self.quiet:
                self._erase()
                self._draw()

    def _prefix(self) -> str:
        return f"[{self.label} {time.perf_counter() - self.t0:7.1f} s]"

    def _write(self, text: str) -> None:
        self.stream.write(text)
        self.stream.flush()

    def _erase(self) -> None:
        """Move up over the status lines and clear to the end of the screen."""
        if self._shown:
            self._write(f"\x1b[{self._shown}F\x1b[J")
            self._shown = 0

    def _draw(self) -> None:
        """The status lines, each cut to the terminal's width (a wrapped line would break
        the count of lines to move up over)."""
        if not self._lines:
            return
        width = max(20, self._columns() - 1)
        self._write("".join(self._lines[i][:width] + "\n" for i in sorted(self._lines)))
        self._shown = len(self._lines)


    def _columns(self) -> int:
        """The width of the terminal the stream writes to (stdout's, or 80, if unknown)."""
        try:
            return os.get_terminal_size(self.stream.fileno()).columns
        except (AttributeError, ValueError, OSError):
            return shutil.get_terminal_size().columns


def _is_terminal(stream) -> bool:
    try:
        return bool(stream.isatty()) and os.environ.get("TERM", "") != "dumb"
    except (AttributeError, ValueError):
        return False


# ---------------------------------------------------------------------- inside a member
@dataclass(frozen=True)
class Member:
    """Who a running sweep member is: index, n, label, the case's label, the start time
    (``time.time()``: the same clock in every process), and where its reports go."""

    index: int
    n: int
    label: str
    case: str
    t0: float
    send: object = None         # callable(Status), or None: reports are dropped


_MEMBER: list = []              # the member running in this process (a stack of 0 or 1)
_QUEUE = None                   # a pool worker's queue to the parent (``worker_init``)


@contextmanager
def as_member(index: int, n: int, label: str, case: str, send):
    """Run the block as sweep member ``index`` of ``n``; ``send`` receives its Statuses.
    Announces the start ("started")."""
    _MEMBER.append(Member(index, n, label, case, time.time(), send))
    try:
        report("started", 0, elapsed=0.0)
        yield
    finally:
        _MEMBER.pop()


def report(stage: str, steps: int, left: float | None = None,
           elapsed: float | None = None) -> None:
    """Report where the member running in this process is (module docstring): ``stage`` in
    words, ``steps`` so far, ``left`` s estimated (None: unknown), ``elapsed`` s (default:
    since the member started). Does nothing outside a sweep member."""
    if not _MEMBER or _MEMBER[-1].send is None:
        return
    m = _MEMBER[-1]
    spent = time.time() - m.t0 if elapsed is None else float(elapsed)
    status = Status(m.index, m.n, m.label, stage, int(steps), spent,
                    None if left is None or not math.isfinite(left) else float(left))
    try:
        m.send(status)
    except Exception:               # a closed pipe or queue: progress never stops a run
        pass


def worker_init(queue) -> None:
    """Initializer of a local pool's worker processes: reports go to ``queue``."""
    global _QUEUE
    _QUEUE = queue


def queue_sender():
    """In a pool worker: the callable that puts a Status on the parent's queue (None when the
    pool was made without one)."""
    return None if _QUEUE is None else _QUEUE.put


def line_sender(case: str):
    """Under MPI: a callable that prints each Status as a plain line on stderr."""
    def send(status: Status) -> None:
        # one write of the whole line: lines of workers sharing the stream do not interleave
        sys.stderr.write(f"[{case}] {status.line()}\n")
        sys.stderr.flush()
    return send


# ---------------------------------------------------------------------- estimates
def ramp_status(rec, levels, elapsed: float, refine_to=None) -> tuple:
    """(stage text, estimated seconds left or None) of a load-parameter search just after a
    level (``dem_core.workflow.limit.LimitRecord`` ``rec`` as an ``on_level`` callback sees it, planned
    ``levels``, ``elapsed`` s so far, ``refine_to`` as given to the search). The estimate is the
    mean time per level so far times the levels still to run: in the first pass the planned
    levels after this one (a model that fails sooner ends sooner), once a level has failed the
    bisection's remaining halvings; unknown (None) while the search closes in from the last
    stable level in ``refine_to`` steps (the level that will fail is not known)."""
    value, name, verdict = rec.level[-1], rec.parameter, rec.verdict[-1]
    per_level = elapsed / len(rec.level)
    if verdict in ("unstable", "undecided"):     # the search stops here
        left = 0
    elif rec.refined == 0 and verdict not in ("failed", "failing"):
        left = sum(1 for v in levels if not _reached(v, value, levels))
    else:
        left = _halvings(rec, refine_to)
    if rec.refined == 0:
        k = sum(1 for v in levels if _reached(v, value, levels))
        text = f"{name} = {value:g} (level {k}/{len(levels)})"
    else:
        text = f"{name} = {value:g} (refining, level {len(rec.level)})"
    return text, (None if left is None else per_level * left)


def _reached(v, value, levels):
    """Whether planned level ``v`` is at or before ``value`` (levels rise or fall)."""
    rising = len(levels) < 2 or levels[-1] > levels[0]
    return v <= value + 1e-12 if rising else v >= value - 1e-12


def _halvings(rec, refine_to):
    """Bisections left to narrow [last stable, failed] to ``refine_to`` just after a level (0
    without ``refine_to``; None when no level has failed yet: the closing steps)."""
    if refine_to is None:
        return 0
    failed = rec.verdict[-1] in ("failed", "failing")
    high = rec.level[-1] if failed else rec.failure_level
    low = rec.last_stable_level if failed else rec.level[-1]
    if high is None:
        return None
    width = abs(high - (0.0 if low is None else low))
    return math.ceil(math.log2(width / refine_to) - 1e-9) if width > refine_to else 0


def stage_reporter(model, n_stages: int):
    """A ``dem_core.workflow.stages.run_stages`` progress callback for a sweep member: reports "k/n
    stages done" with the model's steps after each stage (left unknown: stages differ too much
    in length to extrapolate)."""
    done = [0]

    def say(message: str) -> None:
        done[0] += 1
        report(f"{done[0]}/{n_stages} stages done ({message.split(',')[0]})", int(model.step))
    return say
