"""ParaView output: the DEM's .vtu files read back with meshio equal the model's arrays, the
series' .pvd lists its files with their times, and the continuum's XDMF holds its fields."""
import json
import math
import xml.etree.ElementTree as ET

import meshio
import numpy as np
import pytest

from dem_core.geometry import GeometrySpec, Voronoi, build_block_system, rectangle
from dem_core.contact.materials import Material
from dem_core.model import Model
from dem_core.output.vtk import KIND_BLOCK, KIND_CONTACT, KIND_CRACK, VtkSeries, write_vtk

TOL = 1e-12


@pytest.fixture(scope="module")
def pulled_bar():
    """A 6 x 3 cm Voronoi bar between two platens, the right one pulled up and away until
    flaws break in tension (blocks of 4 to 8 vertices, cracks, rotations)."""
    spec = GeometrySpec(regions=[rectangle("rock", 0, 0, 0.06, 0.03),
                                 rectangle("left", -0.01, 0, 0, 0.03),
                                 rectangle("right", 0.06, 0, 0.07, 0.03)],
                        voronoi={"rock": Voronoi(edge_length=0.006, seed=1, relax_iterations=20)})
    m = Model(build_block_system(spec),
              {"flaw:*": Material(kn=1e12, ks=1e12, tensile_strength=1e6, cohesion=3e6,
                                  friction=35),
               "boundary:*": Material(kn=1e12, ks=1e12, breakable=False)}, density=2500)
    m.fix("left")
    m.set_velocity("right", vx=0.05, vy=0.02)
    m.set_gravity(1.0)
    m.cycle(300)
    assert m.cracks.count[0] > 0 and np.abs(m.state.theta).max() > 0
    return m


def read_back(path):
    """Points, per-cell connectivity (list) and per-cell fields of a .vtu, in file order."""
    r = meshio.read(path)
    conn = [row for block in r.cells for row in block.data]
    fields = {k: np.concatenate(v) for k, v in r.cell_data.items()}
    return r.points, conn, fields, r.point_data


def test_blocks_contacts_and_cracks_read_back_equal_the_model(pulled_bar, tmp_path):
    m = pulled_bar
    pts, conn, f, pdata = read_back(write_vtk(m, tmp_path / "bar.vtu"))
    s, p, c = m.state, m.props, m.contacts
    assert np.all(pts[:, 2] == 0.0)
    # blocks: vertices pos + R(theta) local (CCW), centroid fields
    blocks = np.flatnonzero(f["kind"] == KIND_BLOCK)
    b = f["block"][blocks]
    assert sorted(b) == list(range(m.n_blocks))
    for cell, k in zip(blocks, b):
        lv = p.local_vertices[p.vertex_offsets[k]:p.vertex_offsets[k + 1]]
        cs, sn = s.rot[k]
        world = s.pos[k] + lv @ np.array([[cs, sn], [-sn, cs]])
        assert np.abs(pts[conn[cell], :2] - world).max() < TOL
        x0 = s.pos0[k] + lv @ np.array([[math.cos(s.theta0[k]), math.sin(s.theta0[k])],
                                         [-math.sin(s.theta0[k]), math.cos(s.theta0[k])]])
        assert np.abs(pdata["vertex_displacement"][conn[cell], :2] - (world - x0)).max() < TOL
    assert np.abs(f["displacement"][blocks, :2] - m.displacement()[b]).max() < TOL
    assert np.all(f["displacement"][blocks, 2] == 0.0)
    assert np.abs(f["velocity"][blocks, :2] - s.vel[b]).max() < TOL
    assert np.array_equal(f["rotation"][blocks], (s.theta - s.theta0)[b])
    names = list(m.blocks.groups)
    assert [names[g] for g in f["group"][blocks]] == \
        [next(n for n in names if k in m.blocks.groups[n]) for k in b]
    assert np.array_equal(f["region"][blocks], m.blocks.region_id[b])
    # contacts: the segment x_a -> x_a + L t, stresses (compression +) and states
    lines = np.flatnonzero(f["kind"] == KIND_CONTACT)
    assert len(lines) == c.n
    ends = pts[np.array([conn[i] for i in lines])][:, :, :2]
    assert np.abs(ends[:, 0] - c.position(s.pos, s.rot)).max() < TOL
    assert np.abs(np.hypot(*(ends[:, 1] - ends[:, 0]).T) - c.live("length")).max() < TOL
    assert np.abs(f["sn"][lines] - c.live("sn")).max() < TOL * np.abs(c.live("sn")).max()
    assert np.array_equal(f["ts"][lines], c.live("ts"))
    assert np.array_equal(f["state"][lines], c.state())
    assert np.array_equal(f["damage"][lines], c.live("damage"))     # (0: brittle flaws)
    assert (f["state"][lines] == 2).sum() > 0                  # broken in tension
    assert np.all(np.isnan(f["sn"][blocks])) and np.all(f["state"][blocks] == -1)
    # cracks: where, when and how each bond failed
    log = m.crack_log()
    dots = np.flatnonzero(f["kind"] == KIND_CRACK)
    assert np.abs(pts[[conn[i][0] for i in dots], :2] - np.column_stack([log["x"], log["y"]])
                  ).max() < TOL
    assert np.array_equal(f["mode"][dots], log["mode"])
    assert np.array_equal(f["time"][dots], log["time"])
    assert [m.table.names[i] for i in f["material"][dots]] == log["material"]


