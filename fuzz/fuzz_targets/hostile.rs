//! Scripts under hostile conditions: a small memory budget (8 to 64 MiB
//! over what the fuzzer holds), Ctrl-C at a moment the input chooses
//! (`shell::INTERRUPTED`, which stops the interpreter and renders), and a
//! prelude of extreme materials and tiny or huge geometry. Any panic,
//! abort or stack overflow is a bug; Tcl errors are fine.
#![no_main]

use std::sync::atomic::Ordering;
use std::time::Duration;

use libfuzzer_sys::fuzz_target;
use rayshell::shell::{CaptureHost, INTERRUPTED, Session};

const PRELUDES: [&str; 14] = [
    "",
    // Ks + T > 1 at depth 64 through glass: the ray tree doubles per bounce.
    "trace_depth 64; material 1 1 1 0 0 0.5 1 1 1.5\n\
     for {set i 0} {$i < 8} {incr i} { sphere 0 0 [expr {-$i * 2.5}] 1 }",
    // A mirror too small for single precision.
    "material 1 1 1 0 0 1 1 0 1; sphere 0 0 -1e-30 1e-31",
    // Far away and huge.
    "camera_from 1e30 0 0; camera_target 0 0 0; sphere 0 0 0 1e29",
    // The largest index of refraction, and the smallest.
    "material 1 1 1 0.2 0.8 0 1 0.9 100; sphere 0 0 -5 1\n\
     material 1 1 1 0 0 0 1 1 0.01; sphere 0 0 -3 0.5",
    // A triangle near 1e20, seen from beside it.
    "camera_from 1e20 1e20 1e20; camera_target 1e20 1e20 0\n\
     tri [vertex 1e20 1e20 -5] [vertex [expr {1e20+1e5}] 1e20 -5] [vertex 1e20 [expr {1e20+1e5}] -5]",
    // Coincident glass and mirror spheres.
    "material 1 1 1 0 0 0.5 1 0.5 1.5; sphere 0 0 -4 1; sphere 0 0 -4 1\n\
     material 1 1 1 0 0 1 1 0 1; sphere 0 0 -4 1",
    // The smallest and largest spheres.
    "sphere 0 0 -5 1e-38; sphere 1e37 0 0 1e37",
    // Sampling: many samples, a wide Mitchell filter, a lens, adaptive.
    "samples 9; filter mitchell 4; camera_aperture 0.3; camera_focus 2; adaptive 0.001 64\n\
     sphere 0 0 -4 1",
    // Lights with a size, tiny and huge, inside a sphere light.
    "area_light 5 5 5 -1 3 -1 2 0 0 0 0 2 8; sphere_light 1 1 1 0 0 -4 2 3\n\
     area_light 1 1 1 0 0 0 1e-18 0 0 0 1e-18 0 1; sphere 0 0 -4 1",
    // Shapes at the extremes: a huge and a tiny torus, a needle cone, deep
    // fractals, a nearly singular transform, CSG of them, moving.
    "motion 1e3 0 0; shutter 0 1; torus 1e30 1e29; torus 1e-30 1e-31\n\
     cone 0 0 -5 1e-20 0 0 -4 0; transform { scale 1e-20 1 1; box -1 -1 -6 1 1 -5 }\n\
     sphereflake 0 0 -4 1 10; menger 2 0 -6 1 10; plane 0 1 0 -1e30\n\
     csg difference { torus 1 0.5; blob 0.1 { blob_sphere 0 0 0 1e10 1 } }",
    // Instances of instances, transformed and moving.
    "group a { sphere 0 0 0 1; disk 0 0 0 0 1 0 2 1 }\n\
     for {set i 0} {$i < 31} {incr i} { group a [list transform {rotate 10 20 30; instance a}] }\n\
     motion 0 1 0; shutter 0 1e9; instance a",
    // Path tracing at the extremes: glowing and gaining surfaces (Ks + T
    // above 1), emitters too small and too bright, a tiny sky map.
    "integrator path; trace_depth 64; samples 4; environment 1e30 0 1e-30\n\
     material 1 1 1 0 1 1 1 1 1.5; emission 1e30 1e30 1e30; sphere 0 0 -4 1\n\
     emission 1 1 1; tri [vertex 0 0 -3] [vertex 1e-30 0 -3] [vertex 0 1e-30 -3]\n\
     motion 0 1 0; shutter 0 1; sphere 0 0 -6 1e-20; emission 0 0 0\n\
     group g { emission 2 2 2; box -1 -1 -1 1 1 1 }; instance g",
    "integrator path; area_light 5 5 5 -1 3 -1 2 0 0 0 0 2 8; sphere_light 1 1 1 0 0 -4 2 3\n\
     spot_light 1 1 1 0 5 0 0 -1 0 10 20; parallel_light 1 1 1 0 -1 0\n\
     highlight ward 0.01 1; material 1 1 1 0 0.5 0.5 1e4 0 1; plane 0 1 0 -1; sphere 0 0 -4 1",
];

fuzz_target!(|data: &[u8]| {
    let Some((&head, rest)) = data.split_first() else { return };
    static CHDIR: std::sync::Once = std::sync::Once::new();
    CHDIR.call_once(|| {
        let dir = std::env::temp_dir().join("rayshell-fuzz-out");
        std::fs::create_dir_all(&dir).unwrap();
        std::env::set_current_dir(&dir).unwrap();
        // File commands stay inside the scratch directory (see script.rs).
        rayshell::shell::safe::confine(&dir).expect("the fence goes up");
    });
    let prelude = PRELUDES[(head as usize + rest.len()) % PRELUDES.len()];
    let src = format!(
        "camera_resolution 8 8; point_light 1 1 1 0 5 5\n{prelude}\n{}\nrender fuzz.png\n",
        String::from_utf8_lossy(rest)
    );
    rayshell::mem::set_budget(rayshell::mem::in_use() + ((8 << 20) << (head >> 6)));
    INTERRUPTED.store(false, Ordering::SeqCst);
    // Ctrl-C after 0 to 7 ms.
    let ctrl_c = (head & 0x20 != 0).then(|| {
        let ms = (head >> 3 & 3) as u64 * 2 + (rest.len() % 2) as u64;
        std::thread::spawn(move || {
            std::thread::sleep(Duration::from_millis(ms));
            INTERRUPTED.store(true, Ordering::SeqCst);
        })
    });
    // On the interpreter's own big stack, as in the program.
    rayshell::shell::on_big_stack(move || {
        let mut session = Session::new(Box::new(CaptureHost::default()));
        session.scene.borrow_mut().max_pixels = 16 * 16;
        session.interp.max_commands = Some(20_000);
        session.interp.interrupt = Some(&INTERRUPTED);
        let _ = session.interp.eval_source(&src, Some("fuzz.tsd"));
    })
    .expect("no panic");
    if let Some(t) = ctrl_c {
        let _ = t.join();
    }
    INTERRUPTED.store(false, Ordering::SeqCst);
    rayshell::mem::set_budget(usize::MAX);
});
