"""Polygons (or a dem_core GeometrySpec) -> gmsh model with physical groups -> DOLFINx mesh.

Every input polygon (a region, an excavation/monitoring group, a weak band) becomes a gmsh OCC
surface; `occ.fragment` makes them conforming. Each resulting piece gets its own physical group
(one cell tag), and `MeshData.tags` maps every input name to the tags of the pieces it covers, so
a cell can belong to a region *and* to an excavation stage without duplicated cells. Groups and
bands are clipped to the union of the regions first. Monitoring points are kept by name and
evaluated by interpolation (fragmenting them into the geometry left orphan nodes in gmsh 4.8,
which crash DOLFINx 0.5.2's mesh creation).

Coordinates are metres, x horizontal, y up.

Before gmsh runs, the cell count is estimated (``estimate_cells``: the area over that of an
equilateral triangle of the element size, sqrt(3)/4 h^2, which gmsh's meshes of simple regions
match to 2 %) and the memory of meshing and solving it (``BYTES_PER_CELL``, measured with
``benchmarks/memory_per_block.py``; docs/performance.md): a mesh that would need more memory
than the machine has available, or more cells than a set limit (``max_cells``, else the
environment variable ``CONTINUUM_MAX_CELLS``), is refused with the numbers
(``check_mesh_size``) instead of aborting inside gmsh.
"""
from dataclasses import dataclass, field

import numpy as np
import shapely.geometry as sg
from shapely.ops import unary_union

__all__ = ["PolygonRegion", "WeakBand", "MeshData", "build_mesh", "mesh_from_geometry",
           "refine_near", "estimate_cells", "check_mesh_size", "BYTES_PER_CELL"]

TRIANGLE_AREA = np.sqrt(3.0) / 4.0      # of h^2: an equilateral triangle of side h
BYTES_PER_CELL = 16000                  # 13.1 kB measured with a P2 solve (docs/performance.md)
MAX_CELLS_VARIABLE = "CONTINUUM_MAX_CELLS"
_SAMPLES = 2000                         # points a size field is sampled at for the estimate


@dataclass
class PolygonRegion:
    """A named polygon: exterior [(x, y), ...] and optional holes, each a list of (x, y)."""

    name: str
    exterior: list
    holes: list = field(default_factory=list)


@dataclass
class WeakBand:
    """A joint or fault as a thin region: polyline [(x, y), ...] swept to `thickness` (m)."""

    name: str
    polyline: list
    thickness: float


@dataclass
class MeshData:
    """A DOLFINx mesh with the names of its parts.

    Attributes
    ----------
    mesh : dolfinx.mesh.Mesh
    cell_tags : dolfinx MeshTags
        One tag per conforming piece of the input polygons.
    tags : dict
        name (region, group or band) -> list of cell tags it covers.
    points : dict
        monitoring-point name -> (x, y).
    area : float
        Area of the union of the regions (shapely), m2, for checking the mesh.
    regions : list of str
        Region names in input order (material assignment follows this order, then bands).
    """

    mesh: object
    cell_tags: object
    tags: dict
    points: dict
    area: float
    regions: list
    bands: list

    def cells(self, name):
        """Local cell indices covered by `name`."""
        if name not in self.tags:
            raise KeyError(f"no region, group or band named {name!r}; known: {sorted(self.tags)}")
        mask = np.isin(self.cell_tags.values, self.tags[name])
        return np.asarray(self.cell_tags.indices[mask], dtype=np.int32)

    def mesh_area(self):
        """Sum of the cell areas of the mesh (assembled), m2."""
        import ufl
        from dolfinx import fem

        from continuum_ref._dolfinx05 import compile_form
        one = fem.Constant(self.mesh, 1.0)
        local = fem.assemble_scalar(compile_form(one * ufl.dx(domain=self.mesh)))
        return self.mesh.comm.allreduce(local)


