//! The scene commands' documentation: what `help NAME` shows (the usage
//! comes from the command's registration) and, in the same order, the
//! README's table of scene commands, which a test regenerates from this
//! one source (`readme::the_command_table_is_the_help_text`).

/// One scene command's entry.
pub struct Doc {
    pub name: &'static str,
    /// What it does: one sentence or a few, Markdown code in backticks.
    pub meaning: &'static str,
    /// Its value before any call (state commands), or "".
    pub default: &'static str,
    pub example: &'static str,
}

/// The topics `help` groups the scene commands under, each with a line
/// that says what it is for, and its commands in the reference's order
/// (each scene command is in exactly one: `tests` below). Every other
/// command is Tcl's (`help tcl`).
pub const TOPICS: &[(&str, &str, &[&str])] = &[
    (
        "camera",
        "where the picture is taken from, its size and lens",
        &[
            "camera_from",
            "camera_target",
            "camera_forw",
            "camera_up",
            "camera_angle",
            "camera_resolution",
            "camera_aperture",
            "camera_focus",
        ],
    ),
    (
        "geometry",
        "shapes, meshes and scene files",
        &[
            "vertex",
            "normal",
            "tri",
            "ntri",
            "sphere",
            "plane",
            "box",
            "cylinder",
            "cone",
            "disk",
            "torus",
            "mesh",
            "nff",
            "sphereflake",
            "menger",
            "blob",
            "blob_sphere",
            "max_vertices",
            "max_normals",
            "scene_bounds",
            "clear_scene",
        ],
    ),
    (
        "structure",
        "transforms, CSG, groups and instances",
        &[
            "translate",
            "rotate",
            "rotate_axis",
            "scale",
            "push",
            "pop",
            "transform",
            "csg",
            "group",
            "instance",
        ],
    ),
    (
        "materials",
        "how surfaces look: colour, textures, highlights, bumps, emission",
        &["material", "texture", "highlight", "bump", "displace", "emission"],
    ),
    (
        "lights",
        "lights, the sky and the background",
        &[
            "background",
            "environment",
            "ambient_light",
            "parallel_light",
            "point_light",
            "spot_light",
            "area_light",
            "sphere_light",
        ],
    ),
    (
        "sampling",
        "rays per pixel, path tracing, noise, filters and the look",
        &[
            "trace_depth",
            "integrator",
            "samples",
            "filter",
            "adaptive",
            "seed",
            "exposure",
            "tonemap",
        ],
    ),
    ("animation", "motion blur and moving objects", &["shutter", "motion"]),
    (
        "output",
        "rendering, showing and measuring",
        &["render", "show", "preview", "stats", "raybench", "help"],
    ),
];

/// The topic a command is in, if it is a scene command.
pub fn topic_of(name: &str) -> Option<&'static str> {
    TOPICS.iter().find(|t| t.2.contains(&name)).map(|t| t.0)
}

