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

/// Renders `tests/pov/NAME.pov` with POV-Ray.
fn theirs(dir: &Path, name: &str) -> Vec<u8> {
    povray(&root().join("tests/pov").join(format!("{name}.pov")), dir, name)
}

/// Renders the POV-Ray scene `pov` (from its own directory, for its
/// includes) into `dir/NAME-povray.ppm`, W×H, one ray per pixel, linear.
fn povray(pov: &Path, dir: &Path, name: &str) -> Vec<u8> {
    let out = dir.join(format!("{name}-povray.ppm"));
    let r = Command::new("povray")
        .arg(format!("+I{}", pov.display()))
        .arg(format!("+O{}", out.display()))
        .args(["+FP", &format!("+W{W}"), &format!("+H{H}"), "-D", "-A"])
        .args(["File_Gamma=1.0", "Output_Alpha=off", "-GA"])
        .current_dir(pov.parent().expect("a file in a directory"))
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

/// Every SPD scene in `../shared/spd`, read by `nff`, against POV-Ray's
/// render of the same file written as POV-Ray's language by
/// `scripts/nff2pov.tcl` (what `scripts/bench-spd` times): the same view,
/// lights that do not fall off, materials and shapes. Thin cylinders and
/// sphereflake edges land on either side of a pixel centre in the two
/// renderers, so a few pixels differ a lot; the mean must stay within
/// 1.5/255 and at most 4 % of the pixels may differ by more than 16/255
/// (measured: jacks 1.18/255 and 2.54 %, the others less).
/// A light falling off as 1/r² made rings a mean 146/255 off.
pub fn spd_scenes_match_povray() {
    if !povray_available() {
        crate::util::skip("povray is not installed (apt-get install povray)");
    }
    if !crate::util::tclsh_available() {
        crate::util::skip("tclsh is not installed (scripts/nff2pov.tcl needs it)");
    }
    let spd = root().join("../shared/spd");
    let mut files: Vec<_> = std::fs::read_dir(&spd)
        .map(|d| d.filter_map(|e| e.ok().map(|e| e.path())).collect())
        .unwrap_or_default();
    files.retain(|p| p.extension().is_some_and(|x| x == "nff"));
    files.sort();
    if files.is_empty() {
        crate::util::skip(format!("no SPD scenes in {}", spd.display()));
    }
    let dir = scratch("pov-spd");
    let mut report = Vec::new();
    let mut bad = false;
    for f in &files {
        let name = f.file_stem().unwrap().to_string_lossy().to_string();
        let pov = dir.join(format!("{name}.pov"));
        let r = Command::new("tclsh")
            .arg(root().join("scripts/nff2pov.tcl"))
            .arg(f)
            .args([W.to_string(), H.to_string()])
            .output()
            .expect("run tclsh");
        assert!(r.status.success(), "nff2pov {name}: {}", text(&r.stderr));
        std::fs::write(&pov, &r.stdout).unwrap();
        let b = povray(&pov, &dir, &name);
        let ours_out = dir.join(format!("{name}-ours.ppm"));
        let script = format!(
            "nff {{{}}}; camera_resolution {W} {H}; trace_depth 5; render {{{}}}",
            f.display(),
            ours_out.display()
        );
        let r = raytrace().args(["-q", "-c", &script]).output().expect("run raytrace");
        assert!(r.status.success(), "{name}: {}", text(&r.stderr));
        let a = pixels(&ours_out);
        let mean =
            a.iter().zip(&b).map(|(x, y)| x.abs_diff(*y) as f64).sum::<f64>() / a.len() as f64;
        let far = a
            .chunks(3)
            .zip(b.chunks(3))
            .filter(|(p, q)| p.iter().zip(q.iter()).any(|(x, y)| x.abs_diff(*y) > 16))
            .count() as f64
            / (W * H) as f64;
        bad |= mean > 1.5 || far > 0.04;
        report.push(format!(
            "{name}: mean difference {mean:.3}/255, {:.2} % of pixels off by more than 16/255",
            far * 100.0
        ));
    }
    assert!(!bad, "{}", report.join("\n"));
    println!("{}", report.join("\n"));
}

/// Image textures laid as POV-Ray's `image_map` `map_type 1` (spherical)
/// and `2` (cylindrical) (issue "the first hour": rayshell's longitude
/// ran the other way). POV-Ray takes the nearest texel, rayshell filters
/// them (over a few pixels at this size), so the pictures are compared
/// inside the texels' uniform areas: where POV-Ray's 5 × 5 neighbourhood
/// is one colour, ours must be that colour within 8/255 in at least 97 %
/// of the pixels (the longitude the other way agreed in 58 %).
pub fn image_mappings_match_povray() {
    if !povray_available() {
        crate::util::skip("povray is not installed (apt-get install povray)");
    }
    let dir = scratch("pov-mapping");
    let (ours, theirs) = (ours(&dir, "mapping", ""), theirs(&dir, "mapping"));
    let at = |img: &[u8], x: u32, y: u32| {
        let i = ((y * W + x) * 3) as usize;
        [img[i], img[i + 1], img[i + 2]]
    };
    let (mut uniform, mut agree) = (0, 0);
    for y in 2..H - 2 {
        for x in 2..W - 2 {
            let c = at(&theirs, x, y);
            if c == [0, 0, 0] {
                continue;
            }
            let same = (0..25).all(|k| at(&theirs, x + k % 5 - 2, y + k / 5 - 2) == c);
            if !same {
                continue;
            }
            uniform += 1;
            agree += at(&ours, x, y).iter().zip(c).all(|(a, b)| a.abs_diff(b) <= 8) as usize;
        }
    }
    let share = agree as f64 / uniform.max(1) as f64;
    println!("mapping: {agree} of {uniform} uniform pixels agree ({:.1} %)", share * 100.0);
    assert!(uniform > 2000, "only {uniform} uniform pixels");
    assert!(share >= 0.97, "{agree} of {uniform} uniform pixels agree");
}
