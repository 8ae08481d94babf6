"""benchmarks/centrifuge_resolution.py reports the contact model each run used: a scene that
names none runs the library's default (edge elements on rigid blocks), and the report must
say so (until 2026-12-02 it said end springs for Longtan, whose scene leaves the choice to
the default)."""
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
import centrifuge_resolution as cr  # noqa: E402  (benchmarks/centrifuge_resolution.py)
from dem_core.workflow.scene import build_model  # noqa: E402


@pytest.mark.parametrize("case", ["longtan", "adhikary"])
def test_the_reported_contact_model_is_the_one_the_model_runs(case):
    spec = cr.CASES[case]
    params = spec["params"](edge_length=0.012)          # coarse: only the settings matter
    model = build_model(spec["module"].scene.scene(params))
    assert cr._scene_edge_elements(case) == model.options.edge_elements


def test_a_T_study_is_drawn_against_T_and_a_block_size_study_against_the_edge():
    # (until 2026-12-02 the seeds' T study was drawn against the block edge: six points
    # stacked at 6 mm under the title "T = 0.8 MPa")
    def r(edge, t, seed=1):
        return {"edge_m": edge, "flaw_tensile_mpa": t, "seed": seed, "failure_g": 40.0}
    assert cr.across_tensile([r(0.006, 0.8), r(0.006, 1.1, 2), r(0.006, 1.4, 3)])
    assert not cr.across_tensile([r(0.008, 1.1), r(0.006, 1.1), r(0.004, 1.1)])
    series = cr._series([r(0.006, 0.8, 2), r(0.006, 1.1, 2), r(0.006, 0.8, 3)], by_seed=True)
    assert sorted(len(v) for v in series.values()) == [1, 2]
