//! `trace`: scripts run when a variable is read, written, unset or listed
//! with `array`, when a command is renamed or deleted, and around a
//! command's execution (`enter`, `leave`, and each command inside it with
//! `enterstep`/`leavestep`). Semantics follow Tcl 8.6's tclTrace.c: a
//! callback is the trace's script with the names and operation appended as
//! list elements, run in the frame of the access; the newest trace runs
//! first; traces on an array run before those on its element; while a
//! variable's traces run, that variable's traces are off; an error in a
//! read or write trace becomes the access's error (`can't set "x": ...`),
//! one in an unset trace is ignored; unsetting removes the traces.
//!
//! The evaluator pays one emptiness check per access while no trace
//! exists (`Interp::var_traces` / `exec_traces`).

use std::rc::Rc;

use rustc_hash::FxHashMap;

use super::{check_args, pick_option};
use crate::interp::error::{Code, Exception, TclResult};
use crate::interp::eval::{CommandKind, Interp, Var, VarCell, split_var_name};
use crate::interp::value::Value;

pub(crate) const COMMANDS: &[super::Entry] = &[(
    "trace",
    cmd_trace,
    "option ?arg ...?",
    "run scripts when variables or commands are used (add, remove, info)",
)];

/// Variable operations, as bits.
pub(crate) const READ: u8 = 1;
pub(crate) const WRITE: u8 = 2;
pub(crate) const UNSET: u8 = 4;
pub(crate) const ARRAY: u8 = 8;
/// Set on traces made with the old `trace variable` syntax (callbacks get
/// `r`, `w`, `u`, `a`).
const OLD_STYLE: u8 = 16;

pub(crate) struct VarTrace {
    ops: u8,
    cmd: Rc<str>,
    /// A trace on one element (`trace add variable a(k) ...`).
    elem: Option<Rc<str>>,
}

/// The traces on one variable, keyed in `Interp::var_traces` by the
/// address of its cell (which the entry keeps alive).
pub(crate) struct VarTraces {
    /// Keeps the cell alive, so its address (the key) is not reused.
    _cell: VarCell,
    /// Newest first.
    list: Vec<VarTrace>,
    /// Whether this variable's traces are running now.
    active: bool,
}

pub(crate) type VarTraceTable = FxHashMap<usize, VarTraces>;

fn key(cell: &VarCell) -> usize {
    Rc::as_ptr(cell) as usize
}

/// Command traces: rename/delete and execution.
const RENAME: u8 = 1;
const DELETE: u8 = 2;
const ENTER: u8 = 4;
const LEAVE: u8 = 8;
const ENTERSTEP: u8 = 16;
const LEAVESTEP: u8 = 32;

#[derive(Clone)]
pub(crate) struct CmdTrace {
    ops: u8,
    cmd: Rc<str>,
}

/// Traces on commands, by their table key; and the step traces of the
/// traced commands running now.
#[derive(Default)]
pub(crate) struct CmdTraces {
    by_cmd: FxHashMap<String, Vec<CmdTrace>>,
    steps: Vec<CmdTrace>,
    /// Whether an execution trace's script is running (traces are off
    /// inside one, as in Tcl).
    running: bool,
}

impl CmdTraces {
    #[inline]
    pub(crate) fn is_empty(&self) -> bool {
        self.by_cmd.is_empty() && self.steps.is_empty()
    }
}

fn op_name(op: u8, old_style: bool) -> &'static str {
    match (op, old_style) {
        (ARRAY, false) => "array",
        (READ, false) => "read",
        (WRITE, false) => "write",
        (UNSET, false) => "unset",
        (ARRAY, true) => "a",
        (READ, true) => "r",
        (WRITE, true) => "w",
        _ => "u",
    }
}

