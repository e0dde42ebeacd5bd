//! Parse and evaluate arbitrary bytes as a script, scene commands included,
//! rendering at a tiny resolution. Any panic (or native stack overflow) is a
//! bug; Tcl errors are fine.
#![no_main]

use libfuzzer_sys::fuzz_target;
use rayshell::shell::{CaptureHost, Session};

fuzz_target!(|data: &[u8]| {
    // Images the script renders land in a scratch directory.
    static CHDIR: std::sync::Once = std::sync::Once::new();
    CHDIR.call_once(|| {
        let dir = std::env::temp_dir().join("rayshell-fuzz-out");
        std::fs::create_dir_all(&dir).unwrap();
        std::env::set_current_dir(&dir).unwrap();
        // Scripts may `open`, `file delete` and `cd`: fence every file
        // access into the scratch directory (`--safe`'s machinery).
        rayshell::shell::safe::confine(&dir).expect("the fence goes up");
    });
    let src = String::from_utf8_lossy(data).into_owned();
    // On the interpreter's own big stack, as in the program: `catch` and
    // `if` nest natively 12,000 deep (they are not levels, as in Tcl),
    // more than the fuzzer's main stack holds under ASan.
    rayshell::shell::on_big_stack(move || {
        let mut session = Session::new(Box::new(CaptureHost::default()));
        // Bound the work so an endless loop or a huge picture is not a hang.
        session.scene.borrow_mut().max_pixels = 16 * 16;
        session.interp.max_commands = Some(20_000);
        session.interp.max_depth = 200;
        // A coroutine runs on a stack of its own that ASan is not told
        // about (the generator switches stacks without ASan's fiber hooks),
        // so ASan reports false overflows there; valgrind's memcheck finds
        // nothing in those inputs. Coroutines are left out of this target.
        let _ = session.interp.eval_source("rename coroutine {}", None);
        let _ = session.interp.eval_source(&src, Some("fuzz.tsd"));
    })
    .expect("the interpreter thread ends normally");
});
