"""What happens to a model: scenes, stages, settings and searches.

Holds: ``scene`` (a model as data, JSON), ``stages`` (stage records and ``run_stages``),
``settings`` (``SolveSettings``: one record of solve settings with one set of defaults),
``limit`` (the one search for the load at which a model fails), ``gravity_ramp`` (centrifuge
g-ramps), ``strength`` (factor of safety, strength schedules), ``insitu`` (in-situ stress),
``water`` (water tables), ``loading`` (servo and displacement-controlled loading paths),
``response`` (the verdict over the response time), ``scene_schema`` and ``scene_reference``
(the scene file's JSON Schema and its reference page, generated from the records),
``plausibility`` (a scene's unusual values, warned when a file is read).

May import: the driver (``dem_core.model``), ``dem_core.geometry``, ``dem_core.contact``
(materials), ``dem_core.components`` (support records), ``dem_core.output``. Nothing below
the workflow imports it (``continuum_ref`` reads ``water`` and ``insitu`` fields).
"""
