"""Rupture-surface extraction and the centrifuge g-ramp, against geometry and a closed form."""
import math

import numpy as np
import pytest

from dem_core.contact.materials import Material
from dem_core.model import Model
from dem_core.workflow.gravity_ramp import raise_gravity
from dem_core.output.rupture import (angle_to_joint_normal, depth_from_face, find_rupture,
                                     path_at_angle)
from dem_core.geometry.simple_blocks import brick_grid


def _line_of_cracks(start, angle_deg, length, spacing, rng, noise):
    t = np.arange(0.0, length, spacing)
    d = np.array([-math.cos(math.radians(angle_deg)), math.sin(math.radians(angle_deg))])
    p = np.asarray(start) + t[:, None] * d + rng.normal(0, noise, (t.size, 2))
    return p


def test_rupture_found_and_its_angle_to_the_joint_normal():
    rng = np.random.default_rng(3)
    # a rupture from the toe (0.3, 0.05) into the slope (towards -x), rising 25 deg
    line = _line_of_cracks((0.3, 0.05), 25.0, 0.2, 0.004, rng, 0.001)
    scatter = rng.uniform([0.0, 0.25], [0.1, 0.35], (15, 2))   # isolated cracks elsewhere
    xy = np.vstack([scatter, line])
    face = ((0.3, 0.05), (0.45, 0.35))
    r = find_rupture(xy[:, 0], xy[:, 1], link_distance=0.012, face=face)
    assert r is not None and r.n_cracks == len(line)
    assert r.polyline[0, 0] > r.polyline[-1, 0]          # ordered from the face inwards
    assert r.length == pytest.approx(0.2, rel=0.1)
    # joints dipping 80 into the slope: normal rises 10 deg inwards -> 15 deg above it
    assert angle_to_joint_normal(r.direction, 80.0, "left") == pytest.approx(15.0, abs=1.0)
    assert depth_from_face(r.polyline, face) > 0.1


@pytest.mark.parametrize("dip, dip_direction, inward", [(81.0, "left", -1.0),
                                                        (70.0, "right", -1.0),
                                                        (60.0, "left", 1.0)])
def test_a_path_drawn_at_an_angle_reads_back_that_angle(dip, dip_direction, inward):
    """``path_at_angle`` is the inverse of ``angle_to_joint_normal``; for beds dipping 81 deg
    into a slope facing +x the normal rises 9 deg inwards, so 12 deg above it rises 21 deg."""
    for angle in (-10.0, 0.0, 12.0, 20.0):
        a, b = path_at_angle((0.4, 0.05), dip, angle, 0.3, inward, dip_direction)
        assert np.hypot(*(b - a)) == pytest.approx(0.3, rel=1e-12)
        assert np.sign(b[0] - a[0]) == inward
        assert angle_to_joint_normal(b - a, dip, dip_direction) == pytest.approx(angle, abs=1e-9)
    a, b = path_at_angle((0.4, 0.05), 81.0, 12.0, 1.0)
    assert math.degrees(math.atan2(b[1] - a[1], a[0] - b[0])) == pytest.approx(21.0, abs=1e-9)
    with pytest.raises(ValueError, match="inward"):
        path_at_angle((0.0, 0.0), 81.0, 12.0, 1.0, inward=0.5)


def test_no_rupture_from_scattered_cracks():
    rng = np.random.default_rng(4)
    xy = rng.uniform(0, 1, (30, 2))
    assert find_rupture(xy[:, 0], xy[:, 1], link_distance=0.01, min_cracks=5) is None
    with pytest.raises(ValueError, match="link_distance"):
        find_rupture(xy[:, 0], xy[:, 1], link_distance=0.0)


