"""Bad geometry input raises a ValueError that names the problem, before any compute."""
import numpy as np
import pytest

from dem_core.geometry import (GeometrySpec, JointLine, JointSet, Region, Voronoi,
                               ZoneSizeField, rectangle)

R = [(0, 0), (1, 0), (1, 1), (0, 1)]


@pytest.mark.parametrize("make, match", [
    (lambda: Region("r", [(0, 0), (1, 1), (1, 0), (0, 1)]), "Self-intersection"),
    (lambda: Region("r", [(0, 0), (1, 0), (np.nan, 1)]), "finite"),
    (lambda: Region("r", [(0, 0), (1, 0)]), "at least 3"),
    (lambda: Region("r", R, holes=[[(2, 2), (3, 2), (3, 3)]]), "not a valid"),
    (lambda: Region("a|b", R), "name"),
    (lambda: JointSet("j", 45, 0.0), "spacing must be > 0"),
    (lambda: JointSet("j", 45, -1.0), "spacing must be > 0"),
    (lambda: JointSet("j", 45, 0.1, persistence=1.2), r"persistence k must be in \[0, 1\]"),
    (lambda: JointSet("j", 45, 0.1, persistence=-0.1), r"persistence k must be in \[0, 1\]"),
    (lambda: JointSet("j", 45, 0.1, persistence=0.5), "needs trace_length or bridge_length"),
    (lambda: JointSet("j", 45, 0.1, persistence=0.5, trace_length=1, bridge_length=2), "give k"),
    (lambda: JointSet("j", 120, 0.1), "dip_deg"),
    (lambda: JointSet("j", np.nan, 0.1), "finite"),
    (lambda: JointSet("j", 45, 0.1, dip_direction="up"), "dip_direction"),
    (lambda: JointSet("j", 45, 0.1, jitter=1.5), "jitter"),
    (lambda: JointLine("f", [(0, 0), (1, 1), (1, 0), (0, 1)]), "crosses itself"),
    (lambda: JointLine("f", [(0, 0)]), ">= 2"),
    (lambda: Voronoi(0.0), "edge_length"),
    (lambda: Voronoi(np.nan), "edge_length"),
    (lambda: Voronoi(0.1, relax_iterations=-1), "relax_iterations"),
    (lambda: GeometrySpec([rectangle("r", 0, 0, 1, 0.5)], voronoi={"r": Voronoi(2.0)}),
     "larger than region"),
    (lambda: GeometrySpec([rectangle("r", 0, 0, 1, 1)], voronoi={"q": Voronoi(0.1)}), "unknown region"),
    (lambda: GeometrySpec([rectangle("a", 0, 0, 1, 1), rectangle("b", 0.5, 0, 2, 1)]), "overlap"),
    (lambda: GeometrySpec([rectangle("a", 0, 0, 1, 1), rectangle("a", 1, 0, 2, 1)]), "unique"),
    (lambda: GeometrySpec([]), "at least one region"),
    (lambda: GeometrySpec([rectangle("a", 0, 0, 1, 1)], joint_sets=[JointSet("j", 10, 1, regions=["x"])]),
     "unknown region"),
    (lambda: ZoneSizeField(R, 0.0, 1.0, 1.0), "inside"),
])
def test_bad_input_raises_clear_value_error(make, match):
    with pytest.raises(ValueError, match=match):
        make()


def test_bad_size_field_values_are_caught_before_tessellating():
    from dem_core.geometry import build_block_system
    vs = Voronoi(0.1, size_field=lambda x, y: np.where(x > 0.5, -1.0, 0.1))
    with pytest.raises(ValueError, match="size_field"):
        build_block_system(GeometrySpec([rectangle("r", 0, 0, 1, 1)], voronoi={"r": vs}))


def test_plain_callable_size_field_is_not_silently_dropped_on_save():
    spec = GeometrySpec([rectangle("r", 0, 0, 1, 1)], voronoi={"r": Voronoi(0.1, size_field=lambda x, y: 0.1 + 0 * x)})
    with pytest.raises(TypeError, match="ZoneSizeField"):
        spec.to_dict()
