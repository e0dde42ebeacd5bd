//! Shapes and structure (issue "shapes"): transformed objects against the
//! same objects built in place, an ellipsoid's shading against its
//! gradient, instances against copies, CSG against the boolean formula
//! pixel by pixel, and located errors for bad structure.

use crate::util::{raytrace, scratch, text};

fn render(dir: &std::path::Path, script: &str) -> rayshell::image::Rgb8 {
    let r = raytrace().args(["-q", "-c", script]).current_dir(dir).output().unwrap();
    assert_eq!(r.status.code(), Some(0), "{}", text(&r.stderr));
    let out = script.rsplit(' ').next().unwrap();
    rayshell::image::read_rgb8(&std::fs::read(dir.join(out)).unwrap()).unwrap()
}

/// How many channels differ by more than `tol`, and the largest difference.
fn differ(a: &rayshell::image::Rgb8, b: &rayshell::image::Rgb8, tol: u8) -> (usize, u8) {
    let d = a.rgb.iter().zip(&b.rgb).map(|(x, y)| x.abs_diff(*y));
    (d.clone().filter(|&d| d > tol).count(), d.max().unwrap_or(0))
}

const STAGE: &str = "camera_resolution 96 72; camera_from 1 4 9; camera_target 0 0.5 0\n\
                     point_light 40 40 40 -3 6 5; ambient_light 0.15 0.15 0.15\n\
                     material 0.8 0.8 0.8 0.2 0.8 0 1 0 1\n\
                     tri [vertex -6 0 -6] [vertex -6 0 6] [vertex 6 0 6]\n\
                     tri [vertex -6 0 -6] [vertex 6 0 6] [vertex 6 0 -6]\n\
                     material 0.9 0.4 0.2 0.2 0.7 0.4 30 0 1\n";

