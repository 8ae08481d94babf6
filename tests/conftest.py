"""Test-suite settings: hypothesis runs derandomized (the same examples every run), so a
result does not depend on which random examples CI happened to draw; set
HYPOTHESIS_PROFILE=explore to search with fresh random examples; every test's open
matplotlib figures are closed after it."""
import os

import pytest

from hypothesis import settings

settings.register_profile("deterministic", derandomize=True, print_blob=True)
settings.register_profile("explore", derandomize=False, print_blob=True)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "deterministic"))


@pytest.fixture(autouse=True)
def _close_figures():
    """Close the figures a test's case run made (a CaseResult keeps them open until written),
    so they do not pile up over the session."""
    yield
    import sys
    if "matplotlib.pyplot" in sys.modules:
        sys.modules["matplotlib.pyplot"].close("all")
