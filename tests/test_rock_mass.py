"""A continuum rock mass from a scene's own joints, flaws and blocks
(``continuum_ref.rock_mass``): Goodman's series compliance, the weakest set's strength (lower
bound) or the flaws' (upper bound), and the scene file's ``dem_rock_mass`` entry."""
import math

import pytest

from continuum_ref.rock_mass import dem_rock_mass, rock_stiffness, weakest_joint_set
from dem_core.contact.elastic import lattice_moduli, spacing_from_area
from dem_core.contact.materials import Material
from dem_core.geometry import GeometrySpec, JointSet, Voronoi
from dem_core.geometry.regions import rectangle
from dem_core.workflow.scene import Boundary, Scene

E_BLOCK, NU = 20e9, 0.25
BED = Material(kn=2e9, ks=1e9, cohesion=20e3, friction=35.0, tensile_strength=0.0)
CROSS = Material(kn=5e9, ks=2e9, cohesion=0.0, friction=30.0)
FLAW = Material(kn=4e11, ks=2e11, cohesion=2e6, friction=45.0, tensile_strength=1e6)


def scene(joint_sets, voronoi=None, block_E=E_BLOCK, continuum=None):
    geo = GeometrySpec([rectangle("rock", 0, 0, 40, 20)], joint_sets=joint_sets,
                       voronoi=voronoi or {})
    return Scene(geo, {"joint:bed": BED, "joint:cross": CROSS, "flaw:*": FLAW},
                 density=2600.0, block_E=block_E, block_nu=NU,
                 groups={"base": {"touching": "bottom"}}, boundaries=[Boundary("base")],
                 continuum=continuum, name="rock-mass")


def test_one_persistent_set_in_series_with_the_blocks_is_goodmans_modulus():
    s = scene([JointSet("bed", 40.0, 5.0)])
    E, nu = rock_stiffness(s, "rock")
    assert E == pytest.approx(1.0 / (1.0 / E_BLOCK + 1.0 / (BED.kn * 5.0)), rel=1e-12)
    G_m = 1.0 / (2.0 * (1.0 + NU) / E_BLOCK + 1.0 / (BED.ks * 5.0))
    assert nu == pytest.approx(min(max(E / (2.0 * G_m) - 1.0, 0.0), 0.49), rel=1e-12)


def test_half_persistent_joints_add_half_their_compliance():
    full = rock_stiffness(scene([JointSet("bed", 40.0, 5.0)]), "rock")[0]
    half = rock_stiffness(scene([JointSet("bed", 40.0, 5.0, persistence=0.5,
                                          trace_length=4.0)]), "rock")[0]
    assert 1.0 / half - 1.0 / E_BLOCK == pytest.approx(0.5 * (1.0 / full - 1.0 / E_BLOCK))


def test_voronoi_flaws_give_the_lattices_modulus_in_series_with_deformable_blocks():
    s = scene([], voronoi={"rock": Voronoi(0.5)})
    lat = lattice_moduli(FLAW.kn, FLAW.ks, spacing_from_area(1.5 * math.sqrt(3) * 0.25))
    assert rock_stiffness(s, "rock")[0] == pytest.approx(
        1.0 / (1.0 / lat["E"] + 1.0 / E_BLOCK), rel=1e-12)


def test_the_joint_bound_is_the_weakest_set_and_the_intact_bound_the_flaws():
    s = scene([JointSet("bed", 40.0, 5.0), JointSet("cross", 70.0, 8.0,
                                                    dip_direction="left")])
    sigma = 2600.0 * 9.81 * 20.0 / 2.0
    bed = BED.cohesion + sigma * math.tan(math.radians(35.0))       # 201 kPa
    cross = sigma * math.tan(math.radians(30.0))                     # 147 kPa
    assert cross < bed and weakest_joint_set(s, "rock").name == "cross"
    low = dem_rock_mass(s, "rock", "joints")
    assert (low.cohesion, low.friction, low.dilation) == (1.0, 30.0, 0.0)   # no c: 1 Pa
    high = dem_rock_mass(s, "rock", "intact", dilation=10.0)
    assert (high.cohesion, high.friction, high.tensile_strength, high.dilation) == (
        2e6, 45.0, 1e6, 10.0)
    assert low.E == high.E == rock_stiffness(s, "rock")[0]


def test_bad_requests_name_what_is_wrong():
    with pytest.raises(ValueError, match="no joint set cuts it"):
        dem_rock_mass(scene([]), "rock", "joints")
    with pytest.raises(ValueError, match="bound must be one of"):
        dem_rock_mass(scene([JointSet("bed", 40.0, 5.0)]), "rock", "lower")
    with pytest.raises(ValueError, match="'granite' is not in the scene"):
        dem_rock_mass(scene([JointSet("bed", 40.0, 5.0)]), "granite", "joints")
    with pytest.raises(ValueError, match="set block_E"):
        rock_stiffness(scene([], block_E=None), "rock")


def test_a_scene_file_asks_for_it_by_kind_and_bound(tmp_path):
    from continuum_ref.scene_run import region_materials

    s = scene([JointSet("bed", 40.0, 5.0)],
              continuum={"h": 2.0, "materials": {"rock": {"kind": "dem_rock_mass",
                                                          "bound": "joints"}}})
    path = tmp_path / "s.json"
    s.save(path)
    loaded = Scene.load(path)
    mats, fos = region_materials(loaded, loaded.continuum["materials"])
    assert mats["rock"] == fos["rock"] == dem_rock_mass(s, "rock", "joints")
    bad = {"h": 2.0, "materials": {"rock": {"kind": "dem_rock_mass", "bound": "upper"}}}
    with pytest.raises(ValueError, match="bound must be one of"):
        scene([JointSet("bed", 40.0, 5.0)], continuum=bad)
