"""The search and ramp figures (``staged.history_figure``, ``centrifuge.displacement_figure``):
two runs with the same answer must both be seen."""
import matplotlib

matplotlib.use("Agg")

from comparisons.centrifuge import displacement_figure  # noqa: E402
from comparisons.staged import history_figure  # noqa: E402


def _run(label, crest=(0.18, 0.18, 0.19, 0.49)):
    levels = [7e6, 4e6, 2e6, 1e6]
    return {"label": label, "search": {
        "kind": "strength_schedule", "level": levels, "failure": 1e6,
        "point_ux": {"crest": list(crest), "toe": [0.007] * 4}}}


def test_a_run_with_the_same_curve_as_a_later_one_shows_as_a_wider_rim_beneath_it():
    fig = history_figure([_run("base"), _run("cohesion 15")], ("crest", "toe"))
    ax = fig.axes[0]
    curves = {line.get_label(): line for line in ax.get_lines()
              if not line.get_label().startswith("_")}
    assert len(curves) == 4                       # crest and toe of both runs, in the legend
    for p in ("crest", "toe"):
        first, later = curves[f"{p}, base"], curves[f"{p}, cohesion 15"]
        assert (first.get_xydata() == later.get_xydata()).all()
        assert first.get_linewidth() > later.get_linewidth() + 1.0
        assert first.get_markersize() > later.get_markersize()
        assert first.get_zorder() < later.get_zorder()
    assert ax.xaxis_inverted()                    # a schedule lowers T: read left to right


def test_a_run_with_its_own_curve_gets_no_rim():
    fig = history_figure([_run("friction 50", crest=(0.18, 0.18, 0.23, 0.33)), _run("base")],
                         ("crest",))
    widths = {line.get_label(): line.get_linewidth() for line in fig.axes[0].get_lines()}
    assert widths["crest, friction 50"] == widths["crest, base"]


def test_a_ramp_that_coincides_with_a_later_one_shows_as_a_wider_rim_beneath_it():
    ramp = {"g": [40.0, 60.0, 80.0], "ux_A": [0.0023, 0.0030, 0.0059],
            "ux_B": [0.0008, 0.0011, 0.0024]}
    runs = [dict(ramp, label="T=1.1"), dict(ramp, label="bedding c 5 kPa"),
            dict(ramp, label="T=0.8", ux_A=[0.0023, 0.0046, 0.0090])]
    widths = {line.get_label(): line.get_linewidth()
              for line in displacement_figure(runs).axes[0].get_lines()}
    assert widths["A, T=1.1"] > widths["A, bedding c 5 kPa"] == widths["A, T=0.8"]
    assert widths["B, T=1.1"] > widths["B, bedding c 5 kPa"]
    assert widths["B, T=1.1"] > widths["B, T=0.8"]      # B of T=0.8 is B of the others too
