"""Each case's continuum column is its scene plus a "continuum" section (issue 53): the scene
the case's DEM runs, the rock mass its continuum module documents, and a stage list the
continuum can run. Checked before anything is meshed or solved (``Scene`` validates the
section, ``continuum_ref.scene_run.check_continuum_stages`` the stages); lajtai's specimens
are written by hand (comparisons/lajtai_continuum.py says why)."""
import pytest

from comparisons import (adhikary, adhikary_continuum, checkerboard, checkerboard_continuum,
                         coal_buckling, common_toppling, common_toppling_continuum, highwood,
                         highwood_continuum, longtan, longtan_continuum, lornex,
                         lornex_continuum, underdip)
from comparisons.scenes import checkerboard as checkerboard_scene
from comparisons.scenes import lornex as lornex_scene
from continuum_ref import hoek_brown as hb
from continuum_ref.scene_run import check_boundaries, check_continuum_stages, region_materials
from dem_core.workflow.scene import check_continuum
from dem_core.workflow.stages import stage_to_dict


CASES = {"adhikary": adhikary, "longtan": longtan, "checkerboard": checkerboard,
         "common_toppling": common_toppling, "highwood": highwood, "lornex": lornex,
         "underdip": underdip, "coal_buckling": coal_buckling}


def _quick(case):
    """The quick variant of a case module or name."""
    return (CASES.get(case) or case).VARIANTS["quick"]


def _adhikary():
    v = _quick(adhikary)
    return adhikary_continuum.continuum_scene(v["continuum_h"], v["g_levels"][-1])


def _longtan():
    v = _quick(longtan)
    return longtan_continuum.continuum_scene(v["continuum_h"], v["g_levels"][-1])


def _checkerboard():
    v = _quick(checkerboard)
    p = checkerboard_scene.CheckerboardParams(**dict(v["params"], ucs=v["ucs"][-1]))
    return checkerboard_continuum.continuum_scene(p, v["continuum_h"])


def _common_toppling():
    return common_toppling_continuum.continuum_scene(_quick(common_toppling)["continuum_h"])


def _highwood():
    v = _quick(highwood)
    p = highwood.scene.HighwoodParams(**dict(v["params"], stress_ratio=v["continuum_ratios"][0]))
    return highwood_continuum.continuum_scene(p, v["continuum_h"])


def _lornex():
    v = _quick(lornex)
    return lornex_continuum.continuum_scene(lornex.params_of(lornex.members(v, 1)[0]),
                                            v["continuum_h"])


def _underdip():
    return underdip.continuum_scene(_quick(underdip), 0.0)


def _coal_buckling():
    return coal_buckling.continuum_scene(_quick(coal_buckling), 0.0)


SCENES = {"adhikary": _adhikary, "longtan": _longtan, "checkerboard": _checkerboard,
          "common_toppling": _common_toppling, "highwood": _highwood, "lornex": _lornex,
          "underdip": _underdip, "coal_buckling": _coal_buckling}
STAGES = {"adhikary": ["gravity", "raise_gravity"], "longtan": ["gravity", "raise_gravity"],
          "checkerboard": ["gravity", "factor_of_safety"],
          "common_toppling": ["gravity"] + ["excavate"] * 12 + ["factor_of_safety"],
          "highwood": ["insitu", "gravity", "factor_of_safety"],
          "lornex": ["insitu", "gravity", "water"] + ["excavate"] * 15,
          "underdip": ["gravity", "factor_of_safety"],
          "coal_buckling": ["gravity", "factor_of_safety"]}


@pytest.mark.parametrize("case", sorted(SCENES))
def test_continuum_scene_validates_and_its_stages_run_in_the_continuum(case):
    sc = SCENES[case]()
    check_continuum(sc.continuum, [r.name for r in sc.geometry.regions])
    mats, fos = region_materials(sc, sc.continuum["materials"])
    check_boundaries(sc)
    check_continuum_stages(sc, fos)
    assert [stage_to_dict(s)["kind"] for s in sc.stages] == STAGES[case]
    assert sc.continuum["h"] == _quick(case)["continuum_h"]
    assert set(mats) == {r.name for r in sc.geometry.regions}


