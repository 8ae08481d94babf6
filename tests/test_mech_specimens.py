"""Bonded specimens: tension and compression bars, a cantilever under gravity.

Closed forms used:
- A regular brick bar in tension breaks when the applied stress reaches the flaw tensile
  strength T (its flaws are perpendicular to the load).
- A rigid-block lattice carries uniaxial stress s with flaw normal stress up to
  s (3 kn + ks) / (2 (kn + ks)) (``dem_core.contact.elastic``), which is s for ks = kn: a Voronoi bar
  with ks = kn breaks near T (the irregular blocks lower it a little; docs/mechanics.md).
- Euler-Bernoulli cantilever under its own weight q = rho g H: tip deflection q L^4 / (8 E I),
  I = H^3 / 12, with E the modulus measured on a bar of the same assembly.
"""
import sys
from pathlib import Path

import pytest

from dem_core.contact.elastic import lattice_moduli, spacing_from_area
from dem_core.model import Model
from dem_core.geometry.simple_blocks import brick_grid

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
from scenes import (KN, T, materials, measured_modulus, pull,  # noqa: E402
                    voronoi_bar)                # benchmarks/scenes.py


@pytest.mark.parametrize("ks_ratio", [0.5, 1.0])
def test_brick_bar_breaks_at_flaw_tensile_strength(ks_ratio):
    # end columns are the platens; the flaws between them and the bar break too (same law)
    bs = brick_grid(20, 5, 0.01, 0.01, groups={})
    m, _, stress = pull(bs, 0.18, 0.05, ks_ratio, 2e-3)
    assert stress.max() == pytest.approx(T, rel=0.02)
    assert m.crack_counts()["tension"] >= 5          # a full section opened


@pytest.fixture(scope="module")
def bar():
    return voronoi_bar(0.2, 0.05)


def test_voronoi_bar_breaks_near_flaw_tensile_strength(bar):
    m, _, stress = pull(bar, 0.2, 0.05, 1.0, 2e-3)
    peak = stress.max()
    assert peak == pytest.approx(T, rel=0.15)
    assert stress[-1] < 0.5 * peak                   # it really broke (softened)
    log = m.crack_log()
    assert (log["mode"] == 1).sum() >= 3             # by tension cracks


def test_voronoi_bar_is_linear_in_compression_and_near_lattice_modulus(bar):
    E1, E2 = measured_modulus(bar, 0.2, 0.05, 0.5)
    assert E2 == pytest.approx(E1, rel=0.03)        # linear before damage
    pred = lattice_moduli(KN, 0.5 * KN, spacing_from_area(bar.area.mean()))["E_2d"]
    # measured Voronoi departure from the regular lattice is ~10 % (docs/mechanics.md)
    assert E2 == pytest.approx(pred, rel=0.3)


def test_voronoi_cantilever_deflects_like_euler_bernoulli():
    length, height, rho, g = 0.3, 0.03, 2500.0, 9.81
    bs = voronoi_bar(length, height, edge=0.005, seed=3)
    E1, E = measured_modulus(voronoi_bar(0.15, height, edge=0.005, seed=4), 0.15, height, 1.0)
    m = Model(bs, materials(1.0), density=rho, damping=0.8)
    m.remove("right")
    m.fix("left")
    m.set_gravity(1.0)
    m.add_history_point("tip", (length, 0.5 * height))
    result = m.solve(ratio=1e-5, max_steps=80_000)
    assert result.verdict == "equilibrium", result.reason
    deflection = -m.point_motion("tip")[1]
    q = rho * g * height
    expected = q * length ** 4 / (8 * E * height ** 3 / 12)
    assert deflection == pytest.approx(expected, rel=0.15)
