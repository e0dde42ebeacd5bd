//! Load arbitrary bytes as an OBJ file, place the mesh and render it at a
//! tiny resolution. Any panic is a bug; load errors are fine.
#![no_main]

use libfuzzer_sys::fuzz_target;
use rayshell::scene::{Builder, Scene};

fuzz_target!(|data: &[u8]| {
    let Ok(mesh) = rayshell::shell::obj::parse("fuzz.obj", data) else { return };
    let mut b = Builder::new();
    for flat in [false, true] {
        let _ = b.add_mesh(&mesh, 1.5, glam::DVec3::new(0.0, 0.0, -3.0), flat);
    }
    b.camera_resolution(8, 8).unwrap();
    b.add_light(rayshell::scene::Light::Point {
        color: glam::Vec3::ONE,
        pos: glam::DVec3::new(1.0, 2.0, 3.0),
    })
    .unwrap();
    if let Ok(scene) = Scene::freeze(&b) {
        let _ = rayshell::render::render(&scene, &rayshell::render::Job::default());
    }
});
