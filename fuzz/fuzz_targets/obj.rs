//! Load arbitrary bytes as an OBJ file, place the mesh and render it at a
//! tiny resolution. Any panic is a bug; load errors are fine. Where the
//! single-pass reader reads the bytes, tobj must make the same mesh of
//! them, bit for bit.
#![no_main]

use libfuzzer_sys::fuzz_target;
use rayshell::scene::{Builder, MeshData, Scene};
use rayshell::shell::obj;

/// A mesh's values, bit for bit.
fn bits(m: &MeshData) -> Vec<u32> {
    let mut out: Vec<u32> = m.positions.iter().chain(&m.normals).flat_map(|p| p.to_array().map(f32::to_bits)).collect();
    out.extend(m.uvs.iter().flat_map(|t| t.map(f32::to_bits)));
    for tris in [Some(&m.tris), m.normal_tris.as_ref(), m.uv_tris.as_ref()] {
        out.push(u32::MAX);
        out.extend(tris.into_iter().flatten().flatten());
    }
    out
}

fuzz_target!(|data: &[u8]| {
    if let Some(fast) = obj::parse_fast(data) {
        let tobj = obj::parse_with_tobj("fuzz.obj", data).expect("tobj reads what Fast reads");
        assert!(bits(&fast) == bits(&tobj), "Fast and tobj differ");
    }
    let Ok(mesh) = obj::parse("fuzz.obj", data) else { return };
    let mut b = Builder::new();
    for flat in [false, true] {
        let _ = b.add_mesh(&mesh, 1.5, glam::DVec3::new(0.0, 0.0, -3.0), flat);
    }
    b.camera_resolution(8, 8).unwrap();
    b.add_light(rayshell::scene::Light::Point {
        color: glam::Vec3::ONE,
        pos: glam::DVec3::new(1.0, 2.0, 3.0),
        falloff: rayshell::scene::Falloff::INVERSE_SQUARE,
    })
    .unwrap();
    if let Ok(scene) = Scene::freeze(&b) {
        let _ = rayshell::render::render(&scene, &rayshell::render::Job::default());
    }
});
