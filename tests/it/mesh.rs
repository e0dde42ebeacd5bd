//! The `mesh` command: OBJ files placed in the scene, and bad files.

use crate::util::{raytrace, text};

fn temp_dir(tag: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("rayshell-mesh-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

const QUAD: &str = "# a unit quad as one polygon, plus a comment and unsupported lines\n\
mtllib nothing.mtl\nv -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nvt 0 0\ng quad\nf 1/1 2/1 3/1 4/1\n";

pub fn mesh_is_placed_and_lit() {
    let dir = temp_dir("ok");
    std::fs::write(dir.join("quad.obj"), QUAD).unwrap();
    let script = "puts [mesh quad.obj -scale 2 -translate 0 0 -5]\n\
        camera_resolution 5 5\nambient_light 1 1 1\nmaterial 0 1 0 1 0 0 1 0 1\n\
        puts [mesh quad.obj -flat -translate 10 0 0]\n\
        puts [scene_bounds]\nputs [vertex 0 0 0]\nrender out.ppm\n";
    let r = raytrace().arg("-c").arg(script).current_dir(&dir).output().unwrap();
    assert_eq!(r.status.code(), Some(0), "{}", text(&r.stderr));
    // A mesh's positions stay out of the script's vertex pool: the first
    // `vertex` after it is still number 0.
    assert_eq!(text(&r.stdout), "2\n2\n-2.0 -2.0 -5.0 11.0 2.0 0.0\n0\n");
    let (_, _, rgb) =
        rayshell::image::read_ppm(&std::fs::read(dir.join("out.ppm")).unwrap()).unwrap();
    // The centre pixel sees the first quad, made with the default white material.
    assert_eq!(&rgb[12 * 3..12 * 3 + 3], &[51, 51, 51]);
    let _ = std::fs::remove_dir_all(&dir);
}

pub fn smooth_normals_are_computed_when_missing() {
    let dir = temp_dir("smooth");
    // A tent: two triangles meeting at a ridge along y.
    std::fs::write(dir.join("tent.obj"), "v -1 -1 0\nv 0 -1 1\nv 0 1 1\nv -1 1 0\nv 1 -1 0\nv 1 1 0\nf 1 2 3\nf 1 3 4\nf 2 5 6\nf 2 6 3\n").unwrap();
    let render = |flat: &str| {
        let s = format!(
            "camera_from 0 0 5\ncamera_resolution 21 3\nparallel_light 1 1 1 -1 0 -1\nmesh tent.obj {flat}\nrender {}.ppm\n",
            if flat.is_empty() { "smooth" } else { "flat" }
        );
        let r = raytrace().arg("-c").arg(s).current_dir(&dir).output().unwrap();
        assert_eq!(r.status.code(), Some(0), "{}", text(&r.stderr));
    };
    render("");
    render("-flat");
    let read = |n: &str| rayshell::image::read_ppm(&std::fs::read(dir.join(n)).unwrap()).unwrap().2;
    let (smooth, flat) = (read("smooth.ppm"), read("flat.ppm"));
    // Flat shading gives each face one value; smooth shading varies along the row.
    let row = |img: &[u8]| (0..21).map(|x| img[(21 + x) * 3]).collect::<Vec<u8>>();
    let distinct = |r: Vec<u8>| {
        let mut r = r;
        r.sort();
        r.dedup();
        r.len()
    };
    assert!(
        distinct(row(&smooth)) > distinct(row(&flat)),
        "{:?} vs {:?}",
        row(&smooth),
        row(&flat)
    );
    let _ = std::fs::remove_dir_all(&dir);
}

pub fn bad_obj_files_are_located_errors() {
    let dir = temp_dir("bad");
    let cases: &[(&str, &str)] = &[
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 x\n", "bad.obj:4: bad OBJ line \"f 1 2 x\""),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n", "bad.obj:4: bad OBJ line \"f 1 2 9\""),
        ("v 0 0 zero\nf 1 1 1\n", "bad.obj:1: bad OBJ line \"v 0 0 zero\""),
        ("v 0 0 0\n", "bad.obj: the file has no faces"),
        // Found by fuzzing: tobj multiplied an out-of-range relative normal
        // index and overflowed (a panic in debug builds).
        (
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//-12 3//1\n",
            "bad.obj:5: bad OBJ line \"f 1//1 2//-12 3//1\"",
        ),
        (
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/99999999999999999999 3/1\n",
            "bad.obj:5: bad OBJ line",
        ),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/1/1/1 2 3\n", "bad.obj:4: bad OBJ line"),
        ("v 0 0 0\nv 1 0 0\nf 1 2\n", "bad.obj:3: bad OBJ line \"f 1 2\""),
        // Found by fuzzing: tobj reads `l` lines' indices as a face's too.
        (
            "v 1 -1 0\nv 1 0 0\nv 0 1 2\nvn 0 0 1\nvt 0 0\nl 1/-11 -2 1 -1\nf 1 2 3\n",
            "bad.obj:6: bad OBJ line \"l 1/-11 -2 1 -1\"",
        ),
        ("\u{0}\u{1}binary garbage\u{ff}", "bad.obj"),
    ];
    for (obj, want) in cases {
        std::fs::write(dir.join("bad.obj"), obj).unwrap();
        std::fs::write(dir.join("s.tsd"), "puts hi\nmesh bad.obj\n").unwrap();
        let r = raytrace().arg("s.tsd").current_dir(&dir).output().unwrap();
        let err = text(&r.stderr);
        assert_eq!(r.status.code(), Some(1), "{obj:?}: {err}");
        assert!(err.starts_with(&format!("s.tsd:2: {want}")), "{obj:?}: {err}");
    }
    let r = raytrace().arg("-c").arg("mesh nope.obj").current_dir(&dir).output().unwrap();
    assert!(text(&r.stderr).contains("couldn't read \"nope.obj\": no such file or directory"));
    let r = raytrace().arg("-c").arg("mesh x.obj -scale").current_dir(&dir).output().unwrap();
    assert!(text(&r.stderr).contains(
        "wrong # args: should be \"mesh fileName ?-scale s? ?-translate x y z? ?-subdivide n? ?-flat?\""
    ));
    let _ = std::fs::remove_dir_all(&dir);
}

