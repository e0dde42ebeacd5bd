"""The Mitsuba 3 reference for tsd/cornell.tsd (issue "global illumination"):
the same box in Mitsuba's terms, with the unit mapping of issue "sampling":
`diffuse` reflectance = Kd*colour, an `area` emitter of the same radiance
on a rectangle with a black BSDF, `conductor` with the `none` material for
the mirror, `dielectric` (1.5 inside, 1 outside) for the glass, and the
`path` integrator with max_depth = trace_depth + 1 (Mitsuba counts the
camera's hit as a bounce). 128 x 128 pixels, box filter, 4096 samples per
pixel. Writes cornell.pfm beside this script; `scripts/bench-path` imports
`scene` to time Mitsuba on it.

    venv/bin/python tests/mitsuba/cornell.py    (see lambert.py)
"""
from common import T, diffuse, render_to, sensor

TRACE_DEPTH = 8


def wall(to_world, bsdf):
    """Mitsuba's rectangle is [-1, 1]^2 at z = 0 facing +z."""
    return {"type": "rectangle", "to_world": to_world, "bsdf": bsdf}


def scene(spp=4096):
    """The box as a Mitsuba scene dictionary."""
    white = diffuse(0.75, 0.75, 0.75, 1)
    return {
        "type": "scene",
        "integrator": {"type": "path", "max_depth": TRACE_DEPTH + 1},
        "sensor": sensor(origin=[0, 0, 3.4], target=[0, 0, 0], fov=40, width=128, height=128,
                         spp=spp),
        "floor": wall(T().translate([0, -1, 0]).rotate([1, 0, 0], -90), white),
        "ceiling": wall(T().translate([0, 1, 0]).rotate([1, 0, 0], 90), white),
        "back": wall(T().translate([0, 0, -1]), white),
        "left": wall(T().translate([-1, 0, 0]).rotate([0, 1, 0], 90),
                     diffuse(0.75, 0.15, 0.15, 1)),
        "right": wall(T().translate([1, 0, 0]).rotate([0, 1, 0], -90),
                      diffuse(0.15, 0.75, 0.15, 1)),
        "light": {"type": "rectangle",
                  "to_world": T().translate([0, 0.99, 0]).rotate([1, 0, 0], 90)
                                 .scale([0.25, 0.25, 1]),
                  "bsdf": diffuse(0, 0, 0, 0),
                  "emitter": {"type": "area", "radiance": {"type": "rgb", "value": [12, 12, 12]}}},
        "mirror": {"type": "sphere", "center": [-0.45, -0.65, -0.35], "radius": 0.35,
                   "bsdf": {"type": "conductor", "material": "none"}},
        "glass": {"type": "sphere", "center": [0.45, -0.65, 0.3], "radius": 0.35,
                  "bsdf": {"type": "dielectric", "int_ior": 1.5, "ext_ior": 1.0}},
    }


if __name__ == "__main__":
    render_to(scene(), "cornell.pfm")