@pytest.mark.parametrize("watch", [None, ("tip",)])
def test_gravity_ramp_breaks_a_hanging_block_at_the_closed_form_g_level(watch):
    """A block hangs from a fixed block by one bonded edge of tensile strength T.

    Tension on the edge = rho h g N, so it breaks at N = T / (rho h g) (rigid blocks, the
    shear and bending are zero by symmetry).
    """
    h, w, rho, tensile = 0.1, 0.1, 2500.0, 50e3
    bs = brick_grid(1, 2, w, h)
    mat = Material(kn=1e10, ks=1e10, tensile_strength=tensile, cohesion=1e6, friction=30)
    model = Model(bs, {"flaw:*": mat}, density=rho, damping=0.8)
    model.fix("top")
    model.add_history_point("tip", (0.05, 0.0))
    n_crit = tensile / (rho * h * 9.81)                       # 20.4 g
    rec = raise_gravity(model, np.arange(2.0, 40.0, 2.0), ratio=1e-5, max_steps=4000,
                        failure_displacement=0.01, watch=watch)
    assert rec.failure_g is not None
    assert rec.last_stable_g < n_crit <= rec.failure_g
    assert rec.failure_g - rec.last_stable_g == pytest.approx(2.0)
    assert rec.verdict[-1] == "failed" and all(v == "equilibrium" for v in rec.verdict[:-1])
    # before failure the tip settles as the spring says: u = rho h g N / kn
    i = rec.g.index(rec.last_stable_g)
    assert -rec.point_uy["tip"][i] == pytest.approx(rho * h * 9.81 * rec.g[i] / 1e10, rel=0.02)


def test_gravity_ramp_bisection_brackets_the_closed_form_g_level_finely():
    """Coarse 10 g levels refined to 1.25 g bracket the hanging block's N = T / (rho h g)."""
    h, w, rho, tensile = 0.1, 0.1, 2500.0, 50e3
    mat = Material(kn=1e10, ks=1e10, tensile_strength=tensile, cohesion=1e6, friction=30)
    model = Model(brick_grid(1, 2, w, h), {"flaw:*": mat}, density=rho, damping=0.8)
    model.fix("top")
    model.add_history_point("tip", (0.05, 0.0))
    n_crit = tensile / (rho * h * 9.81)                       # 20.4 g
    rec = raise_gravity(model, [10.0, 30.0, 50.0], ratio=1e-5, max_steps=4000,
                        failure_displacement=0.01, watch=("tip",), refine_to=1.25)
    assert rec.last_stable_g < n_crit <= rec.failure_g
    assert rec.failure_g - rec.last_stable_g <= 1.25 + 1e-9
    assert rec.refined == 4 and rec.g[:2] == [10.0, 30.0]
    # the model is left in its failed state: the bond is broken
    assert model.crack_counts()["tension"] >= 1     # (both points of the bonded edge)
    with pytest.raises(ValueError, match="refine_to"):
        raise_gravity(model, [1.0], refine_to=0.0)


def test_gravity_ramp_refinement_ends_in_steps_of_refine_to():
    """A sudden 9 g step (ramp_steps=0, light damping) overshoots: the hanging block breaks at
    19 g, below its static N = T / (rho h g) = 20.4 g. Refined to 1 g, the ramp ends in 1 g steps
    from the last stable level, so it fails where the overshoot of a 1 g step (at most the step
    again) reaches N: last stable + 2 >= N >= failure g > 19."""
    h, w, rho, tensile = 0.1, 0.1, 2500.0, 50e3
    mat = Material(kn=1e10, ks=1e10, tensile_strength=tensile, cohesion=1e6, friction=30)
    n_crit = tensile / (rho * h * 9.81)

    def ramp(levels, refine_to):
        model = Model(brick_grid(1, 2, w, h), {"flaw:*": mat}, density=rho, damping=0.05)
        model.fix("top")
        model.add_history_point("tip", (0.05, 0.0))
        return raise_gravity(model, levels, ratio=1e-5, max_steps=4000, ramp_steps=0,
                             failure_displacement=0.01, watch=("tip",), refine_to=refine_to)

    coarse = ramp([10.0, 19.0, 50.0], None)
    assert coarse.failure_g == 19.0 < n_crit
    fine = ramp([10.0, 19.0, 50.0], 1.0)
    assert 19.0 < fine.failure_g <= n_crit <= fine.last_stable_g + 2.0
    assert fine.failure_g - fine.last_stable_g == pytest.approx(1.0)
    assert fine.verdict[1] == "failed" and fine.verdict[-1] == "failed"
    # the 1 g steps reach the last level without failing: no failure up to it
    capped = ramp([10.0, 19.0], 1.0)
    assert capped.failure_g is None and capped.last_stable_g == 19.0


