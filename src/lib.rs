//! rayshell: a ray tracer driven by a Tcl-style scene language.
//!
//! # Codemap
//!
//! - `interp`: a Tcl 8.6-compatible interpreter (parser, values, `expr`,
//!   builtins). It knows nothing about graphics.
//! - `scene`: the scene `Builder` the commands change (vertices, normals,
//!   triangles). It knows nothing about the interpreter.
//! - `shell`: the glue and the only module that touches files, the terminal,
//!   the environment and exit codes: command-line arguments, the REPL, the
//!   scene commands registered into the interpreter.
//!
//! # Invariants
//!
//! - `interp` never imports anything else from this crate; `scene` never
//!   imports `interp` or `shell`.
//! - No input makes the program panic: bad scripts are `Exception`s with a
//!   file and line.

pub mod geometry;
pub mod image;
pub mod interp;
pub mod render;
pub mod scene;
pub mod shell;