/// The traces in `list` that `op` on `elem` runs: the array-wide ones,
/// then the element's.
fn matching(list: &[VarTrace], elem: Option<&str>, op: u8) -> Vec<(u8, Rc<str>)> {
    let wide = list.iter().filter(|t| t.ops & op != 0 && t.elem.is_none());
    let own =
        list.iter().filter(|t| t.ops & op != 0 && t.elem.is_some() && t.elem.as_deref() == elem);
    wide.chain(own).map(|t| (t.ops, t.cmd.clone())).collect()
}

/// The callback script: the trace's command with list elements appended.
fn callback(cmd: &str, args: &[&str]) -> String {
    let mut s = cmd.to_string();
    for a in args {
        let v = Value::from(*a);
        s.push(' ');
        s.push_str(Value::from_list(vec![v]).as_str());
    }
    s
}

impl Interp {
    /// Runs the traces for `op` on the variable in `cell` (and on its
    /// element `elem`), as accessed under `name1`. An error in a read,
    /// write or array trace is the access's (`can't set "x": ...`).
    pub(crate) fn fire_var_traces(
        &mut self,
        cell: &VarCell,
        name1: &str,
        elem: Option<&str>,
        op: u8,
    ) -> Result<(), Exception> {
        let k = key(cell);
        let todo: Vec<(u8, Rc<str>)> = match self.var_traces.get_mut(&k) {
            // Element traces live on the array: none while it is none.
            _ if elem.is_some() && !matches!(*cell.borrow(), Var::Array(_)) => return Ok(()),
            Some(t) if !t.active => {
                let list = matching(&t.list, elem, op);
                if list.is_empty() {
                    return Ok(());
                }
                t.active = true;
                list
            }
            _ => return Ok(()),
        };
        let r = self.run_var_traces(k, &todo, name1, elem, op, true);
        if let Some(t) = self.var_traces.get_mut(&k) {
            t.active = false;
        }
        r
    }

    fn run_var_traces(
        &mut self,
        k: usize,
        todo: &[(u8, Rc<str>)],
        name1: &str,
        elem: Option<&str>,
        op: u8,
        attached: bool,
    ) -> Result<(), Exception> {
        for (ops, cmd) in todo {
            // A trace removed by an earlier one does not run.
            if attached
                && !self.var_traces.get(&k).is_some_and(|t| {
                    t.list.iter().any(|t| t.ops == *ops && Rc::ptr_eq(&t.cmd, cmd))
                })
            {
                continue;
            }
            let op_word = op_name(op, ops & OLD_STYLE != 0);
            let script = callback(cmd, &[name1, elem.unwrap_or(""), op_word]);
            let direct = std::mem::replace(&mut self.direct, true);
            let r = self.eval_str(&script);
            self.direct = direct;
            match r {
                Err(e) if matches!(e.code, Code::Exit(_)) => return Err(e),
                Err(e) if op != UNSET => {
                    let name = match elem {
                        Some(el) => format!("{name1}({el})"),
                        None => name1.to_string(),
                    };
                    let (verb, ty) = match op {
                        READ => ("read", "read"),
                        WRITE => ("set", "write"),
                        _ => ("trace array", "array"),
                    };
                    let mut err =
                        Exception::error(format!("can't {verb} \"{name}\": {}", e.value.as_str()));
                    err.error_code = e.error_code.clone();
                    err.trace = format!("{}\n    ({ty} trace on \"{name}\")", e.trace);
                    err.traced = true;
                    return Err(err);
                }
                _ => {}
            }
        }
        Ok(())
    }

