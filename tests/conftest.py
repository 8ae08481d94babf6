"""Test-suite settings: hypothesis runs derandomized (the same examples every run), so a
result does not depend on which random examples CI happened to draw; set
HYPOTHESIS_PROFILE=explore to search with fresh random examples."""
import os

from hypothesis import settings

settings.register_profile("deterministic", derandomize=True, print_blob=True)
settings.register_profile("explore", derandomize=False, print_blob=True)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "deterministic"))
