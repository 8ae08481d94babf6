"""Results at a glance of a scene run (``comparisons.scene_figures``, ``run-scene``): a picture
per stage drawn at that stage's end, a search's plot holding exactly its record's levels and
displacements, the monitoring points' history, a report that links exactly the pictures there
are, and the ParaView series (one file per stage end, the integer codes named in the files)."""
import math
import re
import xml.etree.ElementTree as ET

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import meshio  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

from comparisons.run_scene import run_scene, verdict_line  # noqa: E402
from comparisons.scene_figures import (history_figure, search_figure,  # noqa: E402
                                       stage_figure)
from dem_core.contact.materials import Material  # noqa: E402
from dem_core.geometry import GeometrySpec  # noqa: E402
from dem_core.geometry.regions import rectangle  # noqa: E402
from dem_core.workflow.gravity_ramp import RampRecord  # noqa: E402
from dem_core.workflow.limit import LimitRecord  # noqa: E402
from dem_core.workflow.scene import Boundary, Scene, build_model  # noqa: E402
from dem_core.workflow.stages import (FactorOfSafety, Gravity, Solve,  # noqa: E402
                                      WaterTable, run_stages)

TILT, PHI, WATER = 20.0, 30.0, 1.2          # deg, deg, m: the table 0.2 m above the sliding plane

# the table floods the base's top: a reservoir, meant here
pytestmark = pytest.mark.filterwarnings("ignore:stage 2 \\(water\\)")


def wet_tilted_block():
    """A block on a base under gravity tilted TILT degrees, friction PHI, a water table above
    the plane they share, then its factor of safety (below tan 30 / tan 20 = 1.586: the
    water lifts the block)."""
    th = math.radians(TILT)
    geo = GeometrySpec([rectangle("base", 0, 0, 4, 1), rectangle("block", 1, 1, 2, 1.5)])
    stages = [Gravity(1.0, direction=(math.sin(th), -math.cos(th))),
              Solve(ratio=1e-6, max_steps=20_000), WaterTable(WATER),
              FactorOfSafety(("*",), f_levels=(1.0, 1.25, 1.5, 2.0), refine_to=0.1,
                             failure_displacement=0.01)]
    return Scene(geo, {"*": Material(kn=1e9, ks=1e9, friction=PHI)}, density=2500.0,
                 boundaries=[Boundary("base")], points={"top": (1.5, 1.4)}, stages=stages,
                 name="wet block")


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    """The scene run from its file with --vtk: (folder, records, the model it built)."""
    tmp = tmp_path_factory.mktemp("wet")
    path = tmp / "wet.json"
    wet_tilted_block().save(path)
    folder, records, error = run_scene(path, tmp / "out", vtk=True)
    assert error is None
    return folder, records, build_model(Scene.load(path)), path


def _links(report) -> list:
    return re.findall(r"!\[[^\]]*\]\(([^)]+)\)", report)


def test_each_stage_has_its_picture_and_the_report_links_exactly_the_pictures(run):
    folder, records, _, _ = run
    assert [r.kind for r in records] == ["gravity", "solve", "water", "factor_of_safety"]
    expected = {f"stage{r.index}_{r.kind}.png" for r in records} | {
        "stage3_search.png", "blocks.png", "history.png"}
    assert {p.name for p in folder.glob("*.png")} == expected
    report = (folder / "report.md").read_text()
    assert sorted(_links(report)) == sorted(expected)
    for r in records:                   # each stage's pictures under its verdict line
        head = report.index(f"### {verdict_line(r)}")
        assert report.index(f"(stage{r.index}_{r.kind}.png)") > head


def test_a_resumed_run_links_no_picture_it_does_not_have(run, tmp_path):
    folder, records, _, path = run
    (folder / "stage1_solve.png").unlink()          # as a run by code that drew none
    again, kept, error = run_scene(path, folder.parent, resume=True)
    assert error is None and [r.steps for r in kept] == [r.steps for r in records]
    report = (again / "report.md").read_text()
    assert "stage1_solve.png" not in report
    assert all((again / name).exists() for name in _links(report))
    section = report.split(f"### {verdict_line(kept[1])}")[1].split("###")[0]
    assert "no picture: the stage was kept from an earlier run" in section


