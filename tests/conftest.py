"""Test-suite settings: hypothesis runs derandomized (the same examples every run), so a
result does not depend on which random examples CI happened to draw; set
HYPOTHESIS_PROFILE=explore to search with fresh random examples; every test's open
matplotlib figures are closed after it; the test files are ordered for pytest-xdist
(``pytest_collection_modifyitems``)."""
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


# pytest-xdist (./dev test: --dist loadfile --no-loadscope-reorder) hands whole files to its
# workers in collection order, the next file to whichever worker runs short. First a file that
# steps a model: its worker compiles the step (about two minutes from a clean clone). Then
# files that never step one, in this process or a child: the other worker runs them meanwhile
# and then loads the step from numba's cache instead of compiling it as well
# (``dem_core.jit_cache`` makes it wait for the cache if it gets there first). Then the
# longest files (their seconds, fixtures included, AMD EPYC 2-core, 2026-12-01, two workers,
# one-process sweeps), so that the two workers finish together; the rest in their usual order.
COMPILES_THE_STEP = ["test_mech_closed_forms.py"]        # steps at its first test
NEVER_STEPS = ["test_continuum_ssr.py",                # 140 s (Davis and associated meshes)
               "test_continuum_robustness.py",         # 13
               "test_continuum_model.py",              # 14
               "test_geometry_blocks.py",              # 6
               "test_continuum_return_mapping.py",
               "test_geometry_joints.py",
               "test_continuum_staged.py",
               "test_continuum_hoek_brown.py",
               "test_continuum_footing.py"]
LONGEST = ["test_adhikary_quick.py",                   # 518
           "test_common_toppling_quick.py",            # 304 (edge elements)
           "test_lornex_quick.py",                     # 125
           "test_examples.py",                         # 102 (the README's slope)
           "test_same_bits.py",                        # 93
           "test_sweep_mpi.py",                        # 67
           "test_underdip_quick.py",                   # 57
           "test_lajtai_case.py",                      # 46
           "test_adhikary_case.py",                    # 36
           "test_checkerboard_quick.py",               # 25
           "test_lajtai_deformable.py",                # 19
           "test_longtan_quick.py",                    # 17
           "test_voronoi_beam.py",
           "test_deformable.py"]                       # compiles the threaded step
_ORDER = {name: i for i, name in enumerate(COMPILES_THE_STEP + NEVER_STEPS + LONGEST)}


def pytest_configure(config):
    """In each pytest-xdist worker, sweeps get the worker's share of the cores
    (``COMPARISONS_WORKERS``, ``comparisons.sweep.local_workers``): two workers each running a
    two-process sweep on two cores time-share them."""
    from comparisons.sweep import usable_cores

    workers = int(os.environ.get("PYTEST_XDIST_WORKER_COUNT", "0"))
    if workers > 1 and "COMPARISONS_WORKERS" not in os.environ:
        os.environ["COMPARISONS_WORKERS"] = str(max(1, usable_cores() // workers))


# The thesis's cases (their quick variants and case runs): marked ``case``, so that
# ``./dev test --fast`` (``-m "not case"``) runs the physics without them
CASE_FILES = ("_quick.py", "_case.py")


def pytest_collection_modifyitems(config, items):
    """Files in the order above (a stable sort: each file's tests keep their order); the case
    files' tests marked ``case``."""
    items.sort(key=lambda item: _ORDER.get(item.path.name, len(_ORDER)))
    for item in items:
        if item.path.name.endswith(CASE_FILES):
            item.add_marker(pytest.mark.case)
