//! rayshell: a ray tracer driven by a Tcl-style scene language.
//!
//! # Codemap
//!
//! - `interp`: a Tcl 8.6-compatible interpreter (parser, values, `expr`,
//!   builtins). It knows nothing about graphics.
//! - `shell`: the glue and the only module that touches files, the terminal,
//!   the environment and exit codes: command-line arguments, the REPL, the
//!   scene commands registered into the interpreter.
//!
//! # Invariants
//!
//! - `interp` never imports anything else from this crate.
//! - No input makes the program panic: bad scripts are `Exception`s with a
//!   file and line.

pub mod interp;
pub mod shell;
