"""The Mitsuba 3 reference for tests/mitsuba/area.tsd (issue "sampling"):
a rectangle `area` emitter of the same radiance (its shape given a black
BSDF, so only its light counts), a `point` emitter of intensity pi*I,
`diffuse` BSDFs of reflectance Kd*colour, the `direct` integrator, a box
pixel filter, 1024 samples per pixel. Writes area.pfm beside this script.

    venv/bin/python tests/mitsuba/area.py    (see lambert.py)
"""
from common import T, diffuse, floor, point, render_to, sensor, sphere

render_to({
    "type": "scene",
    "integrator": {"type": "direct"},
    "sensor": sensor(origin=[0, 1.2, 5], target=[0, 0.6, 0]),
    "floor": floor(diffuse(0.8, 0.8, 0.8, 0.9)),
    "a": sphere(-0.8, 0.6, 0, 0.6, diffuse(0.9, 0.3, 0.2, 0.8)),
    "b": sphere(0.9, 0.45, 0.6, 0.45, diffuse(0.2, 0.5, 0.9, 0.8)),
    # x in -1.5..0.5, z in -0.75..0.75 at y = 3, facing down (+z turned to -y).
    "light": {"type": "rectangle",
              "to_world": T().translate([-0.5, 3, 0]).rotate([1, 0, 0], 90).scale([1, 0.75, 1]),
              "bsdf": {"type": "diffuse", "reflectance": {"type": "rgb", "value": [0, 0, 0]}},
              "emitter": {"type": "area", "radiance": {"type": "rgb", "value": [3, 3, 3]}}},
    "point": point(4, 3, 2, 3, 2, 3),
}, "area.pfm")
