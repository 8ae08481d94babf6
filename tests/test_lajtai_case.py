"""The lajtai case, quick variant (thesis ch. 3): one run shared by the tests of this module.

The qualitative results asked of the case: a non-linear envelope, strength non-increasing
with persistence k, k = 1 on the 30 degree friction line (within 10 %), T = 1.0 MPa above
T = 0.5 MPa, and the calibration reaching its target UCS (within 5 %).

k = 1 used to lock (a vertex of the lower half at a corner of the upper half was given the
upper block's free end face, a spring across the joint; fixed in dem_core.contact.detection by the
support rule). The calibration reaches 4.1 MPa only near c = 0: the UCS of our Voronoi
specimen at the thesis's c = 1.2 MPa is about 6.2 MPa (docs/comparisons.md, "## lajtai").

Regression guard: the k = 0 and k = 1 envelope points and the UCS at c = 1.2 MPa must stay the
numbers stored in tests/case_reference.json (benchmarks/case_reference.py) within 10 %.
"""
import json
import math
from pathlib import Path

import numpy as np
import pytest

from comparisons import lajtai
from comparisons.progress import Progress
from comparisons.results import write_results

REFERENCE = json.loads((Path(__file__).parent / "case_reference.json").read_text())


@pytest.fixture(scope="module")
def quick():
    return lajtai.run("quick", seed=1, progress=Progress("lajtai", quiet=True))


def env(result, study):
    e = np.array(result.methods["dem"]["envelopes"][study])
    return e[:, 0], e[:, 1]


def test_summary_holds_the_required_fields(quick, tmp_path):
    dem = quick.methods["dem"]
    for key in ("ucs_mpa", "calibrated_cohesion_mpa", "envelopes", "runtime_s"):
        assert key in dem
    for study in ("lajtai_open", "lajtai_closed", "persistence_k0", "persistence_k0.5",
                  "persistence_k1", "tensile_T0.5", "tensile_T1"):
        pairs = dem["envelopes"][study]
        assert len(pairs) == 3 and all(len(p) == 2 and p[1] > 0 for p in pairs)
    assert all(m["runtime_s"] > 0 for m in quick.methods.values())
    assert {"ucs_mpa", "calibrated_cohesion_mpa", "k1_over_friction_line"} <= set(quick.errors)
    folder = write_results(quick, tmp_path)
    summary = json.loads((folder / "summary.json").read_text())
    assert summary["case"] == "lajtai" and summary["variant"] == "quick"
    assert (folder / "report.md").exists() and (folder / "envelopes.png").exists()


def test_loading_rate_is_quasi_static(quick):
    assert quick.methods["dem"]["ucs_rate_check"]["rel_change"] < 0.05


def test_envelope_is_non_linear(quick):
    """Intact rock (k = 0): the slope of the envelope falls as the normal stress rises.
    (Measured: 0.88 then 0.80 since the split-face fix of the contact search, 0.91 then 0.73
    before it; a straight Coulomb line would give equal slopes.)"""
    sn, tau = env(quick, "persistence_k0")
    slopes = np.diff(tau) / np.diff(sn)
    assert slopes[0] > 1.05 * slopes[-1]


def test_higher_flaw_tensile_strength_gives_a_higher_envelope(quick):
    """Higher where tension governs (lowest normal stress) by more than 3 %; elsewhere not
    lower by more than the scatter between two specimens (at high normal stress both
    envelopes approach the frictional part, and which bond breaks first then decides).
    Measured at 0.3 / 1.2 / 2.4 MPa: T = 1 over T = 0.5 is 1.10 / 0.968 / 0.997 with the
    interfaces divided (the default since 2026-12-02; seed 2: 0.992 at 1.2 MPa), 1.04 at
    0.3 MPa with lengths as made; the two seeds' intact points at 1.2 MPa differ by 5-7 %
    (docs/mechanics.md, "Contact lengths after sliding"), hence 5 %."""
    _, lo = env(quick, "tensile_T0.5")
    _, hi = env(quick, "tensile_T1")
    assert hi[0] > 1.03 * lo[0]
    assert np.all(hi >= 0.95 * lo)


def test_strength_does_not_increase_with_persistence(quick):
    taus = [env(quick, f"persistence_k{k:g}")[1] for k in (0.0, 0.5, 1.0)]
    for a, b in zip(taus, taus[1:]):
        assert np.all(b <= 1.02 * a)


def test_full_persistence_is_on_the_friction_line(quick):
    sn, tau = env(quick, "persistence_k1")
    assert tau == pytest.approx(sn * math.tan(math.radians(30)), rel=0.10)


@pytest.mark.xfail(strict=True, reason=(
    "the UCS has a floor above the thesis's 4.1 MPa: a broken Voronoi specimen interlocks by "
    "friction (docs/comparisons.md, lajtai, problem 2): 4.41-4.42 MPa at c = 0.024-0.11 MPa "
    "with the incremental law at the quasi-static rate 1.5e-7 m/step (2026-11-24; 4.39 MPa "
    "before it; at the faster 2e-7 one version of it reached 4.17 MPa, but that rate is not "
    "quasi-static: the peak moved 5.4 % at half of it). With deformable blocks (the case's "
    "zone_size setting) the calibration converges: c = 0.75 / 1.01 MPa at 3.5 / 1.75 mm zones "
    "(benchmarks/trials/deformable_ucs.py --calibrate; tests/test_lajtai_deformable.py). On "
    "edge elements (the setting edge_elements=true) the calibration stops at 4.09 MPa at c = "
    "0.30 MPa, where the peak is not quasi-static (43 % lower at half the rate; docs/cases/"
    "lajtai.md, 'The UCS floor on edge elements'). The full variant (peak read to 3 % strain) "
    "reaches 4.15 MPa at c = 0.198 MPa, six times below the thesis's 1.2 MPa, where it gives "
    "6.21 MPa, and with seed 2 does not converge (floor 5.7-6.5 MPa; 2026-12-02): the "
    "thesis's calibration is not reproduced there either"))
def test_calibration_reaches_the_thesis_ucs(quick):
    assert quick.methods["dem"]["calibration_converged"]
    assert quick.methods["dem"]["ucs_mpa"] == pytest.approx(4.1, rel=0.05)
    # at the thesis's cohesion (Table 3.1: c about 1.2 MPa), not at any c that gives 4.1 MPa
    assert quick.methods["dem"]["calibrated_cohesion_mpa"] == pytest.approx(1.2, rel=0.25)


def test_continuum_ucs_and_envelope(quick):
    if "continuum" not in quick.methods:
        pytest.skip("DOLFINx not available")
    c = quick.methods["continuum"]
    # Mohr-Coulomb UCS = 2 c cos(phi) / (1 - sin(phi)) = 4.1 MPa by construction of c
    assert c["ucs_mpa"] == pytest.approx(4.1, rel=0.03)
    tau = np.array(c["envelope"])[:, 1]
    assert np.all(np.diff(tau) > 0)


def test_envelope_points_match_the_regression_reference(quick):
    ref = REFERENCE["lajtai_quick"]
    dem = quick.methods["dem"]
    measured = {f"{study} sn {sn:g}": tau for study in ("persistence_k0", "persistence_k1")
                for sn, tau in dem["envelopes"][study]}
    measured["ucs_at_thesis_cohesion"] = dem["ucs_at_thesis_cohesion_mpa"]
    assert set(measured) == set(ref["mpa"])
    for name, value in ref["mpa"].items():
        assert measured[name] == pytest.approx(value, rel=ref["rel_tolerance"]), name