def test_the_stage_ends_are_one_series_and_the_files_name_their_codes(run):
    folder, records, model, _ = run
    pvd = ET.parse(folder / "vtk" / "wet_block.pvd").getroot()
    steps = [float(d.get("timestep")) for d in pvd.iter("DataSet")]
    assert steps == [r.index for r in records]          # one per stage end, increasing
    files = [d.get("file") for d in pvd.iter("DataSet")]
    assert all((folder / "vtk" / f).exists() for f in files)
    last = meshio.read(folder / "vtk" / files[-1])
    named = {k: int(v[0]) for k, v in last.field_data.items() if ": " in k}
    regions = {int(k.split()[1][:-1]): k.split(": ", 1)[1] for k in named
               if k.startswith("region ")}
    assert regions == dict(enumerate(model.blocks.region_names))
    materials = {int(k.split()[1][:-1]): k.split(": ", 1)[1] for k in named
                 if k.startswith("material ")}
    assert materials == dict(enumerate(model.table.names))
    assert all(int(k.split()[1][:-1]) == v for k, v in named.items())  # the name's code
    assert last.field_data["stage"][0] == records[-1].index
    # every contact's and crack's material code is one the field data names
    used = np.concatenate(last.cell_data["material"])
    assert set(used[used >= 0].tolist()) <= set(materials)
    search = ET.parse(folder / "vtk" / "stage3_search.pvd").getroot()
    levels = [meshio.read(folder / "vtk" / d.get("file")).field_data["F"][0]
              for d in search.iter("DataSet")]
    assert levels == pytest.approx(records[3].detail["search"].level)


def test_a_stage_picture_says_which_stage_verdict_and_state_it_shows():
    sc = wet_tilted_block()
    model = build_model(sc)
    records = run_stages(model, sc.stages)
    fos = records[3]
    words = verdict_line(fos).split(": ", 1)[1]
    fig = stage_figure(sc, model, fos, words)
    title = fig.axes[0].get_title().replace("\n", " ")
    assert f"end of stage 3 of 4 (factor_of_safety): {words}" in title
    assert f"state drawn: at F = {fos.detail['first_failed']:.4g}, the first failed" in title
    assert (f"bond failures so far: {fos.cracks['tension']} tension, {fos.cracks['shear']} "
            f"shear (as stages.csv)") in title
    water = [ln for ln in fig.axes[0].get_lines() if ln.get_label().startswith("water table")]
    assert len(water) == 1 and np.allclose(water[0].get_ydata(), WATER)
    plt.close(fig)
    dry = stage_figure(sc, build_model(sc), records[0])     # no water yet: no blue line
    assert not [ln for ln in dry.axes[0].get_lines() if "water" in ln.get_label()]
    plt.close(dry)

    hist = history_figure(records, ["top"], model.history.as_arrays())
    dots = next(ln for ln in hist.axes[0].get_lines() if ln.get_gid() == "stage ends:top")
    assert np.allclose(dots.get_ydata(), [1e3 * math.hypot(*r.points["top"]) for r in records])
    trace = next(ln for ln in hist.axes[0].get_lines() if ln.get_gid() == "history:top")
    assert np.array_equal(trace.get_xdata(), model.history.as_arrays()["step"])
    coarse = history_figure(records, ["top"], None)        # no history: per stage
    dots = next(ln for ln in coarse.axes[0].get_lines() if ln.get_gid() == "stage ends:top")
    assert list(dots.get_xdata()) == [0, 1, 2, 3]
    assert "at the end of each stage" in coarse.axes[0].get_title()
    plt.close("all")


def _lines(ax):
    return {ln.get_gid(): ln for ln in ax.get_lines() if ln.get_gid()}


