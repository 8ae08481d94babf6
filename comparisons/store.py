"""What a case run keeps on disk besides its summary: each finished sweep member's result, so an
interrupted run resumes, and (asked for) the DEM models' VTK files.

The command line (``comparisons.cli``) runs a case inside ``case_output(<out>/<case>, resume,
vtk)``. Inside it, ``sweep.run_sweep`` writes each member's result to
``<out>/<case>/members/<function>-<key>.json`` as soon as the member finishes (``key``: a hash
of the member function's name and its parameters, seeds included) and, with ``resume=True``,
loads a member whose file is there instead of running it. Members are pure functions of their
parameters, and every result goes through the same JSON round trip whether it was just computed
or loaded, so a resumed run's results equal an uninterrupted run's. A kept result is trusted:
after changing the code, run without ``--resume`` (it rewrites the files of every member it
runs).

``vtk_folder()`` is ``<out>/<case>/vtk`` when the run was asked for VTK files, else None; a
case puts it into its members' parameters (members may run in other processes), and a member
that builds a DEM model writes its final state there (``Model.write_vtk``).

A long member can also keep its own progress: ``checkpoint(params)`` is a file stem in the
members folder, unique to the parameters, where a centrifuge member saves its model after each
stable g-level (``dem_core.workflow.limit.save_resumable``) and from which it goes on when it is run
again; a run without ``resume`` first deletes the checkpoints an earlier run left.

From Python: ``with case_output("results/adhikary", resume=True): adhikary.run("full")``.
"""
from __future__ import annotations

import hashlib
import json
import os
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path

import numpy as np

__all__ = ["CaseOutput", "case_output", "current", "vtk_folder", "checkpoint", "member_key",
           "dumps", "loads", "check_folder"]


@dataclass(frozen=True)
class CaseOutput:
    """A case run's folder (``<out>/<case>``), whether to load kept members, whether to write
    VTK files."""

    folder: Path
    resume: bool = False
    vtk: bool = False

    @property
    def members(self) -> Path:
        return self.folder / "members"

    def member_path(self, function, params) -> Path:
        return self.members / f"{function.__name__}-{member_key(function, params)}.json"

    def load(self, function, params) -> tuple:
        """(True, result) of a kept member when resuming, else (False, None). A file that does
        not parse (the run was killed while writing it) counts as missing."""
        path = self.member_path(function, params)
        if not (self.resume and path.exists()):
            return False, None
        try:
            return True, loads(path.read_text())
        except ValueError:
            return False, None

    def save(self, function, params, result):
        """Write a finished member's result (atomically: a killed run leaves no half file) and
        return it as read back, so kept and fresh results are alike."""
        path = self.member_path(function, params)
        text = dumps(result)
        tmp = path.with_name(path.name + ".part")
        tmp.write_text(text)
        os.replace(tmp, path)
        return loads(text)


_CURRENT: list = []


def check_folder(folder) -> Path:
    """Create ``folder`` (and its parents) and check that a file can be written in it, before
    any compute; returns it as a Path. ValueError naming the folder and why otherwise (a file
    in its place, no permission, a read-only or full file system)."""
    folder = Path(folder)
    probe = folder / f".write-test-{os.getpid()}"
    try:
        folder.mkdir(parents=True, exist_ok=True)
        probe.write_text("")
        probe.unlink()
    except OSError as e:
        why = e.strerror or type(e).__name__
        if e.filename is not None and str(e.filename) != str(folder):
            why += f" ({e.filename})"
        raise ValueError(f"cannot write results to {str(folder)!r}: {why}") from None
    return folder


@contextmanager
def case_output(folder, resume: bool = False, vtk: bool = False):
    """Keep the sweep members of the case run inside the block in ``folder/members`` (created
    and checked now, so an unwritable folder fails before any compute: ``check_folder``);
    load them instead of running them when ``resume``; ``vtk``: members write their models to
    ``folder/vtk``."""
    out = CaseOutput(Path(folder), bool(resume), bool(vtk))
    check_folder(out.members)
    if not out.resume:
        for old in out.members.glob("checkpoint-*"):
            old.unlink()
    if out.vtk:
        (out.folder / "vtk").mkdir(exist_ok=True)
    _CURRENT.append(out)
    try:
        yield out
    finally:
        _CURRENT.pop()


def current() -> CaseOutput | None:
    """The innermost ``case_output`` in force, or None (members are then not kept)."""
    return _CURRENT[-1] if _CURRENT else None


def vtk_folder() -> Path | None:
    """``<out>/<case>/vtk`` when the run in force writes VTK files, else None."""
    out = current()
    return out.folder / "vtk" if out is not None and out.vtk else None


def checkpoint(params) -> str | None:
    """``<members>/checkpoint-<hash of params>``: where a member with these parameters keeps
    its progress (a file stem), or None outside a ``case_output``."""
    out = current()
    if out is None:
        return None
    text = json.dumps(params, sort_keys=True, default=_encode)
    return str(out.members / f"checkpoint-{hashlib.sha256(text.encode()).hexdigest()[:16]}")


def member_key(function, params) -> str:
    """16 hex digits of the SHA-256 of the function's module and name and its parameters."""
    name = f"{function.__module__}.{function.__qualname__}"
    text = json.dumps([name, params], sort_keys=True, default=_encode)
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def dumps(value) -> str:
    """JSON of a member's result: numpy arrays keep dtype and shape, numpy scalars become
    Python numbers, NaN and infinities are kept (as JSON's NaN, Infinity)."""
    return json.dumps(value, default=_encode)


def loads(text: str):
    """The inverse of ``dumps`` (tuples come back as lists)."""
    return json.loads(text, object_hook=_decode)


def _encode(value):
    if isinstance(value, np.ndarray):
        return {"__ndarray__": value.tolist(), "dtype": str(value.dtype),
                "shape": list(value.shape)}
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, Path):
        return str(value)
    raise TypeError(f"a sweep member's result holds a {type(value).__name__}, which cannot be "
                    f"kept as JSON: {value!r}")


def _decode(obj):
    if "__ndarray__" in obj:
        return np.array(obj["__ndarray__"], dtype=obj["dtype"]).reshape(obj["shape"])
    return obj