def _entry(case, region="rock"):
    return SCENES[case]().continuum["materials"][region]


@pytest.mark.parametrize("case, entry", [
    # the intact model material smeared: flaw c, friction, T; block E, nu
    ("adhikary", dict(E=2.6e9, nu=0.16, cohesion=1.6e6, friction=37.0, tensile_strength=1.1e6)),
    # Jennings, k = 0.7: c 0.474 MPa, friction 0, T 1.44 MPa; E 2 GPa, nu 0.25
    ("longtan", dict(E=2.0e9, nu=0.25, cohesion=0.474e6, friction=0.0,
                     tensile_strength=1.443e6)),
    # table 5.5's intact quartzite: c 5 MPa, friction 30, T 1.6 MPa; E 20 GPa, nu 0.25
    ("highwood", dict(E=20e9, nu=0.25, cohesion=5e6, friction=30.0, tensile_strength=1.6e6)),
])
def test_one_mohr_coulomb_rock_mass_as_documented(case, entry):
    got = _entry(case)
    assert got["kind"] == "mohr_coulomb" and got["dilation"] == 0.0
    for k, v in entry.items():
        assert got[k] == pytest.approx(v, rel=1e-3, abs=1e-9), k


def test_common_toppling_rock_mass_is_table_5_2_intact_rock_everywhere():
    mats = SCENES["common_toppling"]().continuum["materials"]
    assert mats == {"*": {"kind": "mohr_coulomb", "E": 20e9, "nu": 0.25, "cohesion": 5e6,
                          "friction": 30.0, "tensile_strength": 1e6, "dilation": 0.0}}


def test_checkerboard_units_are_hoek_brown_fits_with_the_rock_mass_cut_off():
    """Weathered units: c and friction of the DEM's flaws (the same fit), a cut-off of 9-30 kPa;
    every unit's cut-off is the Hoek-Brown tensile strength s sci / mb; dilation 0."""
    sc = SCENES["checkerboard"]()
    ucs = _quick(checkerboard)["ucs"][-1]
    for name, m in sc.continuum["materials"].items():
        unit = checkerboard_scene.unit_of(name)
        u = checkerboard_scene.UNITS[unit]
        assert m["kind"] == "mohr_coulomb" and m["dilation"] == 0.0
        assert (m["E"], m["nu"]) == (u["E"], u["nu"])
        mb, s, _ = hb.parameters(u["gsi"], u["mi"])
        sci = ucs if unit in checkerboard_scene.WEATHERED else u["sci"]
        assert m["tensile_strength"] == pytest.approx(s * sci / mb)
        if unit in checkerboard_scene.WEATHERED:
            assert 8e3 <= m["tensile_strength"] <= 30e3
            c, phi, _ = checkerboard_scene.flaw_strength(unit, ucs)
            assert (m["cohesion"], m["friction"]) == pytest.approx((c, phi))


def test_lornex_zones_are_hoek_brown_by_rmr():
    """UCS 65 MPa, a = 0.5, m and s by RMR (Table 6.1), Em = 10^((RMR - 10) / 40) GPa, nu 0.3."""
    sc = SCENES["lornex"]()
    for name, m in sc.continuum["materials"].items():
        rmr = lornex_scene.rmr_of(name)
        row = lornex_scene.RMR[rmr]
        assert m == {"kind": "hoek_brown", "E": row["E"], "nu": 0.3, "sci": 65e6,
                     "mb": row["m"], "s": row["s"], "a": 0.5}
        assert m["E"] == pytest.approx(10 ** ((rmr - 10) / 40) * 1e9, rel=0.02)


@pytest.mark.parametrize("case", ["adhikary", "longtan"])
def test_centrifuge_continuum_raises_gravity_to_the_ramps_top(case):
    """From 1 g to the DEM ramp's last level, resolution 1 g, runaway 0.02 m."""
    ramp = SCENES[case]().stages[-1]
    top = _quick(case)["g_levels"][-1]
    assert (ramp.g_levels, ramp.refine_to, ramp.failure_displacement) == ((1.0, top), 1.0,
                                                                          0.02)