def refine_near(points, h_min, h_max, d_min, d_max):
    """Size callback: h_min within d_min of any of `points` (n, 2), rising linearly to h_max at
    d_max. Returns a function (x, y) -> h to pass as `size_field`."""
    pts = np.asarray(points, dtype=float).reshape(-1, 2)
    if not (0 < h_min <= h_max and 0 <= d_min < d_max):
        raise ValueError(f"refine_near needs 0 < h_min <= h_max and 0 <= d_min < d_max, got "
                         f"h_min={h_min}, h_max={h_max}, d_min={d_min}, d_max={d_max}")

    def size(x, y):
        d = np.sqrt(np.min((pts[:, 0] - x) ** 2 + (pts[:, 1] - y) ** 2))
        t = np.clip((d - d_min) / (d_max - d_min), 0.0, 1.0)
        return h_min + t * (h_max - h_min)
    return size


def estimate_cells(solid, h, size_field=None) -> float:
    """The number of triangles gmsh makes of the shapely (Multi)Polygon ``solid`` at element
    size ``h`` (m): the integral of dA / (TRIANGLE_AREA min(h, size_field)^2), the size field
    sampled at up to ``_SAMPLES`` points of a grid over the solid."""
    if size_field is None:
        return solid.area / (TRIANGLE_AREA * h * h)
    import shapely
    x0, y0, x1, y1 = solid.bounds
    step = np.sqrt(solid.area / _SAMPLES)
    gx, gy = np.meshgrid(np.arange(x0 + step / 2, x1, step), np.arange(y0 + step / 2, y1, step))
    pts = np.column_stack([gx.ravel(), gy.ravel()])
    pts = pts[shapely.contains_xy(solid, pts[:, 0], pts[:, 1])]
    if not len(pts):
        return solid.area / (TRIANGLE_AREA * h * h)
    size = np.array([min(h, float(size_field(x, y))) for x, y in pts])
    return solid.area * float(np.mean(1.0 / (TRIANGLE_AREA * size ** 2)))


def check_mesh_size(solid, h, size_field=None, max_cells=None, available=None) -> float:
    """The estimated cell count (``estimate_cells``); ValueError with the numbers when it is
    above the limit: ``max_cells`` (else ``CONTINUUM_MAX_CELLS``) or the ``available`` memory
    (bytes; default ``dem_core.geometry.budget.available_memory()``) over ``BYTES_PER_CELL``."""
    from dem_core.geometry.budget import available_memory, limit_from

    cells = estimate_cells(solid, h, size_field)
    limit, why = limit_from(max_cells, MAX_CELLS_VARIABLE,
                            available_memory() if available is None else available,
                            BYTES_PER_CELL)
    if cells > limit:
        raise ValueError(f"continuum mesh: about {cells:.3g} cells (area {solid.area:.3g} m^2 "
                         f"at h = {h:g} m{', with the size field' if size_field else ''}) "
                         f"would need about {cells * BYTES_PER_CELL / 1e9:.3g} GB, more than "
                         f"{why}, which allow {limit:.3g} cells; an element size of at least "
                         f"{h * np.sqrt(cells / limit):.2g} m would fit")
    return cells


def _polygon(name, exterior, holes):
    poly = sg.Polygon(exterior, holes)
    if not poly.is_valid or poly.area <= 0.0:
        raise ValueError(f"polygon {name!r} is invalid (self-intersecting or zero area)")
    return sg.polygon.orient(poly)


def _as_polygon(name, obj):
    """Accept a shapely Polygon, an object with .exterior/.holes, (exterior, holes) or exterior."""
    if isinstance(obj, sg.Polygon):
        return _polygon(name, list(obj.exterior.coords), [list(r.coords) for r in obj.interiors])
    if hasattr(obj, "exterior"):
        return _polygon(name, list(obj.exterior), list(getattr(obj, "holes", None) or []))
    if len(obj) == 2 and np.ndim(obj[0]) == 2:
        return _polygon(name, obj[0], obj[1])
    return _polygon(name, obj, [])


