"""A pytest plugin that records numba's first compiles during a test run.

    PYTHONPATH=benchmarks/trials ./dev test -p compile_probe          # or python -m pytest -p ...

It listens to numba's ``numba:compile`` events and keeps, for every compile (a cache load is
one too, and short), the dispatcher's module and name, the nesting depth (0: an entry point
called from Python; deeper: a kernel compiled because an entry point calls it), the seconds,
the start of the argument types, and the test during which it happened. At the end of the
session each process (each pytest-xdist worker, named by ``PYTEST_XDIST_WORKER``) writes
``$COMPILE_PROBE_OUT.<worker>`` (default ``results/benchmarks/compiles.json.<worker>``; the
committed record: ``benchmarks/results/compiles.json.gw0``, ``.gw1``).
A signature compiled twice shows as two records of one name (docs/performance.md, "The test
suite's time").

    python benchmarks/trials/compile_probe.py FILE...     # a table of the records

prints, per file (worker), the seconds of its first compiles called from Python (depth 0)
and the kernels that took longest, with the nested ones they include and the test that
compiled them.
"""
from __future__ import annotations

import json
import os
import time
from pathlib import Path

import numba.core.event as numba_event

_records: list = []
_now = {"test": None, "starts": []}


class _Listener(numba_event.Listener):
    def on_start(self, event):
        _now["starts"].append(time.perf_counter())

    def on_end(self, event):
        seconds = time.perf_counter() - _now["starts"].pop()
        data = event.data or {}
        fn = getattr(data.get("dispatcher"), "py_func", None)
        _records.append({"name": f"{getattr(fn, '__module__', '')}.{getattr(fn, '__qualname__', '?')}",
                         "depth": len(_now["starts"]), "seconds": round(seconds, 3),
                         "args": str(data.get("args"))[:300], "test": _now["test"]})


numba_event.register("numba:compile", _Listener())


def pytest_runtest_setup(item):
    _now["test"] = item.nodeid


def pytest_sessionfinish(session):
    default = Path(__file__).resolve().parents[2] / "results" / "benchmarks" / "compiles.json"
    out = Path(os.environ.get("COMPILE_PROBE_OUT", default))
    out.parent.mkdir(parents=True, exist_ok=True)
    worker = os.environ.get("PYTEST_XDIST_WORKER", "main")
    out.with_name(f"{out.name}.{worker}").write_text(json.dumps(_records, indent=0))


def summary(paths, top=15) -> str:
    """The table of ``python benchmarks/trials/compile_probe.py FILE...`` (module docstring)."""
    lines = []
    for path in paths:
        records = json.loads(Path(path).read_text())
        entry = [r for r in records if r["depth"] == 0]
        lines.append(f"{path}: {len(records)} compiles, "
                     f"{sum(r['seconds'] for r in entry):.1f} s called from Python")
        for r in sorted(records, key=lambda r: -r["seconds"])[:top]:
            test = (r["test"] or "").split("::")[0]
            lines.append(f"  {r['seconds']:7.1f} s  depth {r['depth']}  {r['name']}  [{test}]")
    return "\n".join(lines)


if __name__ == "__main__":
    import sys

    if len(sys.argv) < 2:
        sys.exit("usage: python benchmarks/trials/compile_probe.py FILE...")
    print(summary(sys.argv[1:]))
