//! POV-Ray 3.7 as the outside oracle for refraction and for the shapes of
//! issue "shapes" (`shapes`: plane, box, cylinder, cone, disc, torus, blob;
//! `csg`: union, intersection, difference, merge; and issue "surfaces":
//! `checker`, the checker texture): each `tests/pov/NAME.tsd`
//! has a `NAME.pov` built to the same conventions (glass as `rgbf` filter,
//! `interior { ior }`, no ambient or diffuse on glass, the same trace depth
//! and cut-off), and the two pictures must agree: at most 1 % of the pixels
//! may differ by more than 2/255 (edges of the checkered wall land on either
//! side of a pixel centre in the two renderers). POV-Ray is optional, as
//! `tclsh` is: without it the test says so and skips.

use std::path::Path;
use std::process::Command;

use rayshell::image::read_rgb8;

use crate::util::{raytrace, root, scratch, text};

const W: u32 = 160;
const H: u32 = 120;

fn povray_available() -> bool {
    Command::new("povray").arg("--version").output().is_ok()
}

fn pixels(path: &Path) -> Vec<u8> {
    let data = std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let img = read_rgb8(&data).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    assert_eq!((img.width, img.height), (W, H), "{}", path.display());
    img.rgb
}

/// (pixels off by more than 2/255, their share).
fn compare(a: &[u8], b: &[u8]) -> (usize, f64) {
    let off = a
        .chunks(3)
        .zip(b.chunks(3))
        .filter(|(p, q)| p.iter().zip(q.iter()).any(|(x, y)| x.abs_diff(*y) > 2));
    let n = off.count();
    (n, n as f64 / (W * H) as f64)
}

/// Renders `tests/pov/NAME.tsd` (after `setup`) with rayshell.
fn ours(dir: &Path, name: &str, setup: &str) -> Vec<u8> {
    let out = dir.join(format!("{name}-ours.ppm"));
    let scene = root().join("tests/pov").join(format!("{name}.tsd"));
    let script = format!(
        "{setup}\nsource {{{}}}\ncamera_resolution {W} {H}\nrender {{{}}}\n",
        scene.display(),
        out.display()
    );
    let r = raytrace().args(["-c", &script]).output().expect("run raytrace");
    assert!(r.status.success(), "{name}: {}", text(&r.stderr));
    pixels(&out)
}

fn theirs(dir: &Path, name: &str) -> Vec<u8> {
    let out = dir.join(format!("{name}-povray.ppm"));
    let r = Command::new("povray")
        .arg(format!("+I{name}.pov"))
        .arg(format!("+O{}", out.display()))
        .args(["+FP", &format!("+W{W}"), &format!("+H{H}"), "-D", "-A"])
        .args(["File_Gamma=1.0", "Output_Alpha=off", "-GA"])
        .current_dir(root().join("tests/pov"))
        .output()
        .expect("run povray");
    assert!(r.status.success(), "povray {name}: {}", text(&r.stderr));
    pixels(&out)
}

pub fn refraction_matches_povray() {
    if !povray_available() {
        crate::util::skip("povray is not installed (apt-get install povray)");
    }
    let dir = scratch("pov");
    let mut report = Vec::new();
    for name in ["bubble", "water", "tinted", "cube"] {
        let (n, share) = compare(&ours(&dir, name, ""), &theirs(&dir, name));
        report.push(format!("{name}: {n} pixels ({:.2} %) off by more than 2/255", share * 100.0));
        assert!(share <= 0.01, "{}", report.join("\n"));
    }
    println!("{}", report.join("\n"));
}

pub fn smooth_meshes_refract_the_same_whichever_way_they_are_wound() {
    // With vertex normals, the normals say which side is outside: the
    // clockwise cube is the counter-clockwise one, to the byte. Without
    // normals, the winding decides (a clockwise `tri` cube is inside out).
    let dir = scratch("winding");
    let ccw = ours(&dir, "cube", "set winding ccw; set smooth 0");
    for setup in ["set winding cw; set smooth 1", "set winding ccw; set smooth 1"] {
        let differ = ours(&dir, "cube", setup).iter().zip(&ccw).filter(|(a, b)| a != b).count();
        assert_eq!(
            differ, 0,
            "{setup}: {differ} bytes differ from the flat counter-clockwise cube"
        );
    }
    let (_, share) = compare(&ours(&dir, "cube", "set winding cw; set smooth 0"), &ccw);
    assert!(share > 0.1, "an inside-out flat cube should refract differently");
}

pub fn shapes_and_csg_match_povray() {
    if !povray_available() {
        crate::util::skip("povray is not installed (apt-get install povray)");
    }
    let dir = scratch("pov-shapes");
    let mut report = Vec::new();
    for name in ["shapes", "csg", "checker"] {
        let (n, share) = compare(&ours(&dir, name, ""), &theirs(&dir, name));
        report.push(format!("{name}: {n} pixels ({:.2} %) off by more than 2/255", share * 100.0));
        assert!(share <= 0.01, "{}", report.join("\n"));
    }
    println!("{}", report.join("\n"));
}