def _tag_pieces(gmsh, polys):
    """One physical group per meshed piece inside a region; name -> tags of its pieces.

    Ownership is decided geometrically from the centroid of one triangle of each piece (gmsh
    4.8's fragment map does not list shared pieces reliably). Pieces outside every region get
    no physical group, so DOLFINx does not read them.
    """
    name_tags = {name: [] for name, _, _ in polys}
    tag = 0
    for _, surface in gmsh.model.getEntities(2):
        _, _, node_tags = gmsh.model.mesh.getElements(2, surface)
        if not len(node_tags) or not len(node_tags[0]):
            continue
        xyz = np.array([gmsh.model.mesh.getNode(n)[0] for n in node_tags[0][:3]])
        centre = sg.Point(xyz[:, :2].mean(axis=0))
        owners = [(name, kind) for name, kind, poly in polys if poly.contains(centre)]
        if not any(kind == "region" for _, kind in owners):
            continue
        tag += 1
        gmsh.model.addPhysicalGroup(2, [surface], tag)
        gmsh.model.setPhysicalName(2, tag, "+".join(name for name, _ in owners))
        for name, _ in owners:
            name_tags[name].append(tag)
    return name_tags


def _add_ring(occ, coords):
    coords = list(coords)[:-1] if tuple(coords[0]) == tuple(coords[-1]) else list(coords)
    pts = [occ.addPoint(float(x), float(y), 0.0) for x, y in coords]
    lines = [occ.addLine(pts[i], pts[(i + 1) % len(pts)]) for i in range(len(pts))]
    return occ.addCurveLoop(lines)


def _add_surface(occ, poly):
    """OCC plane surfaces for a shapely (Multi)Polygon; returns their tags."""
    parts = poly.geoms if hasattr(poly, "geoms") else [poly]
    tags = []
    for part in parts:
        outer = occ.addPlaneSurface([_add_ring(occ, part.exterior.coords)])
        holes = [(2, occ.addPlaneSurface([_add_ring(occ, r.coords)])) for r in part.interiors]
        if holes:   # boolean cut: faces built with inner loops broke later fragments (gmsh 4.8)
            out, _ = occ.cut([(2, outer)], holes)
            tags += [tag for dim, tag in out if dim == 2]
        else:
            tags.append(outer)
    return tags


