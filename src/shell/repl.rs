//! The interactive shell (rustyline): a `% ` prompt, history kept across
//! sessions, continuation lines while braces, brackets or quotes are open,
//! tab completion of command names, `$variables`, subcommands, options and
//! file names. Errors are printed (and left in `errorInfo` and `errorCode`,
//! as tclsh does) and the session (variables, procs, the scene) survives.

use std::borrow::Cow;
use std::path::PathBuf;

use rustyline::completion::{Completer, Pair};
use rustyline::error::ReadlineError;
use rustyline::highlight::Highlighter;
use rustyline::hint::Hinter;
use rustyline::history::DefaultHistory;
use rustyline::validate::{ValidationContext, ValidationResult, Validator};
use rustyline::{Context, Editor, Helper};

use std::sync::atomic::Ordering;

use super::feedback::IN_REPL;
use crate::interp::{Code, Interp, is_complete};

struct ShellHelper {
    names: Vec<String>,
    vars: Vec<String>,
    files: rustyline::completion::FilenameCompleter,
}

/// The subcommands offered after a command's name: the interpreter's
/// ensembles, and the shell's own.
fn subcommands(command: &str) -> Option<&'static [&'static str]> {
    crate::interp::subcommands(command).or(match command {
        "preview" => Some(&["on", "off", "term"]),
        _ => None,
    })
}

/// Options offered after these commands' names, for a word that starts
/// with `-`.
const OPTIONS: &[(&str, &[&str])] = &[
    ("render", &["-heatmap", "-progressive", "-srgb"]),
    ("mesh", &["-flat", "-scale", "-translate"]),
    ("raybench", &["-brute", "-shadow", "-threads"]),
];

/// Commands whose arguments are file names.
const FILE_COMMANDS: &[&str] = &["source", "mesh", "render"];

/// What completing the word that ends at `pos` offers: where the word
/// starts and the candidates. Not file names (see `ShellHelper`), which
/// it signals with `None`.
pub fn candidates(
    line: &str,
    pos: usize,
    commands: &[String],
    vars: &[String],
) -> Option<(usize, Vec<String>)> {
    let before = &line[..pos];
    let start = before
        .rfind(|c: char| c.is_whitespace() || matches!(c, '[' | ';' | '{' | '"'))
        .map(|i| i + 1)
        .unwrap_or(0);
    let word = &before[start..];
    // `$name`: the variables.
    if let Some(dollar) = word.rfind('$') {
        let name = &word[dollar + 1..];
        let found = vars.iter().filter(|v| v.starts_with(name)).map(|v| format!("${v}"));
        return Some((start + dollar, found.collect()));
    }
    // The words of the command being typed, before this one.
    let cmd_start = before[..start].rfind(['[', ';', '\n']).map(|i| i + 1).unwrap_or(0);
    let words: Vec<&str> = before[cmd_start..start].split_whitespace().collect();
    let Some(&command) = words.first() else {
        let found = commands.iter().filter(|n| n.starts_with(word)).cloned();
        return Some((start, found.collect()));
    };
    let from = |list: &[&str]| -> Vec<String> {
        list.iter().filter(|s| s.starts_with(word)).map(|s| s.to_string()).collect()
    };
    if word.starts_with('-')
        && let Some((_, opts)) = OPTIONS.iter().find(|(c, _)| *c == command)
    {
        return Some((start, from(opts)));
    }
    if words.len() == 1
        && let Some(subs) = subcommands(command)
    {
        return Some((start, from(subs)));
    }
    if FILE_COMMANDS.contains(&command) || words.last() == Some(&">") {
        return None;
    }
    Some((start, Vec::new()))
}

impl Completer for ShellHelper {
    type Candidate = Pair;

    fn complete(
        &self,
        line: &str,
        pos: usize,
        ctx: &Context<'_>,
    ) -> rustyline::Result<(usize, Vec<Pair>)> {
        match candidates(line, pos, &self.names, &self.vars) {
            Some((start, found)) => Ok((
                start,
                found.into_iter().map(|n| Pair { display: n.clone(), replacement: n }).collect(),
            )),
            None => self.files.complete(line, pos, ctx),
        }
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
            Code::Error => {
                // As tclsh does after an uncaught error.
                let _ = interp.set_var("::errorInfo", crate::interp::Value::from(e.error_info()));
                let _ = interp.set_var("::errorCode", e.error_code());
                match super::did_you_mean(interp, &e) {
                    Some(hint) => Reply::Error(format!("{} ({hint})", e.message())),
                    None => Reply::Error(e.message().to_string()),
                }
            }
            // `return -code error` at the prompt is an error, as in tclsh.
            Code::Return if e.return_code == Some(Code::Error) => {
                Reply::Error(e.value.as_str().to_string())
            }
            Code::Return => shown(&e.value),
            Code::Other(n) => Reply::Error(format!("command returned bad code: {n}")),
            Code::Break | Code::Continue => {
                let w = if e.code == Code::Break { "break" } else { "continue" };
                Reply::Error(format!("invoked \"{w}\" outside of a loop"))
            }
        },
    }
}