def test_removed_blocks_are_left_out(pulled_bar, tmp_path):
    m = pulled_bar
    before = m.snapshot()
    try:
        m.remove("right")
        _, _, f, _ = read_back(write_vtk(m, tmp_path / "cut.vtu"))
    finally:
        m.restore(before)                       # the fixture stays as it was
    b = f["block"][f["kind"] == KIND_BLOCK]
    assert len(b) == m.n_blocks - len(m.group("right"))
    assert not np.isin(m.group("right"), b).any()


def test_series_writes_a_pvd_of_its_files_and_times(pulled_bar, tmp_path):
    series = VtkSeries(tmp_path / "run", name="bar")
    series.add(pulled_bar)
    series.add(pulled_bar, time=2.5)                 # e.g. a g-level as ParaView's time
    rows = ET.parse(tmp_path / "run" / "bar.pvd").getroot().find("Collection")
    got = [(float(d.get("timestep")), d.get("file")) for d in rows]
    assert got == [(pulled_bar.time, "bar_0000.vtu"), (2.5, "bar_0001.vtu")]
    assert all((tmp_path / "run" / name).exists() for _, name in got)
    legend = json.loads((tmp_path / "run" / "bar_legend.json").read_text())
    assert legend["group"] == list(pulled_bar.blocks.groups)
    with pytest.raises(ValueError, match=r"\.vtu"):
        write_vtk(pulled_bar, tmp_path / "bar.vtk")


def xdmf_fields(path):
    """{name: [array per time]} of an ASCII XDMF file, and the times."""
    root = ET.parse(path).getroot()
    out, times = {}, []
    for grid in root.iter("Grid"):
        attr = grid.find("Attribute")
        if attr is None:
            continue
        item = attr.find("DataItem")
        shape = [int(n) for n in item.get("Dimensions").split()]
        data = np.array(item.text.split(), float).reshape(shape)
        out.setdefault(attr.get("Name"), []).append(data[:, 0] if shape[1] == 1 else data)
        times.append(float(grid.find("Time").get("Value")))
    return out, sorted(set(times))


def test_continuum_xdmf_holds_displacement_stress_and_yield(tmp_path):
    pytest.importorskip("dolfinx")
    from continuum_ref.materials import MohrCoulomb
    from continuum_ref.mesh import PolygonRegion, build_mesh
    from continuum_ref.model import ContinuumModel
    from continuum_ref.vtk import FIELDS, XdmfSeries, write_xdmf

    md = build_mesh([PolygonRegion("rock", [(0, 0), (2, 0), (2, 1), (1, 1), (0, 0.5)])],
                    h=0.25)
    model = ContinuumModel(md, MohrCoulomb(E=1e7, nu=0.3, cohesion=3e3, friction=30.0),
                           2000.0)
    model.fix(lambda x: np.isclose(x[1], 0.0))
    assert model.solve_gravity(1.0).converged
    with XdmfSeries(tmp_path / "slope.xdmf", model, encoding="ascii") as series:
        series.add(model, time=0.5)
        series.add(model, time=1.0)
    f, times = xdmf_fields(tmp_path / "slope.xdmf")
    assert set(f) == set(FIELDS) and times == [0.5, 1.0]
    xy, _ = model.triangles()
    u = f["displacement"][-1]
    assert np.abs(u[:, :2] - model.displacement_at(xy)).max() < 1e-9 * np.abs(u).max()
    s = model.stress()
    tensor = f["stress"][-1]                     # xx, xy, 0, xy, yy, 0, 0, 0, 0 (padded)
    assert np.abs(tensor[:, [0, 1, 3, 4]] - s[:, [0, 3, 3, 1]]).max() < 1e-9 * np.abs(s).max()
    assert np.abs(f["stress_zz"][-1] - s[:, 2]).max() < 1e-9 * np.abs(s).max()
    ind = model.yield_indicator()
    assert np.allclose(f["yield_shear"][-1], ind["shear"], atol=1e-12)
    assert f["yield"][-1].max() >= 1                  # this weak slope yields somewhere
    # the default (HDF5) writes the light .xdmf and the .h5 beside it
    path = write_xdmf(model, tmp_path / "h5" / "slope.xdmf")
    assert path.with_suffix(".h5").stat().st_size > 0
    assert all(f'Name="{name}"' in path.read_text() for name in FIELDS)