    /// After an unset: the traces are taken off the variable (the
    /// element's only, for an element), then its unset traces run; they
    /// may set the variable again, and trace it anew.
    pub(crate) fn fire_unset_traces(&mut self, cell: &VarCell, name1: &str, elem: Option<&str>) {
        let k = key(cell);
        let Some(t) = self.var_traces.get_mut(&k) else { return };
        if elem.is_none() {
            // A whole array: its elements' unset traces first.
            let mut elems: Vec<Rc<str>> = t.list.iter().filter_map(|t| t.elem.clone()).collect();
            elems.dedup();
            for e in elems {
                let Some(t) = self.var_traces.get_mut(&k) else { return };
                let todo: Vec<(u8, Rc<str>)> = t
                    .list
                    .iter()
                    .filter(|t| t.ops & UNSET != 0 && t.elem.as_deref() == Some(&*e))
                    .map(|t| (t.ops, t.cmd.clone()))
                    .collect();
                t.list.retain(|t| t.elem.as_deref() != Some(&*e));
                let _ = self.run_var_traces(k, &todo, name1, Some(&e), UNSET, false);
            }
        }
        let Some(t) = self.var_traces.get_mut(&k) else { return };
        let todo = matching(&t.list, elem, UNSET);
        match elem {
            Some(e) => t.list.retain(|t| t.elem.as_deref() != Some(e)),
            None => t.list.clear(),
        }
        if t.list.is_empty() {
            self.var_traces.remove(&k);
        }
        let _ = self.run_var_traces(k, &todo, name1, elem, UNSET, false);
    }

    /// `incr` and `lappend` read the variable first: its read traces run.
    pub(crate) fn fire_read_traces_of(&mut self, name: &str) -> Result<(), Exception> {
        let (base, idx) = split_var_name(name);
        match self.find_var(base) {
            Some(cell) => self.traced_access(&cell, base, idx, READ),
            None => Ok(()),
        }
    }

    /// A proc frame about to go: its own variables that have traces.
    #[inline(never)]
    pub(crate) fn traced_locals(&self, frame: usize) -> Vec<(Rc<str>, VarCell)> {
        self.frames[frame]
            .cells()
            .filter(|(_, c)| self.var_traces.contains_key(&key(c)) && Rc::strong_count(c) <= 2)
            .map(|(n, c)| (n.clone(), c.clone()))
            .collect()
    }

    /// After a proc returned: the unset traces of its variables run, in
    /// its caller's frame.
    #[inline(never)]
    pub(crate) fn fire_frame_unset_traces(&mut self, dying: Vec<(Rc<str>, VarCell)>) {
        for (name, cell) in dying {
            *cell.borrow_mut() = Var::Undefined;
            self.fire_unset_traces(&cell, &name, None);
        }
    }

    /// `trace add variable` on a name: its cell, created undefined if need
    /// be (an array, for an element).
    fn add_var_trace(&mut self, name: &str, ops: u8, cmd: &str) -> Result<(), Exception> {
        let (base, elem) = split_var_name(name);
        let cell = self.var_cell(base);
        let cell = match &*cell.borrow() {
            Var::Elem(array, _) => array.clone(),
            _ => cell.clone(),
        };
        if elem.is_some() {
            let mut var = cell.borrow_mut();
            match &*var {
                Var::Undefined => *var = Var::Array(Default::default()),
                Var::Array(_) => {}
                _ => {
                    return Err(Exception::error(format!(
                        "can't trace \"{name}\": variable isn't array"
                    )));
                }
            }
        }
        let entry = self.var_traces.entry(key(&cell)).or_insert_with(|| VarTraces {
            _cell: cell.clone(),
            list: Vec::new(),
            active: false,
        });
        entry.list.insert(0, VarTrace { ops, cmd: Rc::from(cmd), elem: elem.map(Rc::from) });
        Ok(())
    }

    fn var_trace_entry(&mut self, name: &str) -> Option<(usize, Option<Rc<str>>)> {
        let (base, elem) = split_var_name(name);
        let cell = self.find_var(base)?;
        let k = key(&cell);
        self.var_traces.contains_key(&k).then(|| (k, elem.map(Rc::from)))
    }

    fn remove_var_trace(&mut self, name: &str, ops: u8, cmd: &str) {
        let Some((k, elem)) = self.var_trace_entry(name) else { return };
        let Some(t) = self.var_traces.get_mut(&k) else { return };
        if let Some(i) = t.list.iter().position(|t| {
            t.ops & !OLD_STYLE == ops & !OLD_STYLE && &*t.cmd == cmd && t.elem == elem
        }) {
            t.list.remove(i);
        }
        if t.list.is_empty() {
            self.var_traces.remove(&k);
        }
    }

