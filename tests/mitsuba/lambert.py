"""The Mitsuba 3 reference for tests/mitsuba/lambert.tsd (issue "sampling"):
the same camera, spheres, floor and point lights, a `diffuse` BSDF of
reflectance Kd*colour, `point` emitters of intensity pi*I, the `direct`
integrator (emitter_samples left at 1), a box pixel filter. Writes
lambert.pfm (linear RGB floats) beside this script.

    python3 -m venv venv && venv/bin/pip install mitsuba numpy
    venv/bin/python tests/mitsuba/lambert.py
"""
import math
import os

import mitsuba as mi

mi.set_variant("scalar_rgb")
T = mi.ScalarTransform4f


def diffuse(r, g, b, kd):
    return {"type": "diffuse", "reflectance": {"type": "rgb", "value": [kd * r, kd * g, kd * b]}}


def sphere(x, y, z, radius, bsdf):
    return {"type": "sphere", "center": [x, y, z], "radius": radius, "bsdf": bsdf}


def point(r, g, b, x, y, z):
    return {"type": "point", "position": [x, y, z],
            "intensity": {"type": "rgb", "value": [math.pi * r, math.pi * g, math.pi * b]}}


scene = mi.load_dict({
    "type": "scene",
    "integrator": {"type": "direct"},
    "sensor": {
        "type": "perspective",
        "fov": 50, "fov_axis": "x",
        "to_world": T().look_at(origin=[0, 1.5, 5], target=[0, 0.5, 0], up=[0, 1, 0]),
        "sampler": {"type": "independent", "sample_count": 1024},
        "film": {"type": "hdrfilm", "width": 80, "height": 60, "pixel_format": "rgb",
                 "rfilter": {"type": "box"}},
    },
    # The floor: an 8 x 8 square at y = 0 (a rectangle spans -1..1 in x, y).
    "floor": {"type": "rectangle",
              "to_world": T().rotate([1, 0, 0], -90).scale([4, 4, 1]),
              "bsdf": diffuse(0.8, 0.8, 0.8, 0.9)},
    "a": sphere(-1.2, 0.7, 0, 0.7, diffuse(0.9, 0.3, 0.2, 0.8)),
    "b": sphere(1.0, 0.5, 0.8, 0.5, diffuse(0.2, 0.5, 0.9, 0.8)),
    "c": sphere(0.3, 1.0, -1.5, 1.0, diffuse(0.4, 0.9, 0.3, 0.6)),
    "l1": point(18, 18, 18, -3, 5, 4),
    "l2": point(6, 9, 12, 4, 3, 1),
})
img = mi.render(scene)
here = os.path.dirname(os.path.abspath(__file__))
mi.Bitmap(img).write(os.path.join(here, "lambert.pfm"))
