"""The adhikary case end to end on a tiny variant (the quick one takes minutes): the summary
holds what the issue asks for, every method reports its run time, and the files are written.
The physics of the quick variant is reported in docs/comparisons.md."""
import json

import pytest

from comparisons import adhikary
from comparisons.results import write_results

TINY = dict(edge_length=0.008, relax_iterations=2, g_levels=[40, 60], max_steps=1500,
            refine_to=None, tensile=[1.1e6], frictions=[25.0], bedding_cohesion=[],
            conventional=True, continuum=False, continuum_h=0.02, workers=1, threads=2)


@pytest.fixture(scope="module")
def tiny_result():
    return adhikary.run(TINY, seed=3)          # a custom variant: settings, not a name


def test_summary_fields_and_files(tiny_result, tmp_path):
    r = tiny_result
    dem = r.methods["dem"]
    assert [t for t, _ in dem["failure_g"]] == [1.1]
    assert all(g is None or g in TINY["g_levels"] for _, g in dem["failure_g"])
    assert dem["friction_study"][0][0] == 25.0
    assert "rupture" in dem and dem["runtime_s"] > 0
    assert r.methods["conventional"]["runtime_s"] > 0
    folder = write_results(r, tmp_path)
    summary = json.loads((folder / "summary.json").read_text())
    for key in ("case", "variant", "seed", "methods", "reference", "errors", "versions"):
        assert key in summary
    assert summary["reference"]["experiment_failure_g"] == [80.0, 85.0]
    assert (folder / "report.md").exists() and (folder / "failure_g_vs_tensile.png").exists()
    assert (folder / "displacement_T1.1.csv").read_text().startswith("g_level,ux_A_m,ux_B_m")


def test_unknown_variant_is_refused():
    with pytest.raises(ValueError, match="variant"):
        adhikary.run("medium")
    with pytest.raises(ValueError, match="max_step"):
        adhikary.run({**TINY, "max_step": 10})        # a misspelled setting is named