    fn var_trace_info(&mut self, name: &str, old_style: bool) -> Value {
        let Some((k, elem)) = self.var_trace_entry(name) else { return Value::empty() };
        let list = &self.var_traces[&k].list;
        let items = list
            .iter()
            .filter(|t| t.elem == elem)
            .map(|t| {
                let ops: Vec<Value> = [ARRAY, READ, WRITE, UNSET]
                    .into_iter()
                    .filter(|op| t.ops & op != 0)
                    .map(|op| Value::from(op_name(op, old_style)))
                    .collect();
                let ops = if old_style {
                    Value::from_string(ops.iter().map(|v| v.as_str().to_string()).collect())
                } else {
                    Value::from_list(ops)
                };
                Value::from_list(vec![ops, Value::from(&*t.cmd)])
            })
            .collect();
        Value::from_list(items)
    }

    // -- Command traces -------------------------------------------------------

    /// A command replaced by a new definition: its delete traces run, and
    /// its traces go.
    pub(crate) fn fire_replace_traces(&mut self, key: &str) {
        if self.cmd_traces.by_cmd.contains_key(key) {
            self.fire_rename_traces(key, "");
        }
    }

    /// `rename`: the traces follow the command, and learn of it.
    pub(crate) fn fire_rename_traces(&mut self, old: &str, new: &str) {
        let Some(list) = self.cmd_traces.by_cmd.remove(old) else { return };
        let op = if new.is_empty() { DELETE } else { RENAME };
        if !new.is_empty() {
            self.cmd_traces.by_cmd.insert(new.to_string(), list.clone());
        }
        let qualified = |n: &str| if n.is_empty() { String::new() } else { format!("::{n}") };
        let (old_q, new_q) = (qualified(old), qualified(new));
        for t in list.iter().filter(|t| t.ops & op != 0) {
            let what = if op == DELETE { "delete" } else { "rename" };
            let script = callback(&t.cmd, &[&old_q, &new_q, what]);
            let _ = self.eval_str(&script);
        }
    }

    /// Runs a command under its execution traces and any step traces
    /// active now. An enter trace may delete or redefine the command: it
    /// is looked up again before it runs.
    #[inline(never)]
    pub(crate) fn invoke_traced(
        &mut self,
        key: Option<String>,
        argv: &[Value],
        cmd: &CommandKind,
    ) -> TclResult {
        if self.cmd_traces.running {
            return self.dispatch(cmd, argv);
        }
        let own: Vec<CmdTrace> = key
            .as_ref()
            .and_then(|k| self.cmd_traces.by_cmd.get(k))
            .map(|l| l.iter().filter(|t| t.ops & !(RENAME | DELETE) != 0).cloned().collect())
            .unwrap_or_default();
        let steps = self.cmd_traces.steps.clone();
        if own.is_empty() && steps.is_empty() {
            return self.dispatch(cmd, argv);
        }
        let key = key.unwrap_or_default();
        let command = Value::from_list(argv.to_vec());
        // The step traces of the procs around see this command first
        // (newest first), then its own enter traces run.
        for t in steps.iter().rev().filter(|t| t.ops & ENTERSTEP != 0) {
            self.run_exec_trace(None, t, &[command.as_str(), "enterstep"])?;
        }
        for t in own.iter().filter(|t| t.ops & ENTER != 0) {
            self.run_exec_trace(Some(&key), t, &[command.as_str(), "enter"])?;
        }
        let cmd = match self.resolve_command(argv[0].as_str()) {
            Some(c) => c.clone(),
            None => {
                return Err(Exception::error(format!(
                    "invalid command name \"{}\"",
                    argv[0].as_str()
                ))
                .with_error_code(&format!("TCL LOOKUP COMMAND {}", argv[0].as_str())));
            }
        };
        // Its own step traces, oldest at the bottom.
        let stepping: Vec<CmdTrace> =
            own.iter().rev().filter(|t| t.ops & (ENTERSTEP | LEAVESTEP) != 0).cloned().collect();
        let pushed = stepping.len();
        self.cmd_traces.steps.extend(stepping);
        let r = self.dispatch(&cmd, argv);
        let len = self.cmd_traces.steps.len();
        self.cmd_traces.steps.truncate(len - pushed.min(len));
        let (code, result) = match &r {
            Ok(v) => (0, v.clone()),
            Err(e) => (e.code.as_int(), e.value.clone()),
        };
        let code = code.to_string();
        for t in own.iter().rev().filter(|t| t.ops & LEAVE != 0) {
            self.run_exec_trace(
                Some(&key),
                t,
                &[command.as_str(), &code, result.as_str(), "leave"],
            )?;
        }
        for t in steps.iter().filter(|t| t.ops & LEAVESTEP != 0) {
            self.run_exec_trace(None, t, &[command.as_str(), &code, result.as_str(), "leavestep"])?;
        }
        r
    }