def build_mesh(regions, h, size_field=None, groups=None, weak_bands=(), points=None,
               order=1, quiet=True, max_cells=None):
    """Mesh named polygons with gmsh and read them into DOLFINx.

    Parameters
    ----------
    regions : list of PolygonRegion (or objects with .name, .exterior, .holes)
        The solid; regions may touch but should not overlap.
    h : float
        Largest element size (m).
    size_field : callable (x, y) -> size, optional
        Local element size (m); the smaller of it and h is used. See `refine_near`.
    groups : dict name -> polygon (exterior list, or (exterior, holes)), optional
        Named parts used for staged excavation or output; they split the regions they cross.
    weak_bands : list of WeakBand
        Joints/faults as thin regions (clipped to the regions).
    points : dict name -> (x, y), optional
        Monitoring points (checked to lie inside the regions).
    order : int
        Geometric order of the gmsh elements (1: straight triangles, area exact).
    max_cells : int, optional
        Refuse a mesh estimated at more cells (default: ``CONTINUUM_MAX_CELLS``, if set); one
        that would need more memory than the machine has available is always refused
        (``check_mesh_size``, before gmsh runs).

    Notes
    -----
    Runs its own gmsh session (initialize ... finalize): do not call it while holding one.

    Returns
    -------
    MeshData
    """
    import gmsh

    from . import _dolfinx05 as dx
    if not (np.isfinite(h) and h > 0):
        raise ValueError(f"h={h!r} must be a positive element size")
    polys = [(r.name, "region", _polygon(r.name, r.exterior, list(getattr(r, "holes", []))))
             for r in regions]
    if not polys:
        raise ValueError("no regions given")
    solid = unary_union([p for _, _, p in polys])
    check_mesh_size(solid, h, size_field, max_cells)
    for name, poly in (groups or {}).items():
        clipped = _as_polygon(name, poly).intersection(solid)
        if clipped.area <= 0.0:
            raise ValueError(f"group {name!r} does not overlap any region")
        polys.append((name, "group", clipped))
    for band in weak_bands:
        if not band.thickness > 0:
            raise ValueError(f"weak band {band.name!r} thickness={band.thickness!r} must be > 0")
        strip = sg.LineString(band.polyline).buffer(band.thickness / 2, cap_style=2, join_style=2)
        strip = strip.intersection(solid)
        if strip.area <= 0.0:
            raise ValueError(f"weak band {band.name!r} does not cross any region")
        polys.append((band.name, "band", strip))
    points = dict(points or {})
    for name, xy in points.items():
        if not solid.buffer(1e-9 * np.sqrt(solid.area)).contains(sg.Point(xy)):
            raise ValueError(f"monitoring point {name!r} at {xy} is outside the regions")

    # gmsh 4.8 cannot tell whether it is initialised: this function owns one whole session.
    gmsh.initialize()
    try:
        gmsh.option.setNumber("General.Terminal", 0 if quiet else 1)
        gmsh.model.add("continuum_ref")
        occ = gmsh.model.occ
        objects = [(2, t) for _, _, poly in polys for t in _add_surface(occ, poly)]
        if len(objects) > 1:
            occ.fragment(objects[:1], objects[1:])
        occ.synchronize()
        gmsh.option.setNumber("Mesh.MeshSizeMax", float(h))
        if size_field is not None:
            gmsh.model.mesh.setSizeCallback(lambda dim, tag, x, y, z: min(h, size_field(x, y)))
        gmsh.model.mesh.generate(2)
        name_tags = _tag_pieces(gmsh, polys)
        if order > 1:
            gmsh.model.mesh.setOrder(order)
        mesh, cell_tags, _ = dx.model_to_mesh(gmsh.model, gdim=2)
    finally:
        gmsh.finalize()
    data = MeshData(mesh=mesh, cell_tags=cell_tags, tags=name_tags, points=points,
                    area=float(solid.area), regions=[r.name for r in regions],
                    bands=[b.name for b in weak_bands])
    meshed = data.mesh_area()
    if abs(meshed - data.area) > 1e-6 * data.area:
        raise RuntimeError(f"meshed area {meshed} differs from the polygon area {data.area}: "
                           "overlapping pieces were not fragmented")
    return data


def mesh_from_geometry(spec, h, size_field=None, weak_bands=(), points=None, max_cells=None):
    """Mesh a dem_core GeometrySpec (duck-typed) with the same regions and groups.

    Reads `spec.regions` (each with .name, .exterior, .holes and optionally .groups, names that
    all of the region's cells belong to) and `spec.groups` (dict name -> polygon). Joint sets
    are not meshed: the continuum smears them
    into the rock-mass properties; pass `weak_bands` for faults that should be explicit.
    """
    regions = []
    for r in spec.regions:
        holes = [[tuple(p) for p in hole] for hole in (getattr(r, "holes", None) or [])]
        regions.append(PolygonRegion(r.name, [tuple(p) for p in r.exterior], holes))
    groups = dict(getattr(spec, "groups", None) or {})
    data = build_mesh(regions, h, size_field=size_field, groups=groups, weak_bands=weak_bands,
                      points=points, max_cells=max_cells)
    for r in spec.regions:                 # Region.groups: names all its cells belong to
        for g in getattr(r, "groups", None) or ():
            data.tags.setdefault(g, [])
            data.tags[g] = sorted(set(data.tags[g]) | set(data.tags[r.name]))
    return data
