"""Geometry of the damage model: regions, joints, Voronoi flaws -> a BlockSystem.

See docs/geometry.md for the model, parameters and conventions.
"""
from .build import build_block_system
from .joints import JointLine, JointSet
from .plot import plot_block_system
from .profiles import bench_profile, near_face_regions, slope_profile, zone_polygon_along_face
from .regions import Region, rectangle
from .stats import block_statistics
from .spec import GeometrySpec, Voronoi, ZoneSizeField

__all__ = ["Region", "rectangle", "JointSet", "JointLine", "Voronoi", "ZoneSizeField",
           "GeometrySpec", "build_block_system", "plot_block_system",
           "block_statistics", "slope_profile", "bench_profile", "zone_polygon_along_face",
           "near_face_regions"]
