//! Command-line arguments (clap). Unknown options are errors that list the
//! valid ones.

use std::path::PathBuf;

use clap::Parser;

use super::feedback::ProgressMode;

#[derive(Parser, Debug)]
#[command(
    name = "raytrace",
    version,
    about = "A ray tracer driven by a Tcl-style scene language",
    after_help = "Examples:\n  raytrace tsd/teapot.tsd teapot.ppm   run a scene, render it to a file\n  raytrace anim.tsd                    run a script (it calls render itself)\n  raytrace                             interactive shell\n  raytrace -c 'puts [expr {2**10}]'    run a string\n  raytrace script.tsd -- a b c         pass arguments ($argv)"
)]
pub struct Cli {
    /// The script to run (a .tsd scene is a Tcl script; `-` reads it from
    /// standard input).
    pub script: Option<PathBuf>,
    /// Render the final scene into this file (.png, .ppm or .pfm) after the script.
    pub output: Option<PathBuf>,
    /// Run this script text instead of a file (`-c SCRIPT OUTPUT` renders
    /// the final scene into OUTPUT).
    #[arg(short = 'c', long = "command", value_name = "SCRIPT")]
    pub command: Option<String>,
    /// Render with N threads (default: all cores). The picture is the same
    /// for any N.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u16).range(1..=1024))]
    pub threads: Option<u16>,
    /// After each render, print timings, ray counts, Mrays/s and memory to stderr.
    #[arg(long)]
    pub stats: bool,
    /// How to report progress on stderr [auto: a bar on a terminal, else a
    /// plain line per batch frame].
    #[arg(long, value_enum, value_name = "MODE", default_value_t = ProgressMode::Auto)]
    pub progress: ProgressMode,
    /// No progress output at all (same as --progress none).
    #[arg(short, long)]
    pub quiet: bool,
    /// Trace in coarse-to-fine passes (the same final picture).
    #[arg(long)]
    pub progressive: bool,
    /// Show renders in a window as they are traced (needs the `preview` feature).
    #[arg(long)]
    pub preview: bool,
    /// Render only pixels x0..x1, y0..y1 (exclusive ends) of each picture;
    /// the file records where the region goes, for --merge.
    #[arg(long, num_args = 4, value_names = ["X0", "Y0", "X1", "Y1"])]
    pub crop: Option<Vec<u32>>,
    /// Assemble cropped renders (PARTs) into the full picture OUT.
    #[arg(long, num_args = 2.., value_names = ["OUT", "PART"], conflicts_with_all = ["script", "command"])]
    pub merge: Option<Vec<PathBuf>>,
    /// Join pictures (FRAMEs, in order) into the animated PNG OUT.
    #[arg(long, num_args = 2.., value_names = ["OUT", "FRAME"], conflicts_with_all = ["script", "command", "merge"])]
    pub movie: Option<Vec<PathBuf>>,
    /// Frames a second for --movie.
    #[arg(long, default_value_t = 24, value_parser = clap::value_parser!(u16).range(1..=1000))]
    pub fps: u16,
    /// Animation batch: run the script once per frame (fresh interpreter and
    /// scene, `$frame` set) and render each frame into OUTPUT with its number
    /// (`#` runs or a printf `%0Nd` in OUTPUT; default SCRIPT-####.png, or
    /// only what the script renders itself).
    #[arg(long, value_name = "FIRST..LAST", value_parser = parse_frames)]
    pub frames: Option<(i64, i64)>,
    /// Every Nth frame of --frames.
    #[arg(long, value_name = "N", default_value_t = 1, requires = "frames",
          value_parser = clap::value_parser!(u32).range(1..))]
    pub step: u32,
    /// Render only the frames of shard I of N (frames at positions I, I+N, ...).
    #[arg(long, value_name = "I/N", requires = "frames", value_parser = parse_shard)]
    pub shard: Option<(usize, usize)>,
    /// Leave frames whose output file already exists (reruns are idempotent).
    #[arg(long, requires = "frames")]
    pub skip_existing: bool,
    /// Change the noise pattern of sampled renders (and nothing else); the
    /// script's `seed` command changes it too, independently.
    #[arg(long, value_name = "N", default_value_t = 0)]
    pub seed: u64,
    /// Sampled renders: keep adding samples to a pixel until its relative
    /// standard error is below X (up to `adaptive`'s maximum, else 1024).
    #[arg(long, value_name = "X", value_parser = parse_noise_target)]
    pub noise_target: Option<f32>,
    /// Memory the run may use: 512M, 2G, 50% (of physical memory). Growth
    /// past it is a script error, never a crash [default: 75% of physical
    /// memory, and at most half of what `ulimit -v` leaves].
    #[arg(long, value_name = "SIZE", value_parser = super::budget::parse_size)]
    pub max_memory: Option<u64>,
    /// Run an untrusted scene (docs/safe.md): reads only beneath the
    /// scene's directory and --allow-read DIRs; `render` writes only the
    /// output, or new pictures beside it, never through a link; no other
    /// writes, no `cd`, no programs, no environment.
    #[arg(long)]
    pub safe: bool,
    /// End the run after SECONDS of wall-clock time, as Ctrl-C would, but
    /// with status 124 (as timeout(1)): for untrusted scenes on a farm.
    #[arg(long, value_name = "SECONDS", value_parser = parse_seconds)]
    pub time_limit: Option<f64>,
    /// With --safe, a directory the scene may also read (repeatable).
    #[arg(long, value_name = "DIR", requires = "safe")]
    pub allow_read: Vec<PathBuf>,
    /// Print a completion script for SHELL (bash, zsh, fish, elvish,
    /// powershell) and exit: `raytrace --completions bash >
    /// ~/.local/share/bash-completion/completions/raytrace`.
    #[arg(long, value_name = "SHELL")]
    pub completions: Option<clap_complete::Shell>,
    /// Arguments for the script, after `--` (`$argv`, `$argc`).
    #[arg(last = true)]
    pub args: Vec<String>,
}

