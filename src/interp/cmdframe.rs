//! `info frame`: the evaluations in progress, as Tcl 8.6 keeps them in its
//! `CmdFrame` chain (TIP 280). Each unit of evaluation (a file, a proc
//! body, what `eval`, `uplevel`, `namespace eval` or a top-level `if` runs)
//! pushes one `CmdFrame`; the command it runs now is noted just before that
//! command is invoked, so the record costs a store per call, never per
//! inline command.
//!
//! Where lines are counted from follows Tcl's rules (TclEvalObjEx and
//! TclArgumentGet): a script given to `eval`, `catch`, `if` and the like
//! that is the very value of a literal word of the command running now
//! inherits that command's unit (a braced body in a file keeps the file's
//! absolute lines, one in a dynamic proc body its lines in that body); so
//! does one that is a literal word of a command in progress in a unit
//! evaluated directly (the main script's top level, the REPL), which is
//! also all `uplevel` looks at. Any other script counts its own lines
//! (`type eval`). A proc's body, or a lambda's, is located in its file when
//! it is a literal word of the command that defines it, running from a
//! file; otherwise its lines count from its own first (`type proc`).

use std::rc::Rc;
use std::sync::Arc;

use super::error::Exception;
use super::eval::Interp;
use super::parser::{Command, Script, Word};
use super::value::Value;

/// How a unit reports its lines.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum UnitKind {
    /// Absolute lines of a file.
    Source,
    /// A proc body's lines, counted from its first.
    Proc,
    /// A dynamic script's lines, counted from its first.
    Eval,
}

/// A unit's way of counting lines: its kind, the line relative lines
/// count from (`Proc`, `Eval`), and for `Source` its file and what to add
/// to its scripts' lines (a lambda's body counts from its own first).
#[derive(Clone)]
pub(crate) struct Unit {
    pub(crate) kind: UnitKind,
    pub(crate) first_line: u32,
    pub(crate) file: Option<Rc<str>>,
    pub(crate) shift: u32,
}

impl Unit {
    pub(crate) fn eval(first_line: u32) -> Unit {
        Unit { kind: UnitKind::Eval, first_line, file: None, shift: 0 }
    }

    /// A file's top level (or a script typed in, without a file).
    pub(crate) fn top(file: &Option<Rc<str>>) -> Unit {
        match file {
            Some(_) => Unit { kind: UnitKind::Source, first_line: 1, file: file.clone(), shift: 0 },
            None => Unit::eval(1),
        }
    }

    /// A proc body's unit: in its file when `in_file`, else its own.
    pub(crate) fn body(script: &Script, in_file: bool) -> Unit {
        let kind = if in_file && script.file.is_some() { UnitKind::Source } else { UnitKind::Proc };
        Unit { kind, first_line: script.true_first_line(), file: script.file.clone(), shift: 0 }
    }
}

/// A text a command was parsed from.
#[derive(Clone)]
pub(crate) enum Text {
    Local(Rc<str>),
    Shared(Arc<str>),
}

impl Text {
    pub(crate) fn as_str(&self) -> &str {
        match self {
            Text::Local(s) => s,
            Text::Shared(s) => s,
        }
    }
}

/// The command a unit is running.
pub(crate) enum At {
    /// Command `i` of a parsed script.
    Cmd(Rc<Script>, u32),
    /// A command the streaming evaluator parsed on its own, in its text.
    Loose(Rc<str>, Rc<Command>),
    /// A plain command of a window (no braces, so no literal scripts):
    /// its text, the command's byte range and its line.
    Plain(Text, u32, u32, u32),
}

impl At {
    fn words(&self) -> &[Word] {
        match self {
            At::Cmd(s, i) => &s.cmds[*i as usize].words,
            At::Loose(_, c) => &c.words,
            At::Plain(..) => &[],
        }
    }

    fn line(&self) -> u32 {
        match self {
            At::Cmd(s, i) => s.true_line(&s.cmds[*i as usize]),
            At::Loose(_, c) => c.line,
            At::Plain(_, _, _, line) => *line,
        }
    }

    /// The command's text as Tcl shows it (with the blanks before its
    /// terminator).
    fn text(&self) -> &str {
        match self {
            At::Cmd(s, i) => s.text(&s.cmds[*i as usize]),
            At::Loose(src, c) => with_blanks(src, c.start, c.end),
            At::Plain(t, start, end, _) => with_blanks(t.as_str(), *start, *end),
        }
    }
}

fn with_blanks(src: &str, start: u32, end: u32) -> &str {
    let end = end as usize;
    let blanks = src.as_bytes()[end..].iter().take_while(|&&c| c == b' ' || c == b'\t').count();
    &src[start as usize..end + blanks]
}

