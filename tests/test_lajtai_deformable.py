"""The lajtai UCS test with deformable blocks (docs/comparisons.md, lajtai).

A broken specimen of rigid Voronoi blocks interlocks by friction: at a near-zero flaw cohesion
its UCS is about 4.4 MPa, above the thesis's 4.1 MPa, so the calibration cannot reach the
target (the strict xfail in test_lajtai_case.py). The thesis's UDEC blocks were deformable;
with the specimen's blocks meshed into zones (the case's ``zone_size`` setting) the floor falls
below the target and the calibration has room (benchmarks/trials/deformable_ucs.py: c = 0.75 MPa gives
4.12 MPa with 3.5 mm zones). Coarse 7 mm zones keep this test short.
"""
import pytest

from comparisons import lajtai

FLOOR_COHESION = 0.05e6        # Pa: the bonds break early, the peak is friction and interlock
THESIS_UCS = 4.1               # MPa


def floor(zone_size):
    cfg = dict(lajtai.VARIANTS["quick"], seed=1, zone_size=zone_size)
    return lajtai.ucs_member(lajtai.ucs_query(cfg, FLOOR_COHESION))["peak"] / 1e6


@pytest.fixture(scope="module")
def floors():
    return {"rigid": floor(None), "deformable": floor(0.007)}


def test_rigid_blocks_interlock_above_the_thesis_ucs(floors):
    assert floors["rigid"] > THESIS_UCS


def test_deformable_blocks_bring_the_floor_below_the_thesis_ucs(floors):
    assert floors["deformable"] < 0.9 * THESIS_UCS
    assert floors["deformable"] < 0.85 * floors["rigid"]
