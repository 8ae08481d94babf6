"""Comparing a quick case's failure g-levels with the stored regression numbers
(tests/case_reference.json, written by benchmarks/case_reference.py)."""
import json
from pathlib import Path

import pytest

REFERENCE = json.loads((Path(__file__).parent / "case_reference.json").read_text())


def assert_failure_g_matches(measured: dict, case: str) -> None:
    """Every stored failure g of ``case`` (e.g. "adhikary_quick") equals the measured one
    within the stored tolerance; a stored null (no failure) must stay null."""
    ref = REFERENCE[case]
    assert set(measured) == set(ref["failure_g"])
    for label, g in ref["failure_g"].items():
        if g is None:
            assert measured[label] is None, label
        else:
            assert measured[label] == pytest.approx(g, abs=ref["abs_tolerance_g"]), label
