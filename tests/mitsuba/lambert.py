"""The Mitsuba 3 reference for tests/mitsuba/lambert.tsd (issue "sampling"):
the same camera, spheres, floor and point lights, a `diffuse` BSDF of
reflectance Kd*colour, `point` emitters of intensity pi*I, the `direct`
integrator (emitter_samples left at 1), a box pixel filter. Writes
lambert.pfm (linear RGB floats) beside this script.

    python3 -m venv venv && venv/bin/pip install mitsuba numpy
    venv/bin/python tests/mitsuba/lambert.py
"""
from common import diffuse, floor, point, render_to, sensor, sphere

render_to({
    "type": "scene",
    "integrator": {"type": "direct"},
    "sensor": sensor(origin=[0, 1.5, 5], target=[0, 0.5, 0]),
    "floor": floor(diffuse(0.8, 0.8, 0.8, 0.9)),
    "a": sphere(-1.2, 0.7, 0, 0.7, diffuse(0.9, 0.3, 0.2, 0.8)),
    "b": sphere(1.0, 0.5, 0.8, 0.5, diffuse(0.2, 0.5, 0.9, 0.8)),
    "c": sphere(0.3, 1.0, -1.5, 1.0, diffuse(0.4, 0.9, 0.3, 0.6)),
    "l1": point(18, 18, 18, -3, 5, 4),
    "l2": point(6, 9, 12, 4, 3, 1),
}, "lambert.pfm")
