"""The Mitsuba 3 reference for tests/mitsuba/area.tsd (issue "sampling"):
a rectangle `area` emitter of the same radiance (its shape given a black
BSDF, so only its light counts), a `point` emitter of intensity pi*I,
`diffuse` BSDFs of reflectance Kd*colour, the `direct` integrator, a box
pixel filter, 1024 samples per pixel. Writes area.pfm beside this script.

    venv/bin/python tests/mitsuba/area.py    (see lambert.py)
"""
import math
import os

import mitsuba as mi

mi.set_variant("scalar_rgb")
T = mi.ScalarTransform4f


def diffuse(r, g, b, kd):
    return {"type": "diffuse", "reflectance": {"type": "rgb", "value": [kd * r, kd * g, kd * b]}}


scene = mi.load_dict({
    "type": "scene",
    "integrator": {"type": "direct"},
    "sensor": {
        "type": "perspective",
        "fov": 50, "fov_axis": "x",
        "to_world": T().look_at(origin=[0, 1.2, 5], target=[0, 0.6, 0], up=[0, 1, 0]),
        "sampler": {"type": "independent", "sample_count": 1024},
        "film": {"type": "hdrfilm", "width": 80, "height": 60, "pixel_format": "rgb",
                 "rfilter": {"type": "box"}},
    },
    "floor": {"type": "rectangle",
              "to_world": T().rotate([1, 0, 0], -90).scale([4, 4, 1]),
              "bsdf": diffuse(0.8, 0.8, 0.8, 0.9)},
    "a": {"type": "sphere", "center": [-0.8, 0.6, 0], "radius": 0.6,
          "bsdf": diffuse(0.9, 0.3, 0.2, 0.8)},
    "b": {"type": "sphere", "center": [0.9, 0.45, 0.6], "radius": 0.45,
          "bsdf": diffuse(0.2, 0.5, 0.9, 0.8)},
    # x in -1.5..0.5, z in -0.75..0.75 at y = 3, facing down (+z turned to -y).
    "light": {"type": "rectangle",
              "to_world": T().translate([-0.5, 3, 0]).rotate([1, 0, 0], 90).scale([1, 0.75, 1]),
              "bsdf": {"type": "diffuse", "reflectance": {"type": "rgb", "value": [0, 0, 0]}},
              "emitter": {"type": "area", "radiance": {"type": "rgb", "value": [3, 3, 3]}}},
    "point": {"type": "point", "position": [3, 2, 3],
              "intensity": {"type": "rgb", "value": [math.pi * 4, math.pi * 3, math.pi * 2]}},
})
img = mi.render(scene)
here = os.path.dirname(os.path.abspath(__file__))
mi.Bitmap(img).write(os.path.join(here, "area.pfm"))