fn parse_seconds(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(x) if x > 0.0 && x < 1e9 => Ok(x),
        _ => Err(format!("expected a number of seconds above 0, got \"{s}\"")),
    }
}

/// Parses `std::env::args`; on error or `--help` prints and returns the exit code.
pub fn parse() -> Result<Cli, u8> {
    match Cli::try_parse() {
        Ok(c) => Ok(c),
        Err(e) if e.kind() == clap::error::ErrorKind::UnknownArgument => {
            say!("{}", unknown_option(&e));
            Err(2)
        }
        Err(e) => {
            let _ = e.print();
            Err(if e.use_stderr() { 2 } else { 0 })
        }
    }
}

/// The message for an unknown option: what was given, the likely one, and
/// every valid option. (clap's own advice to write `-- --x` is wrong here:
/// `--` passes arguments to the script.)
fn unknown_option(e: &clap::Error) -> String {
    use clap::error::{ContextKind, ContextValue};
    let given = match e.get(ContextKind::InvalidArg) {
        Some(ContextValue::String(s)) => s.clone(),
        _ => "?".into(),
    };
    let mut msg = format!("raytrace: unknown option \"{given}\"");
    if let Some(v) = e.get(ContextKind::SuggestedArg) {
        let s = match v {
            ContextValue::String(s) => s.clone(),
            ContextValue::Strings(v) => v.join(", "),
            _ => String::new(),
        };
        if !s.is_empty() {
            msg.push_str(&format!(" (did you mean {s}?)"));
        }
    }
    msg.push_str("; the options are:\n  ");
    msg.push_str(&options().join(" "));
    msg.push_str("\n(`raytrace --help` explains them; arguments after `--` go to the script)");
    msg
}

/// Every option, as `--long` (with `-s` for those with a short form).
pub fn options() -> Vec<String> {
    use clap::CommandFactory;
    let cmd = Cli::command();
    let mut v: Vec<String> = cmd
        .get_arguments()
        .filter(|a| !a.is_positional())
        .filter_map(|a| {
            let long = a.get_long().map(|l| format!("--{l}"));
            match (a.get_short(), long) {
                (Some(s), Some(l)) => Some(format!("-{s}/{l}")),
                (None, Some(l)) => Some(l),
                (Some(s), None) => Some(format!("-{s}")),
                (None, None) => None,
            }
        })
        .collect();
    v.push("--help".into());
    v.push("--version".into());
    v
}

/// `FIRST..LAST` (inclusive), or a single frame number.
fn parse_frames(s: &str) -> Result<(i64, i64), String> {
    let bad = || format!("expected FIRST..LAST (e.g. 0..239), got \"{s}\"");
    let (a, b) = match s.split_once("..") {
        Some((a, b)) => (a, b),
        None => (s, s),
    };
    let a: i64 = a.trim().parse().map_err(|_| bad())?;
    let b: i64 = b.trim().parse().map_err(|_| bad())?;
    if b < a {
        return Err(format!("the last frame {b} comes before the first {a}"));
    }
    if b - a > 10_000_000 {
        return Err("more than 10,000,000 frames".into());
    }
    Ok((a, b))
}

/// `I/N` with I < N.
fn parse_shard(s: &str) -> Result<(usize, usize), String> {
    let bad = || format!("expected I/N with 0 <= I < N (e.g. 0/4), got \"{s}\"");
    let (i, n) = s.split_once('/').ok_or_else(bad)?;
    let (i, n): (usize, usize) =
        (i.trim().parse().map_err(|_| bad())?, n.trim().parse().map_err(|_| bad())?);
    if n == 0 || i >= n {
        return Err(bad());
    }
    Ok((i, n))
}

fn parse_noise_target(s: &str) -> Result<f32, String> {
    match s.parse::<f32>() {
        Ok(x) if x > 0.0 && x.is_finite() => Ok(x),
        _ => Err(format!("expected a number above 0, got \"{s}\"")),
    }
}
