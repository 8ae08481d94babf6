"""Progress lines for long runs: one line per step with elapsed time, flushed at once."""
from __future__ import annotations

import sys
import time


class Progress:
    """Print ``[case] message (elapsed s)`` lines; ``quiet=True`` silences them (tests)."""

    def __init__(self, label: str, quiet: bool = False, stream=None):
        self.label = label
        self.quiet = quiet
        self.stream = stream or sys.stderr
        self.t0 = time.perf_counter()

    def __call__(self, message: str) -> None:
        if not self.quiet:
            elapsed = time.perf_counter() - self.t0
            print(f"[{self.label} {elapsed:7.1f} s] {message}", file=self.stream, flush=True)
