//! Command-line arguments (clap). Unknown options are errors that list the
//! valid ones.

use std::path::PathBuf;

use clap::Parser;

#[derive(Parser, Debug)]
#[command(
    name = "raytrace",
    version,
    about = "A ray tracer driven by a Tcl-style scene language",
    after_help = "Examples:\n  raytrace tsd/teapot.tsd teapot.ppm   run a scene, render it to a file\n  raytrace anim.tsd                    run a script (it calls render itself)\n  raytrace                             interactive shell\n  raytrace -c 'puts [expr {2**10}]'    run a string\n  raytrace script.tsd -- a b c         pass arguments ($argv)"
)]
pub struct Cli {
    /// The script to run (a .tsd scene is a Tcl script).
    pub script: Option<PathBuf>,
    /// Render the final scene into this file (.ppm or .png) after the script.
    pub output: Option<PathBuf>,
    /// Run this script text instead of a file.
    #[arg(short = 'c', long = "command", value_name = "SCRIPT", conflicts_with = "script")]
    pub command: Option<String>,
    /// Render with N threads (default: all cores). The picture is the same
    /// for any N.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u16).range(1..=1024))]
    pub threads: Option<u16>,
    /// After each render, print timings, ray counts, Mrays/s and memory to stderr.
    #[arg(long)]
    pub stats: bool,
    /// Arguments for the script, after `--` (`$argv`, `$argc`).
    #[arg(last = true)]
    pub args: Vec<String>,
}

/// Parses `std::env::args`; on error or `--help` prints and returns the exit code.
pub fn parse() -> Result<Cli, u8> {
    match Cli::try_parse() {
        Ok(c) => Ok(c),
        Err(e) => {
            let _ = e.print();
            Err(if e.use_stderr() { 2 } else { 0 })
        }
    }
}