/// One evaluation in progress.
pub(crate) struct CmdFrame {
    /// The call frame (index into `Interp::frames`) it runs in: the
    /// innermost proc's, even under `uplevel`.
    pub(crate) frame: usize,
    /// How it counts lines; `None` for a compiled proc body, whose unit
    /// `frame`'s proc gives (so a call clones nothing for it).
    pub(crate) unit: Option<Unit>,
    pub(crate) at: Option<At>,
    /// Evaluated directly (Tcl's TclEvalEx): the literal words of its
    /// command in progress can be found from anywhere (`uplevel`).
    pub(crate) direct: bool,
    /// A proc's body (where Tcl compiles `foreach`, `switch` and the like
    /// inline, having the proc's local variables).
    pub(crate) proc_body: bool,
}

impl CmdFrame {
    fn has_literal(&self, v: &Value) -> bool {
        self.at
            .as_ref()
            .is_some_and(|at| at.words().iter().any(|w| matches!(w, Word::Lit(x) if x.ptr_eq(v))))
    }
}

impl Interp {
    /// Starts a unit (see the module doc); `end_unit_frame` ends it.
    #[inline]
    pub(crate) fn begin_unit(&mut self, unit: Unit) {
        let frame = self.frames.len() - 1;
        self.cmd_frames.push(CmdFrame {
            frame,
            unit: Some(unit),
            at: None,
            direct: false,
            proc_body: false,
        });
    }

    /// Starts the unit of the compiled body of the proc whose frame is on
    /// top.
    #[inline]
    pub(crate) fn begin_compiled_body_unit(&mut self) {
        const BODY: CmdFrame =
            CmdFrame { frame: 0, unit: None, at: None, direct: false, proc_body: true };
        let frame = self.frames.len() - 1;
        // A constant pushed, then its frame set: a record built on the
        // stack and copied in costs a store-forwarding stall per call.
        self.cmd_frames.push(BODY);
        if let Some(f) = self.cmd_frames.last_mut() {
            f.frame = frame;
        }
    }

    /// A unit's way of counting lines.
    fn unit_of_frame(&self, f: &CmdFrame) -> Unit {
        if let Some(u) = &f.unit {
            return u.clone();
        }
        match &self.frames[f.frame].proc {
            Some(p) => match &*p.compiled.borrow() {
                Some(c) => Unit::body(c.body.script(), p.in_file),
                None => Unit::body(&Interp::script_of(&p.body), p.in_file),
            },
            None => Unit::eval(1),
        }
    }

    /// Starts a proc body's unit.
    #[inline]
    pub(crate) fn begin_body_unit(&mut self, unit: Unit) {
        self.begin_unit(unit);
        if let Some(f) = self.cmd_frames.last_mut() {
            f.proc_body = true;
        }
    }

    /// Whether the current unit is a proc's body.
    #[inline]
    pub(crate) fn in_proc_body(&self) -> bool {
        self.cmd_frames.last().is_some_and(|f| f.proc_body)
    }

    /// Marks the current unit as evaluated directly (see `CmdFrame`).
    pub(crate) fn unit_is_direct(&mut self) {
        if let Some(f) = self.cmd_frames.last_mut() {
            f.direct = true;
        }
    }

    #[inline]
    pub(crate) fn end_unit_frame(&mut self) {
        self.cmd_frames.pop();
    }

    /// Notes that the current unit runs command `i` of `script` now (a
    /// compiled call site). The record is changed in place: the script
    /// is most often the one noted last, and a record built on the stack
    /// and copied in costs a store-forwarding stall on every call.
    #[inline]
    pub(crate) fn note_cmd(&mut self, script: &Rc<Script>, i: u32) {
        if let Some(f) = self.cmd_frames.last_mut() {
            match &mut f.at {
                Some(At::Cmd(s, j)) => {
                    if !Rc::ptr_eq(s, script) {
                        *s = script.clone();
                    }
                    *j = i;
                }
                at => *at = Some(At::Cmd(script.clone(), i)),
            }
        }
    }

    /// Notes the command the current unit runs now.
    #[inline]
    pub(crate) fn note_at(&mut self, at: At) {
        if let Some(f) = self.cmd_frames.last_mut() {
            f.at = Some(at);
        }
    }

    /// The command the current unit runs, taken out while an inline body
    /// runs (`put_at` puts it back).
    #[inline]
    pub(crate) fn take_at(&mut self) -> Option<At> {
        self.cmd_frames.last_mut().and_then(|f| f.at.take())
    }

    #[inline]
    pub(crate) fn put_at(&mut self, at: Option<At>) {
        if let Some(f) = self.cmd_frames.last_mut() {
            f.at = at;
        }
    }

    /// The unit a script value runs as (see the module doc): the current
    /// unit when it is a literal word of the command running now, else a
    /// direct unit's whose command in progress has it as a literal word,
    /// else one of its own.
    pub(crate) fn unit_of(&self, script: &Value, own_first_line: u32) -> Unit {
        match self.current_literal(script) {
            Some((f, _)) => self.unit_of_frame(f),
            None => self.registered_unit(script, own_first_line),
        }
    }

