"""Examples are tests: each script in examples/ asserts one physical number (shrunk here by
``quick=True``); this runs them all, so an example that stops being true fails the suite."""
import importlib
import sys
from pathlib import Path

import pytest

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
NAMES = sorted(p.stem for p in EXAMPLES.glob("*.py"))


def test_every_example_is_run_here():
    assert {"centrifuge_slope", "sliding_block", "bond_in_tension"} <= set(NAMES)


@pytest.mark.parametrize("name", NAMES)
def test_example(name, monkeypatch):
    monkeypatch.syspath_prepend(str(EXAMPLES))
    module = importlib.import_module(name)
    assert module.main(quick=True) > 0          # each main asserts its own number
    sys.modules.pop(name, None)