def test_gravity_ramp_rejects_bad_levels():
    bs = brick_grid(1, 2, 0.1, 0.1)
    model = Model(bs, {"flaw:*": Material(kn=1e10, ks=1e10)}, density=2500.0)
    with pytest.raises(ValueError, match="increase"):
        raise_gravity(model, [5.0, 3.0])
    with pytest.raises(ValueError, match="g_levels"):
        raise_gravity(model, [float("nan")])
    with pytest.raises(ValueError, match="history point"):
        raise_gravity(model, [1.0], watch=("nowhere",))


def test_gravity_ramp_records_a_numerical_blow_up_and_stops_without_a_failure_g():
    """A fixed dt far above the critical step blows the model up at its first level: the ramp
    keeps what it has (verdict "unstable", the message) instead of losing the whole run, and a
    blow-up is not a slope failure."""
    bs = brick_grid(1, 2, 0.1, 0.1)
    model = Model(bs, {"flaw:*": Material(kn=1e12, ks=1e12, breakable=False)}, density=2500.0,
                  dt=1e-3)
    model.fix("top")
    model.add_history_point("tip", (0.05, 0.0))
    rec = raise_gravity(model, [1.0, 2.0], ratio=1e-4, max_steps=2000, watch=("tip",),
                        refine_to=0.5)
    assert rec.unstable is not None and "critical step" in rec.unstable
    assert rec.g == [1.0] and rec.verdict == ["unstable"] and rec.steps[0] > 0
    assert rec.failure_g is None and rec.last_stable_g is None
    from comparisons.centrifuge import unstable_notes
    runs = [{"label": "conventional", "g": rec.g, "unstable": rec.unstable},
            {"label": "T=1.1", "g": [70.0], "unstable": None}]
    notes = unstable_notes(runs)
    assert len(notes) == 1 and notes[0].startswith("conventional: ") and " 1 g" in notes[0]


def test_a_blow_up_after_the_slope_started_to_fail_counts_as_that_levels_failure(monkeypatch):
    """A hanging block whose bond breaks falls freely (its displacement grows without slowing
    down); if the model then blows up (forced here after a few checks of the level), the level
    is "failed" with the message in ``blowups``, bisection goes on from the stable copy, and
    ``unstable`` stays None. A blow-up of a model at rest stays "unstable" (the test above)."""
    from dem_core.model import ModelUnstable

    bs = brick_grid(1, 2, 0.1, 0.1)
    # the bond holds the lower block's weight (245 N/m per g over 0.1 m: 2.45 kPa per g) to 4.08 g
    model = Model(bs, {"flaw:*": Material(kn=1e10, ks=1e10, tensile_strength=1e4, cohesion=1e4,
                                          friction=30.0)}, density=2500.0, kinetic_damping=100)
    model.fix("top")
    model.add_history_point("tip", (0.05, 0.02))
    real_cycle = Model.cycle
    calls = {"n": 0}

    def cycle(self, n):
        real_cycle(self, n)
        if -self.gravity[1] > 5.5 * 9.81 and self.crack_counts()["tension"]:
            calls["n"] += 1
            if calls["n"] == 10:     # ten checks after the bond broke: the block is falling
                raise ModelUnstable("forced blow-up")

    monkeypatch.setattr(Model, "cycle", cycle)
    # no failure displacement: the level is judged by its growth (monitor.verdict)
    rec = raise_gravity(model, [2.0, 6.0], ratio=1e-4, max_steps=4000, watch=("tip",),
                        refine_to=1.0, ramp_steps=0)
    assert rec.unstable is None
    assert [g for g, _ in rec.blowups] == [6.0] and "forced" in rec.blowups[0][1]
    assert rec.verdict[:2] == ["equilibrium", "failed"] and rec.steps[1] < 1000   # ended there
    # bisection goes on from the stable 2 g: the bond (10 kPa against 2.45 kPa per g, 4.08 g
    # static) breaks between 3 and 4 g with each level applied at once
    assert rec.g[2:] == [4.0, 3.0, 4.0] and rec.verdict[2:] == ["failed", "equilibrium", "failed"]
    assert rec.last_stable_g == 3.0 and rec.failure_g == 4.0
    from comparisons.centrifuge import unstable_notes
    notes = unstable_notes([{"label": "T=1.1", "g": rec.g, "unstable": None,
                             "blowups": rec.blowups}])
    assert len(notes) == 1 and "at 6 g" in notes[0] and "counts as failed" in notes[0]