/// The bunny the sample scene uses loads from the repository, compressed,
/// with every triangle; and, when `../shared/models` is there, the plain
/// OBJ it was compressed from gives the same count.
pub fn bundled_bunny_loads() {
    let root = crate::util::root();
    let bundled = root.join("tsd/models/stanford-bunny.obj.gz");
    let script = format!("puts [mesh {{{}}}]", bundled.display());
    let r = raytrace().arg("-c").arg(script).output().unwrap();
    assert_eq!(text(&r.stdout), "69451\n", "{}", text(&r.stderr));
    let bunny = root.join("../shared/models/stanford-bunny.obj");
    if !bunny.exists() {
        crate::util::skip(format!("{} is absent (the bundled copy loaded)", bunny.display()));
    }
    let script = format!("puts [mesh {{{}}}]", bunny.display());
    let r = raytrace().arg("-c").arg(script).output().unwrap();
    assert_eq!(text(&r.stdout), "69451\n", "{}", text(&r.stderr));
}

/// The OBJ reader's single pass (`obj::parse_fast`) reads the real meshes
/// (the bundled bunny and, when `../shared/models` is there, those the
/// benchmarks use) and makes of each the mesh tobj makes, bit for bit.
pub fn obj_readers_agree_on_real_models() {
    use rayshell::scene::MeshData;
    use rayshell::shell::obj;
    let bits = |m: &MeshData| {
        let v3 = |v: &[glam::Vec3]| -> Vec<[u32; 3]> {
            v.iter().map(|p| p.to_array().map(f32::to_bits)).collect()
        };
        let uv: Vec<[u32; 2]> = m.uvs.iter().map(|t| t.map(f32::to_bits)).collect();
        (
            v3(&m.positions),
            v3(&m.normals),
            uv,
            m.tris.clone(),
            m.normal_tris.clone(),
            m.uv_tris.clone(),
        )
    };
    let root = crate::util::root();
    let bundled = root.join("tsd/models/stanford-bunny.obj.gz");
    let bundled = bundled.to_str().unwrap();
    let (ours, tobj) = (obj::load(bundled).unwrap(), obj::load_with_tobj(bundled).unwrap());
    assert_eq!(ours.tris.len(), 69451);
    assert!(bits(&ours) == bits(&tobj), "{bundled}");
    let dir = root.join("../shared/models");
    let Ok(entries) = std::fs::read_dir(&dir) else {
        crate::util::skip(format!("{} is absent (the bundled bunny agreed)", dir.display()));
    };
    let mut files: Vec<_> = entries
        .filter_map(|e| Some(e.ok()?.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "obj"))
        .collect();
    files.sort();
    assert!(files.len() >= 5, "{files:?}");
    for f in files {
        let bytes = std::fs::read(&f).unwrap();
        let fast =
            obj::parse_fast(&bytes).unwrap_or_else(|| panic!("{}: left to tobj", f.display()));
        let tobj = obj::parse_with_tobj("m.obj", &bytes).unwrap();
        assert!(!fast.tris.is_empty());
        assert!(bits(&fast) == bits(&tobj), "{}", f.display());
    }
}