/// The scene commands, in the README's order.
pub const SCENE: &[Doc] = &[
    Doc {
        name: "camera_from",
        meaning: "the eye point",
        default: "0 0 0",
        example: "camera_from 0 2 6",
    },
    Doc {
        name: "camera_target",
        meaning: "the point looked at (the later of this and `camera_forw` wins)",
        default: "0 0 -1",
        example: "camera_target 0 0.5 0",
    },
    Doc {
        name: "camera_forw",
        meaning: "the direction looked along (instead of at `camera_target`)",
        default: "",
        example: "camera_forw 0 -0.3 -1",
    },
    Doc {
        name: "camera_up",
        meaning: "up; made orthogonal to the view direction; parallel to it is an error at `render`, which names the `render` line (or the script's last line for `raytrace scene.tsd out.png`) and both vectors",
        default: "0 1 0",
        example: "camera_up 0 0 1",
    },
    Doc {
        name: "camera_angle",
        meaning: "degrees from the left edge of the image to the right edge; the vertical angle follows from the aspect",
        default: "45",
        example: "camera_angle 60",
    },
    Doc {
        name: "camera_resolution",
        meaning: "image size; at most 64 Mpixel (larger is refused with the memory it would need)",
        default: "256 256",
        example: "camera_resolution 640 480",
    },
    Doc {
        name: "camera_aperture",
        meaning: "the thin lens's radius in scene units (depth of field); 0 is a pinhole. The lens is sampled with the pixel's samples (a second stratified pattern), so raise `samples` with it",
        default: "0",
        example: "camera_aperture 0.05",
    },
    Doc {
        name: "camera_focus",
        meaning: "the distance in focus, along the view direction",
        default: "the distance from `camera_from` to `camera_target` (the length of the `camera_forw` vector)",
        example: "camera_focus 6.2",
    },
    Doc {
        name: "shutter",
        meaning: "the shutter interval: each camera ray samples a time in [t0, t1] (stratified with the pixel's samples), and its reflections and shadow rays keep it; moving objects (`motion`) are seen where they are at that time. With `samples 1` and an open shutter, the one sample's time is random too",
        default: "0 0",
        example: "shutter 0 1",
    },
    Doc {
        name: "motion",
        meaning: "objects created after this (spheres, triangles, meshes) move by (dx, dy, dz) scene units per unit of time, from where they are given at time 0; `motion 0 0 0` stops. Lights stay still",
        default: "0 0 0",
        example: "motion 2 0 0",
    },
    Doc {
        name: "vertex",
        meaning: "add a vertex; returns its index (from 0)",
        default: "",
        example: "set a [vertex 0 0 0]",
    },
    Doc {
        name: "normal",
        meaning: "add a normal (normalized); returns its index (from 0)",
        default: "",
        example: "set n [normal 0 1 0]",
    },
    Doc {
        name: "tri",
        meaning: "flat triangle; its counter-clockwise side is outside (for refraction); zero-area triangles are skipped with one warning at `render`",
        default: "",
        example: "tri $a $b $c",
    },
    Doc {
        name: "ntri",
        meaning: "triangle with normals interpolated across it; the normals say which side is outside, whatever the winding",
        default: "",
        example: "ntri $a $na $b $nb $c $nc",
    },
    Doc {
        name: "sphere",
        meaning: "a sphere; `radius` must be positive",
        default: "",
        example: "sphere 0 1 0 0.5",
    },
    Doc {
        name: "plane",
        meaning: "the infinite plane n̂·p = d, n̂ = n/|n| (the points at distance d from the origin along n̂), as POV-Ray's `plane { <n>, d }`; tested by every ray, outside the BVH",
        default: "",
        example: "plane 0 1 0 -1",
    },
    Doc {
        name: "box",
        meaning: "the box between two corners, axis-aligned before the current transform",
        default: "",
        example: "box -1 0 -1  1 2 1",
    },
    Doc {
        name: "cylinder",
        meaning: "a cylinder of radius r from one end's centre to the other's; capped (a closed solid, usable in `csg`) unless `-open`",
        default: "",
        example: "cylinder 0 0 0  0 2 0  0.5",
    },
    Doc {
        name: "cone",
        meaning: "a truncated cone from (x0, y0, z0) of radius r0 to (x1, y1, z1) of radius r1 (either may be 0); capped unless `-open`",
        default: "",
        example: "cone 0 0 0 1  0 2 0 0",
    },
    Doc {
        name: "disk",
        meaning: "a flat disk of radius r at (x, y, z) facing n; with `inner`, an annulus",
        default: "",
        example: "disk 0 0 0  0 1 0  2 0.5",
    },
    Doc {
        name: "torus",
        meaning: "a torus around the y axis through the origin: the circle of radius R in the xz-plane swept by a circle of radius r (POV-Ray's `torus { R, r }`); place it with the transform. Intersected through its quartic in double precision",
        default: "",
        example: "torus 1 0.25",
    },
    Doc {
        name: "nff",
        meaning: "reads an NFF scene (Eric Haines' Neutral File Format, the SPD benchmarks' format: view, background, lights, fill materials, spheres, open cones and cylinders, polygons, patches with normals) and returns `spheres N cones N polygons N patches N lights N`. NFF has no ambient and its lights do not fall off: each becomes a `point_light` of its colour with falloff `1 0 0`",
        default: "",
        example: "nff balls-s3.nff",
    },
    Doc {
        name: "sphereflake",
        meaning: "Haines' sphereflake with the layout of the SPD `balls` generator: a sphere of radius r and `depth` generations of nine children a third its size (Σ 9^k spheres: 820 at depth 3, 48.4 million at 8), generated as rays reach them, so any depth (up to 10) takes the memory of one sphere",
        default: "",
        example: "sphereflake 0 0 0 0.5 4",
    },
    Doc {
        name: "menger",
        meaning: "a Menger sponge filling the cube of edge `size` centred at (x, y, z), `depth` levels deep (20^depth cubes, up to depth 10), generated as rays reach its cubes",
        default: "",
        example: "menger 0 0 0 3 4",
    },
    Doc {
        name: "blob",
        meaning: "metaballs (POV-Ray's blob): the script's `blob_sphere`s add a field strength·(1 − d²/radius²)² each within their radius; the surface is where the sum equals `threshold`. Found exactly along each ray (a quartic between the spheres' entries and exits), placed by the transform current at `blob`",
        default: "",
        example: "blob 0.5 { blob_sphere 0 0 0 1 1; blob_sphere 1 0 0 1 1 }",
    },
    Doc {
        name: "blob_sphere",
        meaning: "a component of the blob being made: centre, radius and strength (negative strength carves); placed by the transform current now, relative to the blob's",
        default: "",
        example: "blob_sphere 0 1 0 0.8 -0.5",
    },
    Doc {
        name: "translate",
        meaning: "post-multiplies the current transform by a translation (OpenGL's order: in `translate 1 0 0; rotate 0 90 0; sphere ...` the sphere is rotated, then moved); every object made afterwards takes the current transform",
        default: "the identity",
        example: "translate 0 1 0",
    },
    Doc {
        name: "rotate",
        meaning: "post-multiplies a rotation: degrees about x, then about y, then about z",
        default: "",
        example: "rotate 0 45 0",
    },
    Doc {
        name: "rotate_axis",
        meaning: "post-multiplies a rotation of `angle` degrees about the axis (ax, ay, az), counter-clockwise looking down the axis",
        default: "",
        example: "rotate_axis 30 1 1 0",
    },
    Doc {
        name: "scale",
        meaning: "post-multiplies a scale: one factor, or one per axis (none 0); a sphere under a non-uniform scale is an ellipsoid",
        default: "",
        example: "scale 2 1 1",
    },
    Doc {
        name: "push",
        meaning: "saves the current transform (at most 1,000 deep)",
        default: "",
        example: "push",
    },
    Doc { name: "pop", meaning: "restores the last saved transform", default: "", example: "pop" },
    Doc {
        name: "transform",
        meaning: "runs the script between `push` and `pop` (popping even when it fails)",
        default: "",
        example: "transform { translate 2 0 0; sphere 0 0 0 1 }",
    },
    Doc {
        name: "csg",
        meaning: "constructive solid geometry of the closed solids the script makes (spheres, boxes, capped cylinders and cones, tori, blobs, closed meshes from `mesh`, nested `csg`): `union` (every surface, as POV-Ray's), `intersection`, `difference` (the first less the rest), `merge` (a union without inner surfaces). Each solid keeps its material and transform",
        default: "",
        example: "csg difference { box -1 -1 -1 1 1 1; sphere 0 0 0 1.3 }",
    },
    Doc {
        name: "group",
        meaning: "makes a named group from the script, in its own coordinates (from the identity transform), with its own BVH; it is drawn only where `instance` places it. Groups may hold instances of earlier groups",
        default: "",
        example: "group tree { cone 0 0 0 1 0 2 0 0 }",
    },
    Doc {
        name: "instance",
        meaning: "places the group of that name under the current transform (and the current motion): one small record, whatever the group's size",
        default: "",
        example: "transform { translate 3 0 0; instance tree }",
    },
    Doc {
        name: "texture",
        meaning: "the colour pattern of the objects made after it (as `material` is, and replacing the material's colour in its ambient and diffuse terms and in the light that passes through it): `checker r1 g1 b1 r2 g2 b2 ?size?` (POV-Ray's checker: colour 1 where ⌊x/size⌋+⌊y/size⌋+⌊z/size⌋ is even); `noise`, `marble`, `wood`, `granite` with optional colours (from, to) and scale, from a Perlin gradient noise of our own and its turbulence; `image FILE planar|cylindrical|spherical|uv ?-once?`, a PNG or PPM laid as POV-Ray's image_map map types 0, 2 and 1, or by a mesh's own texture coordinates (OBJ `vt`; planar on surfaces without them), mip-mapped; `none` goes back to the flat colour. Evaluated in the coordinates the object was written in, so it moves with the object's transform and its instances",
        default: "none",
        example: "texture marble 0.95 0.93 0.88 0.25 0.22 0.3 0.6",
    },
    Doc {
        name: "highlight",
        meaning: "the specular model of the materials that follow: `phong` (Ks·(R·V)^n_s, COS 426's), `blinn` (Ks·(N·H)^n_s), or `ward ax ay`, Ward's anisotropic lobe with roughness ax along the surface's u direction (the object's x axis, as written, laid onto the surface) and ay across it; Ks is its ρs and n_s is unused",
        default: "phong",
        example: "highlight ward 0.1 0.4",
    },
    Doc {
        name: "bump",
        meaning: "`noise amount ?size?` tilts the shading normals of the objects that follow by the gradient of amount·noise(p/size); `image FILE amount MAPPING` by the gradient of amount times the image's luminance laid as `texture image` lays it (the geometry is unchanged; evaluated as textures are); `none` stops",
        default: "none",
        example: "bump noise 0.2 0.1",
    },
    Doc {
        name: "displace",
        meaning: "`noise amount ?size?`: the meshes made after it are subdivided (as `mesh -subdivide n` asks) and their vertices moved along their area-weighted normals by amount·noise(p/size), in the mesh file's coordinates: real geometry, so silhouettes and shadows change; `image FILE amount` takes the height from the image's luminance on the mesh's xy-plane (the unit square, repeating); `none` stops",
        default: "none",
        example: "displace noise 0.1 0.2; mesh ball.obj -subdivide 3",
    },
    Doc {
        name: "emission",
        meaning: "the radiance the objects made after it emit from their front side (the side flat triangles wind counter-clockwise to, vertex normals point to, the outside of solids): any shape, mesh triangles too. The path tracer lights the scene with it (light sampling finds the top level's still triangles and spheres; emitters in instances, CSG or moving are found by paths); the Whitted tracer shows it as a glow that lights nothing. `emission 0 0 0` stops",
        default: "0 0 0",
        example: "emission 12 12 12",
    },
    Doc {
        name: "max_vertices",
        meaning: "a capacity hint for the vertex pool; using more is still correct",
        default: "",
        example: "max_vertices 100000",
    },
    Doc {
        name: "max_normals",
        meaning: "a capacity hint for the normal pool; using more is still correct",
        default: "",
        example: "max_normals 100000",
    },
    Doc {
        name: "background",
        meaning: "colour of rays that hit nothing (colours are 0..1 floats, not negative)",
        default: "0 0 0",
        example: "background 0.2 0.3 0.5",
    },
    Doc {
        name: "environment",
        meaning: "the light arriving from every direction nothing blocks: a constant radiance `r g b`, or an equirectangular picture (PNG, PPM, PFM or Radiance HDR; u = atan2(−z, x)/2π around the y axis, v the latitude up), times `scale`; the path tracer samples it by its luminance. Whitted rays that escape see it too. `none` goes back to the background colour",
        default: "the background colour",
        example: "environment sky.hdr 1.5",
    },
    Doc {
        name: "ambient_light",
        meaning: "the ambient light; a later call replaces it",
        default: "0 0 0",
        example: "ambient_light 0.1 0.1 0.1",
    },
    Doc {
        name: "parallel_light",
        meaning: "infinitely far light travelling along (x, y, z)",
        default: "",
        example: "parallel_light 1 1 1  0.5 -1 -0.3",
    },
    Doc {
        name: "point_light",
        meaning: "light at (x, y, z); arriving light falls off as 1/r², or as 1/(constant + linear·r + quadratic·r²) when the three coefficients are given (OpenGL's attenuation; `1 0 0` does not fall off, as NFF's and POV-Ray's lights)",
        default: "",
        example: "point_light 20 20 20  -3 6 4",
    },
    Doc {
        name: "spot_light",
        meaning: "at p shining along n: a point light within `angle1` degrees of the axis, fading linearly (in angle) to nothing at `angle2`; falling off with distance as `point_light`'s",
        default: "",
        example: "spot_light 40 40 40  0 5 0  0 -1 0  15 25",
    },
    Doc {
        name: "area_light",
        meaning: "a parallelogram light: corner (x, y, z), edges u and v, emitting radiance (r, g, b) (what a camera looking at it sees) from the side u × v points to; n × n stratified shadow samples per shading point (1..32). Seen by camera and reflected rays from its lit side; its back is not there. A small one of area A far away lights like `point_light` L·A/π",
        default: "n = 4",
        example: "area_light 10 10 10  -1 4 -1  2 0 0  0 0 2",
    },
    Doc {
        name: "sphere_light",
        meaning: "a spherical light of radiance (r, g, b), sampled by solid angle, n × n samples per shading point; seen by camera and reflected rays",
        default: "n = 4",
        example: "sphere_light 5 5 4  2 3 1  0.3",
    },
    Doc {
        name: "material",
        meaning: "colour, ambient, diffuse, specular, Phong exponent, transmittance, index of refraction (an ior of 0 is accepted when T is 0, as SPD-style opaque scenes write it)",
        default: "1 1 1  0.2 0.8 0 1 0 1",
        example: "material 0.9 0.3 0.2  0.2 0.7 0.3 50 0 1",
    },
    Doc {
        name: "trace_depth",
        meaning: "the most bounces a ray makes, 0..64",
        default: "5",
        example: "trace_depth 8",
    },
    Doc {
        name: "integrator",
        meaning: "the light transport: `whitted` (COS 426's recursive tracer) or `path` (Monte Carlo path tracing: diffuse bounces, colour bleeding, caustics; next-event estimation with multiple importance sampling; Russian roulette after 3 bounces; `trace_depth` bounces at most, `samples` paths per pixel). Ambient light is not used by `path`",
        default: "whitted",
        example: "integrator path",
    },
    Doc {
        name: "samples",
        meaning: "camera rays per pixel, 1..65536: stratified and jittered (correlated multi-jittered, Kensler 2013), placed by the filter; `samples 1` traces the pixel centre, exactly the one-ray picture",
        default: "1",
        example: "samples 16",
    },
    Doc {
        name: "filter",
        meaning: "the reconstruction filter and its radius in pixels (default radius: box 0.5, tent 1, gaussian 1.5 with σ = radius/3, mitchell 2 with B = C = 1/3); each sample is placed by importance under its pixel's filter, reaching into neighbouring pixels, and a pixel is the weighted mean of its samples",
        default: "box 0.5",
        example: "filter mitchell",
    },
    Doc {
        name: "adaptive",
        meaning: "after each pixel's `samples`, add batches of that many (at least 4) while the standard error of the pixel's mean luminance (linear units) is above `threshold`, up to `max` camera rays per pixel (default 1024); `adaptive 0` turns it off. `--stats` reports the camera rays spent per pixel",
        default: "off",
        example: "adaptive 0.005 256",
    },
    Doc {
        name: "seed",
        meaning: "the noise pattern of sampled pictures, and nothing else; every random number is a hash of (seed, `--seed`, frame, pixel, sample)",
        default: "0",
        example: "seed 7",
    },
    Doc {
        name: "exposure",
        meaning: "multiply values by 2^ev before the tone map",
        default: "0",
        example: "exposure -0.5",
    },
    Doc {
        name: "tonemap",
        meaning: "how values above 1 reach the file: `clamp` clips each channel (the COS 426 output); `reinhard` (x/(1+x)) and `aces` (Narkowicz's fit) map the largest channel and scale the others with it, so hue is kept",
        default: "clamp",
        example: "tonemap aces",
    },
    Doc {
        name: "render",
        meaning: "trace and write `.ppm` (binary P6, maxval 255) or `.png`; `-heatmap` writes the cost picture instead: each pixel coloured by the BVH traversal steps its primary ray took, nodes entered plus leaf blocks of four primitives tested (black, blue, red, yellow, white at the most)",
        default: "",
        example: "render -srgb out.png",
    },
    Doc {
        name: "mesh",
        meaning: "add an OBJ mesh (read in one pass of our own, tobj reading the files that pass leaves to it; a name ending in `.gz` is read as gzip-compressed OBJ) with the current material, scaled then moved; polygons are triangulated; smooth normals from `vn`, or computed from the faces (area-weighted) when the file has none; texture coordinates from `vt` (for `texture image FILE uv`); `-flat` turns smoothing off; `-subdivide n` splits each triangle into four, n times (then `displace` moves the vertices); the current transform places it too; returns the triangle count (its vertices keep out of the `vertex` pool, so `vertex` numbering is unaffected). A bad file is an error naming its line (`bunny.obj:12: bad OBJ line \"f 1 2 x\"`)",
        default: "",
        example: "mesh bunny.obj.gz -scale 6 -translate 0 -0.2 0",
    },
    Doc {
        name: "scene_bounds",
        meaning: "the bounding box of all geometry: `xmin ymin zmin xmax ymax zmax`",
        default: "",
        example: "lassign [scene_bounds] x0 y0 z0 x1 y1 z1",
    },
    Doc {
        name: "raybench",
        meaning: "trace one primary ray per pixel (and one shadow ray per hit towards the first light) without shading; returns `primary_mrays_per_s ... shadow_mrays_per_s ... build_ms ... primitives ... bvh_nodes ... bytes_per_triangle ... bvh_steps_per_ray ...`; `-brute` adds `brute_mrays_per_s`, primary rays that test every primitive (on a spread subset of the pixels), the baseline the BVH is measured against; `-threads` traces on a pool of that many threads (1 to 256), so one process can time one and two threads in turn",
        default: "",
        example: "raybench -shadow -threads 1",
    },
    Doc {
        name: "preview",
        meaning: "`on`: the live preview window (needs the `preview` feature and a display); `term`: draw each finished render in the terminal; `off`: neither",
        default: "",
        example: "preview term",
    },
    Doc {
        name: "show",
        meaning: "draw the last render (or `fileName`, or a quick preview of the scene before any render) in the terminal: kitty, iTerm2 or sixel graphics where the terminal has them, else 24-bit half-blocks sized to its width (`-width` to choose, `-blocks` to force them)",
        default: "",
        example: "show -width 60",
    },
    Doc {
        name: "stats",
        meaning: "the statistics of the last render (see `--stats`)",
        default: "",
        example: "puts [stats]",
    },
    Doc {
        name: "clear_scene",
        meaning: "back to the initial state",
        default: "",
        example: "clear_scene",
    },
];

/// The entry for `name`, if it is a scene command.
pub fn find(name: &str) -> Option<&'static Doc> {
    SCENE.iter().find(|d| d.name == name)
}
