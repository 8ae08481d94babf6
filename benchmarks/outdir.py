"""Where the benchmarks write their results.

A rerun writes under the top-level ``results/benchmarks/`` (``OUT``; ignored by git). The few
files the docs cite as references are committed under ``benchmarks/results/`` (``REFERENCE``);
a benchmark that writes one of them writes it there when run with ``--reference`` (then commit
it and update the doc that quotes it). The trials (``benchmarks/trials/``) write under ``OUT``
only: their committed files are the record of a one-off run.
"""
from __future__ import annotations

import argparse
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "results" / "benchmarks"
REFERENCE = ROOT / "benchmarks" / "results"


def results_dir(reference: bool = False) -> Path:
    """The folder to write to (made if missing): ``REFERENCE`` if ``reference``, else ``OUT``."""
    path = REFERENCE if reference else OUT
    path.mkdir(parents=True, exist_ok=True)
    return path


def add_reference_flag(ap: argparse.ArgumentParser) -> argparse.ArgumentParser:
    """``--reference``: write to ``benchmarks/results/`` (committed) instead of ``OUT``."""
    ap.add_argument("--reference", action="store_true",
                    help="write the results to benchmarks/results/ (the committed files the "
                         "docs cite) instead of results/benchmarks/")
    return ap


def find(name: str) -> Path:
    """An earlier result file ``name``: a rerun's (``OUT``) if there is one, else the committed
    one (``REFERENCE``); ``OUT / name`` if neither exists."""
    for folder in (OUT, REFERENCE):
        if (folder / name).exists():
            return folder / name
    return OUT / name
