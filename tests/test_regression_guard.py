"""Regression guard: cheap closed-form checks must give the stored reference numbers.

The numbers, their tolerances and the reason for each tolerance are in
``tests/regression_reference.json`` (written by ``benchmarks/regression_numbers.py --write``,
which also says how the tolerances were chosen: far above round-off, at least 10x below the
change a real physics or solver change makes). A failure here means the physics or the solver
changed: if that was intended, check the closed-form tests still pass, regenerate the reference
and say so in the commit.

Each number is also checked against its closed form with the physics tolerance of the
corresponding test, so the reference itself cannot drift into a wrong answer.
"""
import json
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "benchmarks"))

import regression_numbers  # noqa: E402

REFERENCE = json.loads((ROOT / "tests" / "regression_reference.json").read_text())["numbers"]

# closed-form sanity bounds (the accuracy the closed-form tests claim)
PHYSICS = {
    "dem.sliding_block.rel_error": lambda v: abs(v) < 0.01,
    "dem.oscillation.rel_error": lambda v: abs(v) < 0.02,
    "dem.oscillation.energy_drift": lambda v: v < 0.01,
    "dem.brick_bar.rel_error": lambda v: abs(v) < 0.02,
    "dem.cantilever_10mm.deflection_um": lambda v: 5.0 < v < 50.0,
    "dem.auto_dt_kn1e12.ns": lambda v: v > 0,
    "continuum.gravity_column_P2.rel_error": lambda v: abs(v) < 1e-10,
    "continuum.gravity_column_P1_h0.5.stress_rel_error": lambda v: 0 < v < 0.05,
    "continuum.footing_h0.1.q_over_c": lambda v: abs(v / 5.1416 - 1) < 0.05,
}


@pytest.fixture(scope="module")
def measured():
    return regression_numbers.measure()


def test_every_reference_number_has_a_tolerance_and_a_reason():
    assert set(REFERENCE) == set(regression_numbers.TOLERANCES)
    for name, ref in REFERENCE.items():
        assert ref["abs_tolerance"] > 0 and ref["what"], name
        # a tolerance wider than 1 % of the value could not catch a real change
        assert ref["abs_tolerance"] <= 0.01 * abs(ref["value"]) or abs(ref["value"]) < 1e-9, name


@pytest.mark.parametrize("name", sorted(REFERENCE))
def test_number_matches_reference(measured, name):
    if name.startswith("continuum."):
        pytest.importorskip("dolfinx")
    value, ref = measured[name], REFERENCE[name]
    assert PHYSICS[name](value), f"{name} = {value!r} is off its closed form"
    assert abs(value - ref["value"]) <= ref["abs_tolerance"], (
        f"{name} = {value!r}, reference {ref['value']!r} +- {ref['abs_tolerance']} "
        f"({ref['what']}): the physics or the solver changed")