    /// The unit of a script `uplevel` runs: only a direct unit's literal
    /// words are known to it.
    pub(crate) fn registered_unit(&self, script: &Value, own_first_line: u32) -> Unit {
        let found = self.mine().iter().rev().find(|f| f.direct && f.has_literal(script));
        found.map_or_else(|| Unit::eval(own_first_line), |f| self.unit_of_frame(f))
    }

    /// The units a running coroutine sees (only its own, as in Tcl).
    fn mine(&self) -> &[CmdFrame] {
        &self.cmd_frames[self.coro_cmd_base.min(self.cmd_frames.len())..]
    }

    /// The current unit and its command, when `v` is a literal word of it.
    fn current_literal(&self, v: &Value) -> Option<(&CmdFrame, &At)> {
        let f = self.mine().last()?;
        let at = f.at.as_ref()?;
        f.has_literal(v).then_some((f, at))
    }

    /// Whether `v` is a literal word of the command running now.
    pub(crate) fn is_current_literal(&self, v: &Value) -> bool {
        self.current_literal(v).is_some()
    }

    /// Whether a proc body given as `body` is located in a file: it is a
    /// literal word of the `proc` command, which runs from a file.
    pub(crate) fn body_in_file(&self, body: &Value) -> bool {
        self.current_literal(body)
            .is_some_and(|(f, _)| self.unit_of_frame(f).kind == UnitKind::Source)
    }

    /// A lambda's unit (`apply`): in the file, its body's lines shifted to
    /// where the body sits, when the term is a literal word of a command
    /// running from a file; its own otherwise.
    pub(crate) fn lambda_unit(&self, term: &Value, body: &Value) -> Unit {
        let own = Unit { kind: UnitKind::Proc, first_line: 1, file: None, shift: 0 };
        let Some((f, at)) = self.current_literal(term) else { return own };
        let unit = self.unit_of_frame(f);
        if unit.kind != UnitKind::Source {
            return own;
        }
        // The term's line: the command's, plus the lines before the term
        // in its text; then the lines before the body in the term.
        let text = at.text();
        let term_s = term.as_str();
        let Some(at_term) = text.find(term_s) else { return own };
        let Some(at_body) = term_s.rfind(body.as_str()) else { return own };
        let newlines = |s: &str| s.bytes().filter(|&c| c == b'\n').count() as u32;
        let line =
            at.line() + unit.shift + newlines(&text[..at_term]) + newlines(&term_s[..at_body]);
        Unit { kind: UnitKind::Source, first_line: 1, file: unit.file, shift: line - 1 }
    }

    /// How many units are in progress (`info frame`).
    pub(crate) fn frame_count(&self) -> usize {
        self.cmd_frames.len()
    }

    /// `info frame N`: the unit N counts to (absolute when positive,
    /// relative to the current one otherwise), as Tcl describes it.
    pub(crate) fn frame_info(&self, spec: &Value) -> Result<Value, Exception> {
        let top = self.cmd_frames.len() as i64;
        let n = spec.as_int()?;
        if n > top || n <= -top {
            return Err(Exception::error(format!("bad level \"{}\"", spec.as_str()))
                .with_error_code(&format!("TCL LOOKUP LEVEL {}", spec.as_str())));
        }
        let idx = if n > 0 { n - 1 } else { top - 1 + n } as usize;
        let f = &self.cmd_frames[idx];
        let unit = self.unit_of_frame(f);
        let mut out: Vec<Value> = Vec::with_capacity(12);
        let mut pair = |k: &str, v: Value| {
            out.push(Value::from(k));
            out.push(v);
        };
        let (line, text) = match &f.at {
            Some(at) => (at.line(), at.text()),
            None => (unit.first_line, ""),
        };
        match unit.kind {
            UnitKind::Source => {
                pair("type", Value::from("source"));
                pair("line", Value::from_int(line as i64 + unit.shift as i64));
                let file = unit.file.as_deref().unwrap_or("");
                pair("file", Value::from(file));
            }
            kind => {
                pair("type", Value::from(if kind == UnitKind::Proc { "proc" } else { "eval" }));
                let rel = (line as i64 + 1 - unit.first_line as i64).max(1);
                pair("line", Value::from_int(rel));
            }
        }
        pair("cmd", Value::from(text));
        // The proc (or lambda) whose call frame it runs in.
        if let Some(p) = &self.frames[f.frame].proc {
            match &p.lambda {
                Some(term) => pair("lambda", term.clone()),
                None => pair("proc", Value::from_string(format!("::{}", p.name))),
            }
        }
        // Its level, when that frame is on the current chain of callers.
        let mut i = self.cur;
        for _ in 0..=self.frames.len() {
            if i == f.frame {
                let level = self.frames[self.cur].level - self.frames[f.frame].level;
                pair("level", Value::from_int(level as i64));
                break;
            }
            if i == 0 {
                break;
            }
            i = self.frames[i].caller;
        }
        Ok(Value::from_list(out))
    }
}
