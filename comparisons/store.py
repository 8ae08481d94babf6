"""What a case run keeps on disk besides its summary: each finished sweep member's result, so an
interrupted run resumes, and (asked for) the DEM models' VTK files.

The command line (``comparisons.cli``) runs a case inside ``case_output(<out>/<case>, resume,
vtk)``. Inside it, ``sweep.run_sweep`` writes each member's result to
``<out>/<case>/members/<function>-<key>.json`` as soon as the member finishes (``key``: a hash
of the member function's name and its parameters, seeds included) and, with ``resume=True``,
loads a member whose file is there instead of running it. Members are pure functions of their
parameters, and every result goes through the same JSON round trip whether it was just computed
or loaded, so a resumed run's results equal an uninterrupted run's.

What a kept result came from: each member file holds ``{"source": {"member": <key>, "run":
<source>}, "result": ...}``, ``source`` being a hash of the whole run's input (``source_hash``;
the command line's: the case, its settings after ``--set`` and the seed, or the scene's
canonical JSON and the ``--set`` overrides). With ``resume``, ``case_output`` first reads every
kept member and checkpoint of the folder and refuses (``StaleResult``, a ValueError: one line
naming the file) one written by a run of another source, or one that does not say, before any
compute: the scene or settings changed since it was written. A run without ``resume``, or with
``restart``, deletes the folder's kept results first and starts over. The code is not in the
source: after changing the code, run without ``--resume``.

``vtk_folder()`` is ``<out>/<case>/vtk`` when the run was asked for VTK files, else None; a
case puts it into its members' parameters (members may run in other processes), and a member
that builds a DEM model writes its final state there (``Model.write_vtk``).

A long member can also keep its own progress: ``checkpoint(params)`` is a file stem in the
members folder, unique to the parameters, where a centrifuge member saves its model after each
stable g-level (``dem_core.workflow.limit.save_resumable``) and from which it goes on when it is run
again. Next to it, ``<stem>.source.json`` records the source of the run that asked for it (the
checkpoint's own files are ``dem_core.workflow.limit``'s); a checkpoint ``.json`` that does not
parse is refused on ``resume`` (one line naming it), not met later as a traceback.

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
           "dumps", "loads", "check_folder", "source_hash", "StaleResult", "clear_kept",
           "check_kept"]


class StaleResult(ValueError):
    """A kept result or checkpoint that does not belong to the present run (its message: one
    line naming the file)."""


@dataclass(frozen=True)
class CaseOutput:
    """A case run's folder (``<out>/<case>``), whether to load kept members, whether to write
    VTK files."""

    folder: Path
    resume: bool = False
    vtk: bool = False
    source: str | None = None

    @property
    def members(self) -> Path:
        return self.folder / "members"

    def member_path(self, function, params) -> Path:
        return self.members / f"{function.__name__}-{member_key(function, params)}.json"

    def load(self, function, params) -> tuple:
        """(True, result) of a kept member when resuming, else (False, None). A file that does
        not parse (the run was killed while writing it) counts as missing; one kept by a run
        of another source, or for other parameters, is a ``StaleResult``."""
        path = self.member_path(function, params)
        if not (self.resume and path.exists()):
            return False, None
        try:
            kept = loads(path.read_text())
        except ValueError:
            return False, None
        expected = {"member": member_key(function, params), "run": self.source}
        if not isinstance(kept, dict) or kept.get("source") != expected:
            raise StaleResult(stale_message(path))
        return True, kept["result"]

    def save(self, function, params, result):
        """Write a finished member's result with its source (atomically: a killed run leaves no
        half file) and return it as read back, so kept and fresh results are alike."""
        path = self.member_path(function, params)
        text = dumps({"source": {"member": member_key(function, params), "run": self.source},
                      "result": result})
        tmp = path.with_name(path.name + ".part")
        tmp.write_text(text)
        os.replace(tmp, path)
        return loads(text)["result"]


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


def stale_message(path) -> str:
    return (f"{str(path)!r} was kept by a run of another scene or other settings: the scene or "
            f"settings changed since it was written (or it predates recorded sources); run "
            f"again with --restart to delete the kept results and start over")


def source_hash(value) -> str:
    """16 hex digits of the SHA-256 of ``value`` as canonical JSON (sorted keys): what a run
    came from (``CaseOutput.source``)."""
    text = json.dumps(value, sort_keys=True, default=_encode_any)
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def _kept_files(members: Path) -> list:
    """The files a run keeps in ``members``: member results, checkpoints and their parts."""
    if not members.is_dir():
        return []
    return [f for f in members.iterdir() if f.is_file() and (
        f.name.startswith("checkpoint-") or f.suffix in (".json", ".part", ".npz"))]


def clear_kept(folder) -> None:
    """Delete the kept results of the run folder ``folder`` (``folder/members``)."""
    for f in _kept_files(Path(folder) / "members"):
        f.unlink(missing_ok=True)


def check_kept(folder, source) -> None:
    """Refuse (``StaleResult``, naming the file) a kept member or checkpoint of the run folder
    ``folder`` that a run of another ``source`` wrote, or that does not say; a checkpoint
    ``.json`` that does not parse is a ValueError naming it. A member file that does not parse
    passes (it counts as missing: ``CaseOutput.load``)."""
    for f in sorted(_kept_files(Path(folder) / "members")):
        name = f.name
        if f.suffix != ".json" or name.endswith((".part.json", ".source.json")):
            continue
        if name.startswith("checkpoint-"):
            try:
                saved = json.loads(f.read_text())
            except (ValueError, UnicodeDecodeError) as e:
                raise ValueError(f"checkpoint {str(f)!r} is not valid JSON ({e}): it was cut "
                                 f"short; run again with --restart to start over") from None
            recorded = saved.get("source") if isinstance(saved, dict) else None
            if recorded is None:
                side = f.with_name(f.name[:-len(".json")] + ".source.json")
                try:
                    recorded = json.loads(side.read_text())
                except (OSError, ValueError):
                    recorded = None
            if not isinstance(recorded, dict) or recorded.get("run") != source:
                raise StaleResult(stale_message(f))
        else:
            try:
                kept = loads(f.read_text())
            except (ValueError, UnicodeDecodeError):
                continue                                # half written: run again
            recorded = kept.get("source") if isinstance(kept, dict) else None
            if not isinstance(recorded, dict) or recorded.get("run") != source:
                raise StaleResult(stale_message(f))


@contextmanager
def case_output(folder, resume: bool = False, vtk: bool = False, source: str | None = None,
                restart: bool = False):
    """Keep the sweep members of the case run inside the block in ``folder/members`` (created
    and checked now, so an unwritable folder fails before any compute: ``check_folder``);
    load them instead of running them when ``resume`` (after ``check_kept``: a kept result of
    another ``source`` is refused now); without ``resume``, or with ``restart``, the kept
    results are deleted first; ``vtk``: members write their models to ``folder/vtk``.
    ``source``: what the run came from (``source_hash``), recorded with every kept result."""
    out = CaseOutput(Path(folder), bool(resume) and not restart, bool(vtk), source)
    check_folder(out.members)
    if out.resume:
        check_kept(out.folder, source)
    else:
        clear_kept(out.folder)
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
    its progress (a file stem), or None outside a ``case_output``; writes
    ``<stem>.source.json``, the run's source (``check_kept``)."""
    out = current()
    if out is None:
        return None
    stem = out.members / f"checkpoint-{source_hash(params)}"
    side = stem.with_name(stem.name + ".source.json")
    side.write_text(json.dumps({"member": source_hash(params), "run": out.source}))
    return str(stem)


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


def _encode_any(value):
    """``_encode``, and anything else by its repr (a hash needs no round trip)."""
    try:
        return _encode(value)
    except TypeError:
        return repr(value)


def _decode(obj):
    if "__ndarray__" in obj:
        return np.array(obj["__ndarray__"], dtype=obj["dtype"]).reshape(obj["shape"])
    return obj