/// Objects made under `translate`, `rotate`, `scale` and `push`/`pop`
/// against the same objects given in place: spheres, triangles with
/// normals, cylinders, boxes, cones. The same picture, up to rounding
/// (the transformed ones are intersected in their own coordinates). A
/// cylinder or cone placed by a similarity is tested natively, four at
/// once in the tree's leaves; one stretched along its axis is the general
/// solid in its own frame: the two kinds of test give the same picture.
pub fn transformed_objects_match_objects_built_in_place() {
    let dir = scratch("shapes-transform");
    let cases = [
        ("transform { translate 1 0.5 0; sphere 0 0 0 0.5 }", "sphere 1 0.5 0 0.5"),
        ("transform { translate 0 1 0; scale 2; sphere 0.5 0 0 0.25 }", "sphere 1 1 0 0.5"),
        (
            "transform { translate -1 0 0; rotate 0 90 0; cylinder 0 0.5 0 1 0.5 0 0.3 }",
            "cylinder -1 0.5 0 -1 0.5 -1 0.3",
        ),
        (
            "translate 0 0 1; push; rotate 0 0 90; cone 0 0 0 0.5 1 0 0 0.1; pop; box -2 0 -2 -1.5 0.5 -1.5",
            "cone 0 0 1 0.5 0 1 1 0.1; box -2 0 -1 -1.5 0.5 -0.5",
        ),
        (
            "transform { scale 2 1 1; cylinder 0 0.5 0 0.5 0.5 0 0.3 }",
            "cylinder 0 0.5 0 1 0.5 0 0.3",
        ),
        (
            "transform { scale 1 2 1; cone 1 0 0 0.4 1 0.5 0 0.1 -open }",
            "cone 1 0 0 0.4 1 1 0 0.1 -open",
        ),
        (
            "set n [normal 0 0 1]; transform { translate 2 0 -1; rotate_axis 90 0 1 0; \
             ntri [vertex 0 0 0] $n [vertex 1 0 0] $n [vertex 0 1 0] $n }",
            "set n [normal 1 0 0]; ntri [vertex 2 0 -1] $n [vertex 2 0 -2] $n [vertex 2 1 -1] $n",
        ),
        (
            "transform { translate 0.5 0.5 0.5; rotate 0 0 90; box -0.5 -0.25 -0.5 0.5 0.25 0.5 }",
            "box 0.25 0 0 0.75 1 1",
        ),
    ];
    for (moved, placed) in cases {
        let a = render(&dir, &format!("{STAGE}{moved}\nrender a.ppm"));
        let b = render(&dir, &format!("{STAGE}{placed}\nrender b.ppm"));
        let (n, max) = differ(&a, &b, 2);
        assert!(n <= 4, "{moved}: {n} channels differ (max {max})");
        // And the object is there at all.
        let empty = render(&dir, &format!("{STAGE}render c.ppm"));
        assert!(differ(&a, &empty, 2).0 > 50, "{moved}: nothing drawn");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// A sphere under `scale 2 1 1` is the ellipsoid x²/4 + y² + z² = 1: lit by
/// a parallel light, each pixel is Kd·I·max(0, n̂·l̂) with n̂ its gradient
/// (x/4, y, z), at the point the pixel's ray meets it (solved here).
pub fn ellipsoids_shade_by_their_gradient() {
    let dir = scratch("shapes-ellipsoid");
    let (w, depth, half) = (80u32, 50.0f64, 2.5f64);
    let angle = 2.0 * (half / depth).atan().to_degrees();
    let l = [1.0f64, 2.0, 3.0];
    let script = format!(
        "camera_resolution {w} {w}; camera_angle {angle}; camera_from 0 0 {depth}; camera_target 0 0 0\n\
         parallel_light 0.9 0.9 0.9 {} {} {}\n\
         material 1 1 1 0 1 0 1 0 1; scale 2 1 1; sphere 0 0 0 1; render e.ppm",
        -l[0], -l[1], -l[2]
    );
    let img = render(&dir, &script);
    let ll = (l[0] * l[0] + l[1] * l[1] + l[2] * l[2]).sqrt();
    let (mut checked, mut worst) = (0, 0.0f64);
    for j in 0..w {
        for i in 0..w {
            // The pixel centre's ray, as the camera makes it.
            let px = ((i as f64 + 0.5) / w as f64 * 2.0 - 1.0) * half / depth;
            let py = (1.0 - (j as f64 + 0.5) / w as f64 * 2.0) * half / depth;
            let (o, d) = ([0.0, 0.0, depth], [px, py, -1.0]);
            // (o + t·d) on x²/4 + y² + z² = 1.
            let a = d[0] * d[0] / 4.0 + d[1] * d[1] + d[2] * d[2];
            let b = 2.0 * (o[0] * d[0] / 4.0 + o[1] * d[1] + o[2] * d[2]);
            let c = o[0] * o[0] / 4.0 + o[1] * o[1] + o[2] * o[2] - 1.0;
            let disc = b * b - 4.0 * a * c;
            if disc < 0.2 {
                continue; // off the ellipsoid or at its silhouette
            }
            let t = (-b - disc.sqrt()) / (2.0 * a);
            let p = [o[0] + t * d[0], o[1] + t * d[1], o[2] + t * d[2]];
            let g = [p[0] / 4.0, p[1], p[2]];
            let gl = (g[0] * g[0] + g[1] * g[1] + g[2] * g[2]).sqrt();
            let cos = (g[0] * l[0] + g[1] * l[1] + g[2] * l[2]) / (gl * ll);
            let want = 0.9 * cos.max(0.0);
            let got = img.rgb[((j * w + i) * 3) as usize] as f64 / 255.0;
            worst = worst.max((got - want).abs());
            checked += 1;
        }
    }
    assert!(checked > 1500, "{checked} pixels on the ellipsoid");
    assert!(worst <= 2.5 / 255.0, "a pixel is {worst} off the gradient's shading");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Instances of a group (triangles, a sphere, a torus and a nested
/// instance) under transforms, against the same things placed by hand.
pub fn instances_render_as_copies() {
    let dir = scratch("shapes-instance");
    let group = "group leaf { sphere 0 0.3 0 0.3; tri [vertex -0.5 0 0] [vertex 0.5 0 0] [vertex 0 0.8 0.2] }\n\
                 group pair { instance leaf; transform { translate 0 0 -1; instance leaf } }\n";
    let placed = "transform { translate -1 0 0.5; instance pair }\n\
                  transform { translate 1.5 0 0; rotate 0 90 0; instance leaf }\n";
    let by_hand = "sphere -1 0.3 0.5 0.3; tri [vertex -1.5 0 0.5] [vertex -0.5 0 0.5] [vertex -1 0.8 0.7]\n\
                   sphere -1 0.3 -0.5 0.3; tri [vertex -1.5 0 -0.5] [vertex -0.5 0 -0.5] [vertex -1 0.8 -0.3]\n\
                   sphere 1.5 0.3 0 0.3; tri [vertex 1.5 0 0.5] [vertex 1.5 0 -0.5] [vertex 1.7 0.8 0]\n";
    let a = render(&dir, &format!("{STAGE}{group}{placed}render a.ppm"));
    let b = render(&dir, &format!("{STAGE}{by_hand}render b.ppm"));
    let (n, max) = differ(&a, &b, 2);
    assert!(n <= 6, "{n} channels differ (max {max})");
    let _ = std::fs::remove_dir_all(&dir);
}

/// CSG pixel by pixel: a camera looking straight down at a box and a sphere
/// (orthographic enough), lit by ambient light only; each pixel is lit
/// where the column under it meets the composite, whose top is where the
/// boolean formula first holds: union/merge where either does,
/// intersection where both, difference where the box holds and the sphere
/// not (a hole shows the sphere's inside, lit too).
pub fn csg_follows_the_boolean_formula() {
    let dir = scratch("shapes-csg");
    let (w, depth, half) = (64u32, 1000.0f64, 1.6f64);
    let angle = 2.0 * (half / depth).atan().to_degrees();
    let head = format!(
        "camera_resolution {w} {w}; camera_angle {angle}; camera_from 0 {depth} 0; camera_target 0 0 0; camera_up 0 0 -1\n\
         ambient_light 1 1 1; material 1 1 1 1 0 0 1 0 1\n"
    );
    // Box: |x|, |z| < 1, -1 < y < 0.2. Sphere: centre (0.6, 0, 0), radius 0.8.
    let in_box = |x: f64, z: f64| x.abs() < 1.0 && z.abs() < 1.0;
    let in_ball = |x: f64, z: f64| (x - 0.6).powi(2) + z * z < 0.64;
    type Inside<'a> = &'a dyn Fn(f64, f64) -> bool;
    let cases: [(&str, Inside); 4] = [
        ("union", &|x, z| in_box(x, z) || in_ball(x, z)),
        ("merge", &|x, z| in_box(x, z) || in_ball(x, z)),
        ("intersection", &|x, z| in_box(x, z) && in_ball(x, z)),
        // The column meets the box's top, or the hole's floor below it.
        ("difference", &|x, z| in_box(x, z)),
    ];
    for (op, lit) in cases {
        let img = render(
            &dir,
            &format!(
                "{head}csg {op} {{ box -1 -1 -1 1 0.2 1; sphere 0.6 0 0 0.8 }}; render {op}.ppm"
            ),
        );
        let mut wrong = 0;
        for j in 0..w {
            for i in 0..w {
                let x = ((i as f64 + 0.5) / w as f64 * 2.0 - 1.0) * half;
                let z = ((j as f64 + 0.5) / w as f64 * 2.0 - 1.0) * half;
                // Skip pixels within a pixel of an outline.
                let step = 2.0 * half / w as f64;
                let near_edge = [(step, 0.0), (-step, 0.0), (0.0, step), (0.0, -step)]
                    .iter()
                    .any(|(dx, dz)| lit(x + dx, z + dz) != lit(x, z));
                if near_edge {
                    continue;
                }
                let got = img.rgb[((j * w + i) * 3) as usize] > 128;
                wrong += (got != lit(x, z)) as usize;
            }
        }
        assert_eq!(wrong, 0, "{op}: {wrong} pixels disagree with the formula");
    }
    // Difference: the hole's floor (the sphere's inside, below the box's
    // top) is farther than the top: seen from the side, a notch.
    let _ = std::fs::remove_dir_all(&dir);
}

/// Bad structure is a located error that says what is wrong.
pub fn bad_structure_is_a_located_error() {
    for (script, msg) in [
        ("pop", "pop without a matching push"),
        ("scale 1 0 1", "scale must not be 0 on any axis"),
        ("box 0 0 0 1 0 1", "a box needs a size on every axis"),
        ("cylinder 0 0 0 0 0 0 1", "a cone or cylinder needs two different end points"),
        ("cone 0 0 0 0 0 1 0 0", "a cone's radii must be 0 or more, and not both 0"),
        ("cylinder 0 0 0 0 1 0 1 -closed", "bad option \"-closed\": must be -open"),
        ("torus 1 0", "a torus needs radii above 0"),
        ("disk 0 0 0 0 1 0 1 2", "a disk needs a radius above 0 and an inner radius"),
        ("plane 0 0 0 1", "a plane's normal must not be the zero vector"),
        (
            "csg union { tri [vertex 0 0 0] [vertex 1 0 0] [vertex 0 1 0] }",
            "csg takes closed solids only, not triangles",
        ),
        ("csg merge { cylinder 0 0 0 0 1 0 1 -open }", "csg takes closed solids only"),
        (
            "csg xor { sphere 0 0 0 1 }",
            "bad csg operation \"xor\": must be union, intersection, difference or merge",
        ),
        ("csg union {}", "csg made no solids"),
        ("instance tree", "no group named \"tree\""),
        ("group a {sphere 0 0 0 1}; instance b", "no group named \"b\" (groups: a)"),
        ("proc f {} {transform {f}}; f", "too many nested"),
        (
            "group g0 {sphere 0 0 0 1}; for {set i 1} {$i < 40} {incr i} {group g$i [list instance g[expr {$i - 1}]]}",
            "instances nested too deep: \"g31\" holds instances 32 deep (the limit is 32)",
        ),
    ] {
        let r = raytrace().args(["-c", script]).output().unwrap();
        assert_eq!(r.status.code(), Some(1), "{script}");
        let err = text(&r.stderr);
        assert!(err.starts_with("-c:1: ") && err.contains(msg), "{script}: {err}");
    }
    // A failed group or csg leaves the scene as it was.
    let r = raytrace()
        .args(["-c", "catch {group g {sphere 0 0 0 1; error boom}}; catch {instance g} m; puts $m; catch {csg union {sphere 0 0 0 1; error x}}; puts [scene_bounds]"])
        .output()
        .unwrap();
    assert_eq!(
        text(&r.stdout),
        "no group named \"g\": make one with group g {...}\n\n",
        "{}",
        text(&r.stderr)
    );
}

/// The SPD scenes in `../shared/spd` load, with as many spheres, cones,
/// polygons, patches and lights as their files hold, and render.
pub fn spd_scenes_load_with_their_counts() {
    let spd = crate::util::root().join("../shared/spd");
    if !spd.is_dir() {
        crate::util::skip("../shared/spd is absent (the SPD scenes come with the shared data)");
    }
    let dir = scratch("shapes-spd");
    let mut files: Vec<_> =
        std::fs::read_dir(&spd).unwrap().filter_map(|e| e.ok()).map(|e| e.path()).collect();
    files.retain(|p| p.extension().is_some_and(|x| x == "nff"));
    files.sort();
    assert!(files.len() >= 10, "{files:?}");
    for f in files {
        let text = std::fs::read_to_string(&f).unwrap();
        // Items start lines (SPD writes one per line, or `c` over three).
        let count =
            |item: &str| text.lines().filter(|l| l.split_whitespace().next() == Some(item)).count();
        let want = format!(
            "spheres {} cones {} polygons {} patches {} lights {}",
            count("s"),
            count("c"),
            count("p"),
            count("pp"),
            count("l")
        );
        let script =
            format!("puts [nff {{{}}}]; camera_resolution 48 48; render out.ppm", f.display());
        let r = raytrace().args(["-q", "-c", &script]).current_dir(&dir).output().unwrap();
        assert_eq!(r.status.code(), Some(0), "{}: {}", f.display(), text_of(&r.stderr));
        assert_eq!(text_of(&r.stdout).trim(), want, "{}", f.display());
        let img = rayshell::image::read_rgb8(&std::fs::read(dir.join("out.ppm")).unwrap()).unwrap();
        let distinct: std::collections::HashSet<&[u8]> = img.rgb.chunks(3).collect();
        assert!(distinct.len() > 20, "{}: a flat picture", f.display());
    }
    let _ = std::fs::remove_dir_all(&dir);
}

fn text_of(b: &[u8]) -> String {
    text(b)
}

/// `sphereflake` against the same flake given sphere by sphere: here by a
/// Tcl procedure written from the SPD `balls` generator's description
/// (children 4r/3 from their parent's centre along nine directions turned
/// to the parent's own), and, when `../shared/spd` is there, by the SPD
/// file itself. The same picture.
pub fn sphereflakes_match_their_spheres() {
    let dir = scratch("shapes-flake");
    let head = "camera_from 2.1 1.3 1.7; camera_target 0 0 0; camera_up 0 0 1; camera_resolution 96 96\n\
                point_light 12 12 12 4 3 2; point_light 12 12 12 -3 1 5; ambient_light 0.1 0.1 0.1\n\
                material 1 0.9 0.7 0.2 0.5 0.5 37 0 1\n";
    let tcl_flake = r#"
        proc rot {axis angle v} {
            # Rodrigues: v turned by angle about the unit axis.
            lassign $axis kx ky kz; lassign $v x y z
            set c [expr {cos($angle)}]; set s [expr {sin($angle)}]
            set dot [expr {$kx*$x + $ky*$y + $kz*$z}]
            set cx [expr {$ky*$z - $kz*$y}]; set cy [expr {$kz*$x - $kx*$z}]; set cz [expr {$kx*$y - $ky*$x}]
            list [expr {$x*$c + $cx*$s + $kx*$dot*(1-$c)}] [expr {$y*$c + $cy*$s + $ky*$dot*(1-$c)}] \
                 [expr {$z*$c + $cz*$s + $kz*$dot*(1-$c)}]
        }
        set d [expr {1/sqrt(2)}]
        set tip [list $d [expr {-$d}] 0]
        set dirs {}
        foreach set {0 1 2} {
            foreach v [list [list $d $d 0] [list $d 0 [expr {-$d}]] [list 0 $d [expr {-$d}]]] {
                set v [rot $tip [expr {asin(2/sqrt(6))}] $v]
                lappend dirs [rot {0 0 1} [expr {$set*2*acos(-1)/3}] $v]
            }
        }
        proc flake {c r dir depth} {
            global dirs
            sphere {*}$c $r
            if {$depth == 0} return
            lassign $dir dx dy dz
            # The turn from +z to dir.
            if {$dz >= 1} { set axis {0 0 1}; set ang 0 } else {
                set n [expr {sqrt($dy*$dy + $dx*$dx)}]
                set axis [list [expr {-$dy/$n}] [expr {$dx/$n}] 0]; set ang [expr {acos($dz)}]
            }
            foreach u $dirs {
                set v [rot $axis $ang $u]
                set cc {}
                foreach a $c b $v { lappend cc [expr {$a + $b*$r*4/3.0}] }
                flake $cc [expr {$r/3.0}] $v [expr {$depth - 1}]
            }
        }
        flake {0 0 0} 0.5 {0 0 1} 2
    "#;
    let lazy = render(&dir, &format!("{head}sphereflake 0 0 0 0.5 2; render a.ppm"));
    let given = render(&dir, &format!("{head}{tcl_flake}\nrender b.ppm"));
    let (n, max) = differ(&lazy, &given, 2);
    assert!(n <= 6, "against the Tcl flake: {n} channels differ (max {max})");
    let balls = crate::util::root().join("../shared/spd/balls-s3.nff");
    if balls.is_file() {
        // The file's camera, lights, floor and materials, less its spheres.
        let text = std::fs::read_to_string(&balls).unwrap();
        let rest: String =
            text.lines().filter(|l| !l.starts_with("s ")).map(|l| format!("{l}\n")).collect();
        std::fs::write(dir.join("rest.nff"), rest).unwrap();
        let from_file = render(
            &dir,
            &format!("nff {{{}}}; camera_resolution 96 96; render c.ppm", balls.display()),
        );
        let flake = render(
            &dir,
            "nff rest.nff; camera_resolution 96 96; sphereflake 0 0 0 0.5 3; render d.ppm",
        );
        let (n, max) = differ(&from_file, &flake, 2);
        // The file rounds positions and radii to 6 digits: edge pixels of
        // the smallest spheres move (66 channels of 27,648 here).
        assert!(n <= 140, "against balls-s3.nff: {n} channels differ (max {max})");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// `menger` against the same sponge made of `box`es.
pub fn sponges_match_their_boxes() {
    let dir = scratch("shapes-menger");
    let head = "camera_from 4 3 5; camera_target 0 0 0; camera_resolution 96 96\n\
                ambient_light 0.2 0.2 0.2; point_light 40 40 40 5 6 4; material 0.9 0.8 0.6 0.3 0.7 0.2 20 0 1\n";
    let boxes = r#"
        proc sponge {x y z s depth} {
            if {$depth == 0} {
                set h [expr {$s / 2.0}]
                box [expr {$x-$h}] [expr {$y-$h}] [expr {$z-$h}] [expr {$x+$h}] [expr {$y+$h}] [expr {$z+$h}]
                return
            }
            set t [expr {$s / 3.0}]
            foreach i {-1 0 1} { foreach j {-1 0 1} { foreach k {-1 0 1} {
                if {($i == 0) + ($j == 0) + ($k == 0) >= 2} continue
                sponge [expr {$x + $i*$t}] [expr {$y + $j*$t}] [expr {$z + $k*$t}] $t [expr {$depth - 1}]
            }}}
        }
        sponge 0 0 0 3 2
    "#;
    let lazy = render(&dir, &format!("{head}menger 0 0 0 3 2; render a.ppm"));
    let given = render(&dir, &format!("{head}{boxes}\nrender b.ppm"));
    let (n, max) = differ(&lazy, &given, 2);
    assert!(n <= 6, "{n} channels differ (max {max})");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Blobs and closed meshes are CSG solids too: a cube read from an OBJ
/// file less a ball is the box less the ball, and a blob intersected with
/// a box around it is the blob.
pub fn blobs_and_closed_meshes_join_csg() {
    let dir = scratch("shapes-csg-mesh");
    // A unit cube, faces counter-clockwise seen from outside.
    let cube = "v -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\nv -1 -1 1\nv 1 -1 1\nv 1 1 1\nv -1 1 1\n\
                f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 4 8 7 3\nf 1 5 8 4\nf 2 3 7 6\n";
    std::fs::write(dir.join("cube.obj"), cube).unwrap();
    let ball = "sphere 0.6 0.7 0.8 0.9";
    let from_mesh = render(
        &dir,
        &format!(
            "{STAGE}transform {{ translate 0 1 0; csg difference {{ mesh cube.obj -flat; {ball} }} }}; render a.ppm"
        ),
    );
    let from_box = render(
        &dir,
        &format!(
            "{STAGE}transform {{ translate 0 1 0; csg difference {{ box -1 -1 -1 1 1 1; {ball} }} }}; render b.ppm"
        ),
    );
    let (n, max) = differ(&from_mesh, &from_box, 2);
    assert!(n <= 8, "mesh cube vs box: {n} channels differ (max {max})");
    let blob = "blob 0.4 { blob_sphere -0.4 1 0 0.9 1; blob_sphere 0.5 1.2 0 0.8 1 }";
    let alone = render(&dir, &format!("{STAGE}{blob}; render c.ppm"));
    let cut = render(
        &dir,
        &format!("{STAGE}csg intersection {{ {blob}; box -3 -1 -3 3 3 3 }}; render d.ppm"),
    );
    let (n, max) = differ(&alone, &cut, 2);
    assert!(n <= 8, "blob vs blob within a box: {n} channels differ (max {max})");
    let halved = render(
        &dir,
        &format!("{STAGE}csg intersection {{ {blob}; box -3 -1 -3 0 3 3 }}; render e.ppm"),
    );
    assert!(differ(&alone, &halved, 2).0 > 100, "cutting the blob in half changes it");
    let _ = std::fs::remove_dir_all(&dir);
}
