//! Parse and evaluate arbitrary bytes as a script, scene commands included.
//! Any panic (or native stack overflow) is a bug; Tcl errors are fine.
#![no_main]

use libfuzzer_sys::fuzz_target;
use rayshell::shell::{CaptureHost, new_interp};

fuzz_target!(|data: &[u8]| {
    let src = String::from_utf8_lossy(data);
    let mut interp = new_interp(Box::new(CaptureHost::default()));
    // Bound the work so an endless loop is not reported as a hang.
    interp.max_commands = Some(20_000);
    interp.max_depth = 200;
    let _ = interp.eval_source(&src, Some("fuzz.tsd"));
});
