"""The quick ``highwood`` variant end to end (the 100 m slope at coarse resolution: three
quartzite beds with 0.5 m flaws, k = 0.5 and 3, T lowered in 0.1 MPa steps; 20-30 s on
2 cores), and the scene's checks that need no run.

Asserted where the quick resolution shows the thesis's findings: the onset of damage (the T at
which the intact quartzite first cracks) rises with the in-situ stress ratio, it starts in the
lower part of the face and spreads to the middle, the conventional model's quartzite does not
break, and the continuum's factor of safety lies between limit-analysis bounds. The thesis's
collapse (buckling at T = 0.2 MPa, T at failure rising with k) is not reproduced: strict xfail
with the measured reason.
"""
import math

import numpy as np
import pytest
from scipy.optimize import brentq

from comparisons import highwood
from comparisons.scenes import highwood as scene
from dem_core.workflow.scene import Scene


@pytest.fixture(scope="module")
def quick():
    return highwood.run("quick", seed=1)


def _by_k(method):
    return dict(zip(method["stress_ratio"], range(len(method["stress_ratio"]))))


def test_onset_of_damage_rises_with_the_stress_ratio(quick):
    """Thesis fig 5.19: the strength needed to prevent failure rises with k. Its measurable
    precursor here: the T at which the quartzite first cracks is higher at k = 3 than at
    k = 0.5 (the face's horizontal stress released at high k loads the beds in tension). A
    trend, no band: the two onset values are compared with each other, not with a number."""
    m = quick.methods["dem"]
    i = _by_k(m)
    low, high = m["onset_T_MPa"][i[0.5]], m["onset_T_MPa"][i[3.0]]
    assert low is not None and high is not None
    assert high > low


@pytest.mark.xfail(strict=True, reason=(
    "measured 2026-11-25 on end springs and again 2026-12-01 on edge elements: no collapse. "
    "Quick: the slope stands down to T = 0.05 MPa at k = 0.5 and 3 (face points move < 20 mm, "
    "everything in equilibrium); full resolution, k = 5: 5,200 (edge elements 5,800) "
    "quartzite cracks but it stands down to 0.05 MPa (B moves 36 mm). The toe's assumed "
    "dimensions do not matter (10-60 m of rock under the toe, bench 2-40 m, dip 84 or 88: "
    "all stand; benchmarks/trials/highwood_toe.py), nor do rigid blocks (deformable "
    "quartzite stands too). The planar beds lean on the limestone: pushed on it by "
    "cos(dip) of their weight, they must be deflected 1.7-5 m outwards before they can "
    "buckle (Rayleigh-Ritz; Hobbs's upheaval buckling), so they break up without buckling "
    "out; the thesis's buckles need a waviness or an unsupported toe "
    "(docs/cases/highwood.md, 'Why the beds stand')"))
def test_T_at_failure_rises_with_the_stress_ratio(quick):
    """Thesis 5.3.3: the slope buckles (k = 5 at 1.15 MPa, base run at 0.2 MPa) and T at
    failure rises with k."""
    m = quick.methods["dem"]
    i = _by_k(m)
    low, high = m["failure_T_MPa"][i[0.5]], m["failure_T_MPa"][i[3.0]]
    assert low is not None and high is not None and high > low


def test_damage_starts_in_the_lower_part_of_the_face(quick):
    """Thesis figs 5.15-5.16: buckling starts at the toe. "Lower part" = the lower third of
    the face: the first cracks' mean height above the toe level is below H / 3 at each k."""
    for f in quick.methods["dem"]["onset_fraction_of_height"]:
        assert f is not None and f < highwood.LOWER_PART


def test_damage_spreads_to_the_middle_of_the_face(quick):
    """Thesis fig 5.16/5.20: buckling extends to the middle of the slope (no significant
    fracturing at the crest). At k = 3, at the end of the schedule, cracks reach the middle
    third of the face (H/3 to 2H/3 above the toe level), and fewer cracks lie in the upper
    third than in the lower third."""
    p = scene.HighwoodParams()
    cracks = quick.curves["cracks_k3"]
    y = np.asarray(cracks.rows)[:, 1] - p.base
    h = p.slope_height
    assert np.any((y > h / 3) & (y < 2 * h / 3))
    assert np.sum(y > 2 * h / 3) < np.sum(y < h / 3)


def test_conventional_quartzite_does_not_break(quick):
    """The conventional model's flaws are glued: no intact crack, and (like the damage model
    here) no collapse."""
    m = quick.methods["conventional"]
    assert m["cracks"] == [0]
    assert m["onset_T_MPa"] == [None]


def _f_for_height(height, c, phi, gamma, h):
    """F at which a slope of critical height ``height(c_F, phi_F)`` equals h (c and tan phi
    divided by F)."""
    def g(f):
        p = math.atan(math.tan(math.radians(phi)) / f)
        return height(c / f, p) / gamma - h
    return brentq(g, 1.0, 100.0)


def test_continuum_factor_of_safety_between_limit_analysis_bounds(quick):
    """Intact-quartzite continuum (c 5 MPa, phi 30, 100 m face at 84 degrees), k = 1.
    Bounds derived from limit analysis with c and tan(phi) divided by F: lower, a vertical
    cut's lower bound H = 2 c tan(45 + phi / 2) / gamma (a steeper face is weaker: F 4.5);
    upper, Culmann's planar wedge for the 84 degree face, H = 4 c sin(b) cos(phi) / (gamma
    (1 - cos(b - phi))) (F 9.5). The continuum's last stable F lies between them."""
    p = scene.HighwoodParams()
    b = math.radians(p.face_dip)
    lower = _f_for_height(lambda c, f: 2 * c * math.tan(math.pi / 4 + f / 2),
                          p.flaw_cohesion, p.flaw_friction, scene.UNIT_WEIGHT, p.slope_height)
    upper = _f_for_height(lambda c, f: 4 * c * math.sin(b) * math.cos(f) / (1 - math.cos(b - f)),
                          p.flaw_cohesion, p.flaw_friction, scene.UNIT_WEIGHT, p.slope_height)
    f = quick.methods["continuum"]["last_stable"][0]
    assert lower < f < upper


def test_scene_round_trips_and_refuses_bad_input(tmp_path):
    p = scene.HighwoodParams(**highwood.VARIANTS["quick"]["params"])
    sc = scene.scene(p, scene.stages(p, highwood.VARIANTS["quick"]["values"]))
    sc.save(tmp_path / "highwood.json")
    back = Scene.load(tmp_path / "highwood.json")
    assert back.to_dict() == sc.to_dict()
    for bad in (dict(edge_length=-0.2), dict(face_dip=95.0), dict(quartzite_beds=()),
                dict(zone_top=200.0), dict(stress_ratio=-1.0)):
        name = next(iter(bad))
        with pytest.raises(ValueError, match=name):
            scene.HighwoodParams(**bad)
