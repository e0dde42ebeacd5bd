//! The interactive shell (rustyline): a `% ` prompt, history kept across
//! sessions, continuation lines while braces, brackets or quotes are open,
//! tab completion of command names. Errors are printed and the session
//! (variables, procs, the scene) survives.

use std::borrow::Cow;
use std::path::PathBuf;

use rustyline::completion::{Completer, Pair};
use rustyline::error::ReadlineError;
use rustyline::highlight::Highlighter;
use rustyline::hint::Hinter;
use rustyline::history::DefaultHistory;
use rustyline::validate::{ValidationContext, ValidationResult, Validator};
use rustyline::{Context, Editor, Helper};

use crate::interp::{Code, Interp, is_complete};

struct ShellHelper {
    names: Vec<String>,
}

impl Completer for ShellHelper {
    type Candidate = Pair;

    fn complete(
        &self,
        line: &str,
        pos: usize,
        _: &Context<'_>,
    ) -> rustyline::Result<(usize, Vec<Pair>)> {
        let start = line[..pos]
            .rfind(|c: char| c.is_whitespace() || matches!(c, '[' | ';' | '{'))
            .map(|i| i + 1)
            .unwrap_or(0);
        let word = &line[start..pos];
        let pairs = self
            .names
            .iter()
            .filter(|n| n.starts_with(word))
            .map(|n| Pair { display: n.clone(), replacement: n.clone() })
            .collect();
        Ok((start, pairs))
    }
}

impl Hinter for ShellHelper {
    type Hint = String;
}

impl Highlighter for ShellHelper {
    fn highlight_prompt<'b, 's: 'b, 'p: 'b>(
        &'s self,
        prompt: &'p str,
        _default: bool,
    ) -> Cow<'b, str> {
        Cow::Borrowed(prompt)
    }
}

impl Validator for ShellHelper {
    fn validate(&self, ctx: &mut ValidationContext<'_>) -> rustyline::Result<ValidationResult> {
        Ok(if is_complete(ctx.input()) {
            ValidationResult::Valid(None)
        } else {
            ValidationResult::Incomplete
        })
    }
}

impl Helper for ShellHelper {}

fn history_path() -> Option<PathBuf> {
    let base = std::env::var_os("XDG_DATA_HOME")
        .map(PathBuf::from)
        .or_else(|| std::env::var_os("HOME").map(|h| PathBuf::from(h).join(".local/share")))?;
    let dir = base.join("rayshell");
    std::fs::create_dir_all(&dir).ok()?;
    Some(dir.join("history"))
}

/// What the REPL shows after one input.
#[derive(Debug, PartialEq, Eq)]
pub enum Reply {
    /// A non-empty result, printed as tclsh does.
    Result(String),
    Nothing,
    /// An error message (the session goes on).
    Error(String),
    /// `exit N`.
    Exit(i32),
}

/// Evaluates one complete input as the REPL does: whatever happens, the
/// interpreter, its variables, procs and the scene stay usable.
pub fn eval_line(interp: &mut Interp, line: &str) -> Reply {
    let r = interp.eval_source(line, None);
    interp.flush();
    // Ctrl-C stopped this command (a render, a loop); the session goes on.
    super::feedback::INTERRUPTED.store(false, std::sync::atomic::Ordering::SeqCst);
    let shown = |v: &crate::interp::Value| match v.as_str() {
        "" => Reply::Nothing,
        s => Reply::Result(s.to_string()),
    };
    match r {
        Ok(v) => shown(&v),
        Err(e) => match e.code {
            Code::Exit(n) => Reply::Exit(n),
            Code::Error => Reply::Error(e.message().to_string()),
            Code::Return => shown(&e.value),
            Code::Break | Code::Continue => {
                let w = if e.code == Code::Break { "break" } else { "continue" };
                Reply::Error(format!("invoked \"{w}\" outside of a loop"))
            }
        },
    }
}

/// Runs the REPL until Ctrl-D or `exit`; returns the exit code.
pub fn run(interp: &mut Interp) -> i32 {
    let config =
        rustyline::Config::builder().completion_type(rustyline::CompletionType::List).build();
    let mut rl: Editor<ShellHelper, DefaultHistory> = match Editor::with_config(config) {
        Ok(r) => r,
        Err(e) => {
            eprintln!("raytrace: cannot start the interactive shell: {e}");
            return 1;
        }
    };
    rl.set_helper(Some(ShellHelper { names: Vec::new() }));
    let history = history_path();
    if let Some(h) = &history {
        let _ = rl.load_history(h);
    }
    println!("rayshell {} — type `help` for commands, Ctrl-D to quit", env!("CARGO_PKG_VERSION"));
    let mut code = 0;
    loop {
        if let Some(h) = rl.helper_mut() {
            h.names = interp.command_names();
        }
        match rl.readline("% ") {
            Ok(line) => {
                if line.trim().is_empty() {
                    continue;
                }
                let _ = rl.add_history_entry(line.as_str());
                match eval_line(interp, &line) {
                    Reply::Result(v) => println!("{v}"),
                    Reply::Nothing => {}
                    Reply::Error(msg) => eprintln!("{msg}"),
                    Reply::Exit(n) => {
                        code = n;
                        break;
                    }
                }
            }
            Err(ReadlineError::Interrupted) => continue,
            Err(ReadlineError::Eof) => break,
            Err(e) => {
                eprintln!("raytrace: {e}");
                code = 1;
                break;
            }
        }
    }
    if let Some(h) = &history {
        let _ = rl.save_history(h);
    }
    interp.flush();
    code
}