    /// Runs one execution trace, unless an earlier one removed it from
    /// the command `key`.
    fn run_exec_trace(
        &mut self,
        key: Option<&str>,
        t: &CmdTrace,
        args: &[&str],
    ) -> Result<(), Exception> {
        if let Some(k) = key
            && !self
                .cmd_traces
                .by_cmd
                .get(k)
                .is_some_and(|l| l.iter().any(|x| x.ops == t.ops && Rc::ptr_eq(&x.cmd, &t.cmd)))
        {
            return Ok(());
        }
        let script = callback(&t.cmd, args);
        self.cmd_traces.running = true;
        let r = self.eval_str(&script);
        self.cmd_traces.running = false;
        r.map(|_| ())
    }
}

/// An operation list: each name spelled out (Tcl takes no abbreviations
/// here).
fn parse_ops(list: &Value, names: &[(&'static str, u8)]) -> Result<u8, Exception> {
    let items = list.as_list()?;
    let mut choices: Vec<&str> = names.iter().map(|(n, _)| *n).collect();
    choices.sort_unstable();
    let must = match choices.as_slice() {
        [a, b] => format!("{a} or {b}"),
        [rest @ .., last] => format!("{}, or {last}", rest.join(", ")),
        [] => String::new(),
    };
    if items.is_empty() {
        return Err(Exception::error(format!(
            "bad operation list \"\": must be one or more of {must}"
        )));
    }
    let mut ops = 0;
    for it in items.iter() {
        match names.iter().find(|(n, _)| *n == it.as_str()) {
            Some((_, b)) => ops |= b,
            None => {
                return Err(Exception::error(format!(
                    "bad operation \"{}\": must be {must}",
                    it.as_str()
                )));
            }
        }
    }
    Ok(ops)
}

const VAR_OPS: &[(&str, u8)] =
    &[("array", ARRAY), ("read", READ), ("unset", UNSET), ("write", WRITE)];
const CMD_OPS: &[(&str, u8)] = &[("delete", DELETE), ("rename", RENAME)];
const EXEC_OPS: &[(&str, u8)] =
    &[("enter", ENTER), ("leave", LEAVE), ("enterstep", ENTERSTEP), ("leavestep", LEAVESTEP)];

/// Old-style ops: a string of the letters r, w, u, a.
fn parse_old_ops(s: &str) -> Result<u8, Exception> {
    let mut ops = OLD_STYLE;
    for c in s.chars() {
        ops |= match c {
            'r' => READ,
            'w' => WRITE,
            'u' => UNSET,
            'a' => ARRAY,
            _ => {
                return Err(Exception::error(format!(
                    "bad operations \"{s}\": should be one or more of rwua"
                )));
            }
        };
    }
    if ops == OLD_STYLE {
        return Err(Exception::error(format!(
            "bad operations \"{s}\": should be one or more of rwua"
        )));
    }
    Ok(ops)
}

fn cmd_trace(interp: &mut Interp, argv: &[Value]) -> TclResult {
    check_args(argv, 2, usize::MAX, "option ?arg ...?")?;
    let sub = pick_option(
        argv[1].as_str(),
        &["add", "info", "remove", "variable", "vdelete", "vinfo"],
        "option",
    )?;
    match sub {
        "variable" | "vdelete" => {
            check_args(argv, 5, 5, "variable name ops command")
                .map_err(|_| Exception::wrong_args(&format!("trace {sub} name ops command")))?;
            let ops = parse_old_ops(argv[3].as_str())?;
            if sub == "variable" {
                interp.add_var_trace(argv[2].as_str(), ops, argv[4].as_str())?;
            } else {
                interp.remove_var_trace(argv[2].as_str(), ops, argv[4].as_str());
            }
            Ok(Value::empty())
        }
        "vinfo" => {
            if argv.len() != 3 {
                return Err(Exception::wrong_args("trace vinfo name"));
            }
            Ok(interp.var_trace_info(argv[2].as_str(), true))
        }
        _ => {
            if argv.len() < 3 {
                return Err(Exception::wrong_args(&if sub == "info" {
                    "trace info type name".to_string()
                } else {
                    format!("trace {sub} type ?arg ...?")
                }));
            }
            let ty =
                pick_option(argv[2].as_str(), &["command", "execution", "variable"], "option")?;
            if sub == "info" {
                if argv.len() != 4 {
                    return Err(Exception::wrong_args(&format!("trace info {ty} name")));
                }
                return Ok(match ty {
                    "variable" => interp.var_trace_info(argv[3].as_str(), false),
                    _ => cmd_trace_info(interp, ty, argv[3].as_str())?,
                });
            }
            if argv.len() != 6 {
                return Err(Exception::wrong_args(&format!(
                    "trace {sub} {ty} name opList command"
                )));
            }
            let (name, cmd) = (argv[3].as_str(), argv[5].as_str());
            match ty {
                "variable" => {
                    let ops = parse_ops(&argv[4], VAR_OPS)?;
                    if sub == "add" {
                        interp.add_var_trace(name, ops, cmd)?;
                    } else {
                        interp.remove_var_trace(name, ops, cmd);
                    }
                }
                _ => {
                    let table = if ty == "command" { CMD_OPS } else { EXEC_OPS };
                    let ops = parse_ops(&argv[4], table)?;
                    let key = interp.command_key(name).ok_or_else(|| {
                        Exception::error(format!("unknown command \"{name}\""))
                            .with_error_code(&format!("TCL LOOKUP COMMAND {name}"))
                    })?;
                    let list = interp.cmd_traces.by_cmd.entry(key.clone()).or_default();
                    if sub == "add" {
                        list.insert(0, CmdTrace { ops, cmd: Rc::from(cmd) });
                    } else if let Some(i) = list.iter().position(|t| t.ops == ops && &*t.cmd == cmd)
                    {
                        list.remove(i);
                    }
                    if list.is_empty() {
                        interp.cmd_traces.by_cmd.remove(&key);
                    }
                }
            }
            Ok(Value::empty())
        }
    }
}

fn cmd_trace_info(interp: &Interp, ty: &str, name: &str) -> TclResult {
    let key = interp.command_key(name).ok_or_else(|| {
        Exception::error(format!("unknown command \"{name}\""))
            .with_error_code(&format!("TCL LOOKUP COMMAND {name}"))
    })?;
    let table = if ty == "command" { CMD_OPS } else { EXEC_OPS };
    let items = interp
        .cmd_traces
        .by_cmd
        .get(&key)
        .into_iter()
        .flatten()
        .filter(|t| table.iter().any(|(_, b)| t.ops & b != 0))
        .map(|t| {
            let ops: Vec<Value> = table
                .iter()
                .filter(|(_, b)| t.ops & b != 0)
                .map(|(n, _)| Value::from(*n))
                .collect();
            Value::from_list(vec![Value::from_list(ops), Value::from(&*t.cmd)])
        })
        .collect();
    Ok(Value::from_list(items))
}