/// Runs the REPL until Ctrl-D or `exit`; returns the exit code. Time spent
/// waiting for typing is left out of `state`'s parse time.
pub fn run(interp: &mut Interp, state: &std::cell::RefCell<super::stats::ShellState>) -> i32 {
    super::feedback::REPL_SESSION.store(true, Ordering::SeqCst);
    let _ = interp.set_var("::tcl_interactive", crate::interp::Value::from("1"));
    let config =
        rustyline::Config::builder().completion_type(rustyline::CompletionType::List).build();
    let mut rl: Editor<ShellHelper, DefaultHistory> = match Editor::with_config(config) {
        Ok(r) => r,
        Err(e) => {
            say!("raytrace: cannot start the interactive shell: {e}");
            return 1;
        }
    };
    rl.set_helper(Some(ShellHelper {
        names: Vec::new(),
        vars: Vec::new(),
        files: rustyline::completion::FilenameCompleter::new(),
    }));
    let history = history_path();
    if let Some(h) = &history {
        let _ = rl.load_history(h);
    }
    show_line!("rayshell {} — type `help` for commands, Ctrl-D to quit", env!("CARGO_PKG_VERSION"));
    let mut code = 0;
    let mut bad_input = 0;
    loop {
        if let Some(h) = rl.helper_mut() {
            h.names = interp.command_names();
            h.vars = interp
                .eval_str("info globals")
                .and_then(|v| v.as_list())
                .map(|l| l.iter().map(|v| v.as_str().to_string()).collect())
                .unwrap_or_default();
        }
        let waiting = std::time::Instant::now();
        let read = rl.readline("% ");
        state.borrow_mut().since_last += waiting.elapsed();
        match read {
            Ok(line) => {
                bad_input = 0;
                if line.trim().is_empty() {
                    continue;
                }
                let _ = rl.add_history_entry(line.as_str());
                // A Ctrl-C at the prompt (a terminal in line mode sends it
                // as a signal) was for the line being typed, not this one.
                super::feedback::INTERRUPTED.store(false, Ordering::SeqCst);
                IN_REPL.store(true, Ordering::SeqCst);
                let reply = eval_line(interp, &line);
                IN_REPL.store(false, Ordering::SeqCst);
                match reply {
                    Reply::Result(v) => show_line!("{v}"),
                    Reply::Nothing => {}
                    // The terminal echoed `^C` where the cursor was: the
                    // message goes on a line of its own.
                    Reply::Error(msg) if msg == "interrupted" => say!("\n{msg}"),
                    Reply::Error(msg) => say!("{msg}"),
                    Reply::Exit(n) => {
                        code = n;
                        break;
                    }
                }
            }
            Err(ReadlineError::Interrupted) => continue,
            Err(ReadlineError::Eof) => break,
            // Bytes that are not UTF-8 (`caf\xe9` typed in Latin-1): the
            // line is lost, the session is not. Only a stream of nothing
            // else (a binary file on stdin) ends it.
            Err(ReadlineError::Io(e))
                if e.kind() == std::io::ErrorKind::InvalidData && bad_input < 100 =>
            {
                bad_input += 1;
                say!("raytrace: that line was not UTF-8 text; it was dropped");
                continue;
            }
            Err(e) => {
                say!("raytrace: {e}");
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

#[cfg(test)]
mod tests {
    use super::candidates;

    fn offer(line: &str) -> Option<(usize, Vec<String>)> {
        let commands: Vec<String> = ["render", "rename", "sphere", "string", "source"]
            .iter()
            .map(|s| s.to_string())
            .collect();
        let vars: Vec<String> = ["radius", "rows", "x"].iter().map(|s| s.to_string()).collect();
        candidates(line, line.len(), &commands, &vars)
    }

    #[test]
    fn completes_what_the_word_can_be() {
        assert_eq!(offer("ren"), Some((0, vec!["render".into(), "rename".into()])));
        assert_eq!(offer("sphere 0 $r"), Some((9, vec!["$radius".into(), "$rows".into()])));
        assert_eq!(offer("puts \"at $x"), Some((9, vec!["$x".into()])));
        assert_eq!(
            offer("string to"),
            Some((7, vec!["tolower".into(), "totitle".into(), "toupper".into()]))
        );
        assert_eq!(offer("render -s"), Some((7, vec!["-srgb".into()])));
        assert_eq!(offer("set a [sph"), Some((7, vec!["sphere".into()])));
        // File names: rustyline's file completer takes over.
        assert_eq!(offer("source sc"), None);
        assert_eq!(offer("render out"), None);
        assert_eq!(offer("puts hi > ou"), None);
        // Nothing sensible to offer for a plain argument.
        assert_eq!(offer("sphere 0 "), Some((9, vec![])));
    }
}