def test_the_search_plot_holds_the_records_levels_displacements_and_verdicts():
    lr = LimitRecord(
        "F", level=[1.0, 1.25, 1.5, 2.0, 1.75],
        verdict=["equilibrium", "moving", "equilibrium", "failed", "failed"], steps=[100] * 5,
        max_displacement=[1e-6, 2e-5, 1e-4, 0.3, 0.05],
        point_ux={"crest": [1e-4, 2e-4, 3e-4, 0.2, 0.04]},
        point_uy={"crest": [0.0, -1e-4, -1e-4, -0.1, -0.02]},
        failure_level=1.75, last_stable_level=1.5, refined=1)
    fig = search_figure(lr, "stage 3 (factor_of_safety)", failure_displacement=0.01)
    top, bottom = fig.axes[:2]
    order = np.argsort(lr.level)
    largest = _lines(top)["max_displacement"]
    assert np.allclose(largest.get_xdata(), np.array(lr.level)[order])
    assert np.allclose(largest.get_ydata(), 1e3 * np.array(lr.max_displacement)[order])
    for v in ("equilibrium", "moving", "failed"):       # each level's marker by its verdict
        k = [i for i, w in enumerate(lr.verdict) if w == v]
        assert sorted(_lines(top)[f"verdict:{v}"].get_xdata()) == sorted(
            np.array(lr.level)[k])
    crest = _lines(bottom)["point:crest"]
    u = 1e3 * np.hypot(lr.point_ux["crest"], lr.point_uy["crest"])
    assert np.allclose(crest.get_ydata(), u[order])
    assert top.get_yscale() == "log"                    # 1e-3 to 300 mm
    labels = top.get_legend_handles_labels()[1]
    assert "last stable: F = 1.5" in labels and "first failed: F = 1.75" in labels
    assert "failure displacement 10 mm" in labels
    assert "strength-reduction factor F" in bottom.get_xlabel()
    assert top.get_title().startswith("stage 3 (factor_of_safety)")
    plt.close(fig)


def test_a_schedule_reads_towards_failure_and_a_ramp_plots_its_points_alone():
    lr = LimitRecord("tensile_strength", level=[4e5, 2e5, 1e5, 5e4],
                     verdict=["equilibrium", "equilibrium", "undecided", "unstable"],
                     steps=[1] * 4, max_displacement=[1e-4, 2e-4, 3e-4, None],
                     point_ux={"A": [0.0] * 4}, point_uy={"A": [0.0] * 4},
                     last_stable_level=2e5, undecided_level=1e5)
    fig = search_figure(lr)
    top = fig.axes[0]
    assert top.xaxis_inverted()                         # lowered: failure to the right
    assert list(_lines(top)["unstable"].get_xdata()) == [5e4]
    plt.close(fig)
    ramp = RampRecord(level=[40.0, 60.0, 80.0], verdict=["equilibrium", "equilibrium", "failed"],
                      point_ux={"A": [0.001, 0.002, 0.02], "B": [0.0005, 0.001, 0.01]},
                      failure_level=80.0, last_stable_level=60.0)
    fig = search_figure(ramp, "T=1.1")
    assert len(fig.axes) == 1                           # the points only
    a = _lines(fig.axes[0])["point:A"]
    assert np.allclose(a.get_ydata(), [1.0, 2.0, 20.0])
    assert "|ux|" in fig.axes[0].get_ylabel() and "g-level" in fig.axes[0].get_xlabel()
    plt.close(fig)


def test_a_scene_run_carries_the_hashes_of_its_results_and_final_state(run):
    import json

    folder = run[0]
    summary = json.loads((folder / "summary.json").read_text())
    report = (folder / "report.md").read_text()
    assert len(summary["results_hash"]) == len(summary["state_hash"]) == 16
    assert f"Results hash: `{summary['results_hash']}`, final state: " \
           f"`{summary['state_hash']}`" in report
