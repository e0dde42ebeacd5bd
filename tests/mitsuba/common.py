"""What lambert.py and area.py share: the camera, film and sampler of the
comparison scenes, diffuse BSDFs and point lights in rayshell's units, and
writing the reference PFM beside the scripts."""
import math
import os

import mitsuba as mi

mi.set_variant("scalar_rgb")
T = mi.ScalarTransform4f


def sensor(origin, target, fov=50, width=80, height=60, spp=1024):
    """A perspective camera as rayshell's (`camera_angle` is the x field of
    view), a box pixel filter."""
    return {
        "type": "perspective",
        "fov": fov, "fov_axis": "x",
        "to_world": T().look_at(origin=origin, target=target, up=[0, 1, 0]),
        "sampler": {"type": "independent", "sample_count": spp},
        "film": {"type": "hdrfilm", "width": width, "height": height, "pixel_format": "rgb",
                 "rfilter": {"type": "box"}},
    }


def diffuse(r, g, b, kd):
    """rayshell's `material r g b 0 Kd 0 ...`: reflectance Kd*colour."""
    return {"type": "diffuse", "reflectance": {"type": "rgb", "value": [kd * r, kd * g, kd * b]}}


def sphere(x, y, z, radius, bsdf):
    return {"type": "sphere", "center": [x, y, z], "radius": radius, "bsdf": bsdf}


def point(r, g, b, x, y, z):
    """rayshell's `point_light r g b x y z`: intensity pi * (r, g, b)."""
    return {"type": "point", "position": [x, y, z],
            "intensity": {"type": "rgb", "value": [math.pi * r, math.pi * g, math.pi * b]}}


def floor(kd_colour):
    """The 8 x 8 square at y = 0 of both scenes (a rectangle spans -1..1)."""
    return {"type": "rectangle", "to_world": T().rotate([1, 0, 0], -90).scale([4, 4, 1]),
            "bsdf": kd_colour}


def render_to(scene_dict, name):
    img = mi.render(mi.load_dict(scene_dict))
    here = os.path.dirname(os.path.abspath(__file__))
    mi.Bitmap(img).write(os.path.join(here, name))
