//! `Interp`: evaluation, variables and call frames, the command table and
//! procs. Commands are plain functions over `&[Value]`; the host (the shell)
//! adds its own commands as closures and supplies I/O through `Host`, so
//! this module does no I/O of its own and knows nothing of graphics.

use std::borrow::Cow;
use std::cell::RefCell;
use std::collections::BTreeMap;
use std::rc::Rc;

use indexmap::IndexMap;
use rustc_hash::FxHashMap;
use smallvec::SmallVec;

use super::cmdframe::{At, Unit};
use super::compile::{self, CompiledProc, Outcome};
use super::error::{Code, Exception, Loc, TclResult};
use super::expr::{self, Expr, Operand};
use super::number::Num;
use super::parser::{Command, Part, Script, VarName, Word};
use super::value::{self, Rep, Value};

pub type NativeFn = fn(&mut Interp, &[Value]) -> TclResult;
pub type HostFn = Rc<dyn Fn(&mut Interp, &[Value]) -> TclResult>;
/// A command whose arguments are all numbers: it can be called without
/// building values at all (the fast path for long generated meshes).
/// It returns a number or nothing (the empty string).
pub type NumericFn = Rc<dyn Fn(&mut Interp, &[Num]) -> Result<Option<Num>, Exception>>;

/// Nested command invocations allowed before "too many nested evaluations",
/// counted as Tcl 8.6 counts them (`interp recursionlimit`): each call of
/// a proc or of a command Tcl does not compile inline (`eval`, `uplevel`,
/// `puts`...) is a level; `if`, `while`, `catch`, `[...]` are not.
pub const DEFAULT_MAX_DEPTH: usize = 1000;
/// The deepest the evaluator itself may recurse (commands, substitutions
/// and expressions, whether Tcl counts them or not), which the interpreter
/// thread's stack must hold.
pub const MAX_NATIVE_DEPTH: usize = 12_000;

/// The commands Tcl 8.6 compiles to bytecode (they run inline and are not
/// a nesting level): tclBasic.c's `builtInCmds` with a compile procedure.
const INLINE: &[&str] = &[
    "append",
    "array",
    "break",
    "catch",
    "concat",
    "continue",
    "dict",
    "error",
    "expr",
    "for",
    "foreach",
    "format",
    "global",
    "if",
    "incr",
    "info",
    "join",
    "lappend",
    "lassign",
    "lindex",
    "linsert",
    "list",
    "llength",
    "lmap",
    "lrange",
    "lreplace",
    "lset",
    "namespace",
    "regexp",
    "regsub",
    "return",
    "set",
    "string",
    "subst",
    "switch",
    "tailcall",
    "throw",
    "try",
    "unset",
    "upvar",
    "variable",
    "while",
    "yield",
];
/// The largest string or list the interpreter builds (bytes or elements).
pub const MAX_VALUE_LEN: usize = 1 << 30;

pub(crate) enum CommandKind {
    /// A builtin, and whether Tcl runs it inline (not a level; `INLINE`).
    Native(NativeFn, bool),
    Host(HostFn),
    Numeric(usize, Rc<str>, NumericFn),
    Proc(Rc<Proc>),
}

// By hand, to be inlined: a call site clones its cached command per call.
impl Clone for CommandKind {
    #[inline]
    fn clone(&self) -> Self {
        match self {
            CommandKind::Native(f, inline) => CommandKind::Native(*f, *inline),
            CommandKind::Host(f) => CommandKind::Host(f.clone()),
            CommandKind::Numeric(n, usage, f) => CommandKind::Numeric(*n, usage.clone(), f.clone()),
            CommandKind::Proc(p) => CommandKind::Proc(p.clone()),
        }
    }
}

pub struct Proc {
    pub(crate) name: String,
    pub(crate) params: Vec<(Rc<str>, Option<Value>)>,
    pub(crate) variadic: bool,
    pub(crate) body: Value,
    pub(crate) arg_spec: Value,
    /// For `apply`: the lambda term (named in usage and traces).
    pub(crate) lambda: Option<Value>,
    /// The namespace it runs in.
    pub(crate) ns: Rc<str>,
    /// Its compiled body, made at the first call (`compile.rs`).
    pub(crate) compiled: RefCell<Option<Rc<CompiledProc>>>,
    /// Whether its body was a literal word in a file when it was defined
    /// (`info frame` then gives the file's lines; see `cmdframe.rs`).
    pub(crate) in_file: bool,
}

/// What the interpreter needs from the outside world.
/// What a script asks of a file, for the host's policy.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Access {
    Read,
    Write,
    /// Deleting, renaming, making directories, changing directory,
    /// running programs.
    Modify,
    /// An image the host writes for the script (`render`).
    Image,
    /// Running a program (`exec`, `open |cmd`): the path is its name.
    Run,
}

/// A host's file policy: `Err(message)` refuses.
pub type FsPolicy = Box<dyn Fn(&str, Access) -> Result<(), String>>;

pub trait Host {
    fn stdout(&mut self, s: &str) -> std::io::Result<()>;
    fn stderr(&mut self, s: &str) -> std::io::Result<()>;
    fn read_file(&mut self, path: &str) -> std::io::Result<String>;
    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

pub(crate) enum Var {
    Undefined,
    Scalar(Value),
    Array(ArrayMap),
    /// `upvar a(k) e`: `e` stands for element `k` of the array in the cell.
    Elem(VarCell, Rc<str>),
}

/// Follows an element link: a plain name that is `upvar`ed to an array
/// element means that element.
#[inline]
fn deref_elem<'a>(cell: VarCell, idx: Option<&'a str>) -> (VarCell, Option<Cow<'a, str>>) {
    let target = match (&*cell.borrow(), idx) {
        (Var::Elem(array, key), None) => Some((array.clone(), key.clone())),
        _ => None,
    };
    match target {
        Some((array, key)) => (array, Some(Cow::Owned(key.to_string()))),
        None => (cell, idx.map(Cow::Borrowed)),
    }
}

pub(crate) type VarCell = Rc<RefCell<Var>>;
/// An array's elements (in the order they were made; `array names` sorts
/// them into Tcl's hash order itself).
pub(crate) type ArrayMap = IndexMap<String, Value, rustc_hash::FxBuildHasher>;
pub(crate) type VarMap = IndexMap<Rc<str>, VarCell, rustc_hash::FxBuildHasher>;

/// What proc calls reuse instead of allocating: argument vectors and
/// slot arrays of frames that have returned.
#[derive(Default)]
pub(crate) struct Pools {
    objv: Vec<Vec<Value>>,
    slots: Vec<Vec<Slot>>,
}

impl Pools {
    const MAX: usize = 256;

    /// Takes back what a returned frame held.
    fn recycle(&mut self, mut f: Frame) {
        f.slots.clear();
        if self.slots.len() < Self::MAX {
            self.slots.push(std::mem::take(&mut f.slots));
        }
        if self.objv.len() < Self::MAX && f.objv.capacity() <= 64 {
            f.objv.clear();
            self.objv.push(std::mem::take(&mut f.objv));
        }
    }
}

/// A compiled proc's local variable, held in its frame's slot array
/// (`compile.rs`): the value itself while only compiled code reaches it,
/// numbers unboxed; a shared cell once anything else does.
pub(crate) enum Slot {
    /// The variable does not exist.
    Empty,
    /// A scalar whose value is this integer (or double), with no string
    /// yet: its string would be the canonical one.
    Int(i64),
    Dbl(f64),
    /// A scalar's value.
    Val(Value),
    /// The variable reached by name too (a lookup, `upvar`, `global`, a
    /// trace): the cell is the variable from then on.
    Cell(VarCell),
}

impl Slot {
    /// The variable as a shareable cell (made one now, for good), or
    /// `None` when it does not exist.
    fn promote(&mut self) -> Option<VarCell> {
        let var = match std::mem::replace(self, Slot::Empty) {
            Slot::Empty => return None,
            Slot::Cell(c) => {
                *self = Slot::Cell(c.clone());
                return Some(c);
            }
            Slot::Int(i) => Var::Scalar(Value::from_int(i)),
            Slot::Dbl(d) => Var::Scalar(Value::from_f64(d)),
            Slot::Val(v) => Var::Scalar(v),
        };
        let c = Rc::new(RefCell::new(var));
        *self = Slot::Cell(c.clone());
        Some(c)
    }

    /// Whether the variable exists with a value (not only declared).
    fn is_defined(&self) -> bool {
        match self {
            Slot::Empty => false,
            Slot::Cell(c) => !matches!(*c.borrow(), Var::Undefined),
            _ => true,
        }
    }
}

/// A frame's variables by name, and its links.
#[derive(Default)]
struct Named {
    vars: VarMap,
    links: Vec<Rc<str>>,
}

pub(crate) struct Frame {
    /// The namespace code in this frame runs in.
    pub(crate) ns: Rc<str>,
    /// Variables by name and links, when the frame has any (boxed: a
    /// compiled proc's frame rarely does).
    named: Option<Box<Named>>,
    pub(crate) level: usize,
    /// Index of the frame whose variables the caller saw (for `upvar 1`).
    pub(crate) caller: usize,
    pub(crate) objv: Vec<Value>,
    /// A compiled proc's locals (`compile.rs`): `slots[i]` holds the
    /// variable named `names[i]`, so compiled code reaches it by index;
    /// every other name lives in `vars`.
    pub(crate) names: Option<Rc<[Rc<str>]>>,
    pub(crate) slots: Vec<Slot>,
    /// The proc (or lambda) this is a call of.
    pub(crate) proc: Option<Rc<Proc>>,
}

impl Frame {
    pub(crate) fn new(ns: Rc<str>, level: usize, caller: usize, objv: Vec<Value>) -> Frame {
        Frame { ns, named: None, level, caller, objv, names: None, slots: Vec::new(), proc: None }
    }

    /// The variables known by name (not compiled locals), in the order
    /// they were made (`info vars` in a proc lists them so).
    pub(crate) fn vars(&self) -> Option<&VarMap> {
        self.named.as_ref().map(|n| &n.vars)
    }

    pub(crate) fn vars_mut(&mut self) -> &mut VarMap {
        &mut self.named.get_or_insert_with(Default::default).vars
    }

    /// Names made links by `upvar`, `global` or `variable` (which `info
    /// locals` leaves out).
    pub(crate) fn links(&self) -> &[Rc<str>] {
        self.named.as_ref().map_or(&[], |n| &n.links)
    }

    pub(crate) fn add_link(&mut self, name: Rc<str>) {
        self.named.get_or_insert_with(Default::default).links.push(name);
    }

    #[inline]
    fn slot_of(&self, name: &str) -> Option<usize> {
        self.names.as_ref()?.iter().position(|n| &**n == name)
    }

    /// The variable a name means in this frame, if it exists (a compiled
    /// local becomes a shared cell: see `Slot`).
    #[inline]
    pub(crate) fn get(&mut self, name: &str) -> Option<VarCell> {
        match self.slot_of(name) {
            Some(i) => self.slots[i].promote(),
            None => self.vars()?.get(name).cloned(),
        }
    }

    pub(crate) fn insert(&mut self, name: Rc<str>, cell: VarCell) {
        match self.slot_of(&name) {
            Some(i) => self.slots[i] = Slot::Cell(cell),
            None => {
                self.vars_mut().insert(name, cell);
            }
        }
    }

    pub(crate) fn remove(&mut self, name: &str) {
        match self.slot_of(name) {
            Some(i) => self.slots[i] = Slot::Empty,
            None => {
                if let Some(n) = &mut self.named {
                    n.vars.shift_remove(name);
                }
            }
        }
    }

    /// The names of the frame's variables that have values: the compiled
    /// locals in their order, then the others in the order they were made
    /// (as Tcl lists them).
    pub(crate) fn defined_names(&self) -> impl Iterator<Item = &Rc<str>> {
        let names = self.names.as_deref().unwrap_or(&[]);
        let slots = names.iter().zip(&self.slots).filter(|(_, s)| s.is_defined()).map(|(n, _)| n);
        let others = self.vars().into_iter().flatten();
        let others = others.filter(|(_, c)| !matches!(*c.borrow(), Var::Undefined));
        slots.chain(others.map(|(n, _)| n))
    }

    /// The frame's variables that are cells (the only ones a trace can
    /// be on).
    pub(crate) fn cells(&self) -> impl Iterator<Item = (&Rc<str>, &VarCell)> {
        let names = self.names.as_deref().unwrap_or(&[]);
        let slots = names.iter().zip(&self.slots).filter_map(|(n, s)| match s {
            Slot::Cell(c) => Some((n, c)),
            _ => None,
        });
        slots.chain(self.vars().into_iter().flatten())
    }
}

/// The `errorCode` of an interrupted script.
pub const INTERRUPT_CODE: &str = "RAYSHELL INTERRUPT";

pub struct Interp {
    pub(crate) commands: FxHashMap<String, CommandKind>,
    /// Bumped on every change to `commands`, so lookups can be cached.
    pub(crate) cmd_epoch: u64,
    /// Bumped when a command that `compile.rs` compiles inline may have
    /// changed meaning (Tcl's compile epoch): compiled bodies recompile.
    pub(crate) inline_epoch: u64,
    /// The builtins compiled inline, as registered (see
    /// `is_original_builtin`).
    inline_builtins: Vec<(&'static str, NativeFn)>,
    pub(crate) frames: Vec<Frame>,
    /// Index into `frames` of the frame whose variables are visible now.
    pub(crate) cur: usize,
    /// How deep the evaluator is (see `MAX_NATIVE_DEPTH`).
    pub(crate) depth: usize,
    /// Tcl's nesting level, and its limit (see `DEFAULT_MAX_DEPTH`).
    pub(crate) levels: usize,
    pub max_depth: usize,
    /// Optional cap on the number of commands run (for fuzzing and
    /// sandboxes): past it every command fails.
    pub max_commands: Option<u64>,
    /// When set (by a Ctrl-C handler, say), the next command fails with
    /// "interrupted" and `errorCode` `INTERRUPT_CODE`; it stays set, so a
    /// `catch` cannot swallow it for long.
    pub interrupt: Option<&'static std::sync::atomic::AtomicBool>,
    commands_run: u64,
    pub(crate) host: Box<dyn Host>,
    rand_seed: i64,
    pub(crate) script_file: Option<Rc<str>>,
    /// Whether commands run directly from a file's top level, not inside a
    /// unit Tcl would compile (see `add_trace`).
    pub(crate) direct: bool,
    help: BTreeMap<String, (String, String)>,
    pub(crate) packages: super::builtins::Packages,
    /// The current namespace, qualified without the leading `::` (empty:
    /// the global one), and the namespaces that exist besides it.
    pub(crate) ns: Rc<str>,
    pub(crate) namespaces: std::collections::BTreeSet<String>,
    /// The commands `namespace ensemble create` made.
    ensembles: std::collections::BTreeSet<String>,
    /// `namespace export`: each namespace's patterns.
    pub(crate) exports: BTreeMap<String, Vec<String>>,
    /// What `info nameofexecutable` says (the host sets it).
    pub executable: String,
    /// `interp alias`: each alias's target words.
    pub(crate) aliases: BTreeMap<String, Vec<Value>>,
    /// The command a `tailcall` left to run when its proc returns.
    pub(crate) tailcall: Option<Vec<Value>>,
    /// Open files (`open`, `gets`...).
    pub(crate) channels: super::builtins::Channels,
    /// What the host allows scripts to read and write (`--safe`).
    fs_policy: Option<FsPolicy>,
    /// `trace add variable`: traces by variable (empty: no trace cost).
    pub(crate) var_traces: super::builtins::VarTraceTable,
    /// `trace add command` and `trace add execution`.
    pub(crate) cmd_traces: super::builtins::CmdTraces,
    /// Coroutines, by command key, and the one running now with the index
    /// of its first frame (see builtins/coro.rs).
    pub(crate) coroutines: super::builtins::Coroutines,
    pub(crate) current_coro: Option<Rc<str>>,
    pub(crate) coro_base: usize,
    /// `namespace path`: each namespace's list of namespaces to look in.
    pub(crate) ns_paths: FxHashMap<String, Vec<String>>,
    /// Reused by proc calls.
    pools: Pools,
    /// The units of evaluation in progress (`info frame`; `cmdframe.rs`),
    /// and where a running coroutine's own begin.
    pub(crate) cmd_frames: Vec<super::cmdframe::CmdFrame>,
    pub(crate) coro_cmd_base: usize,
    /// The `-errorstack` of the last error caught (`info errorstack`).
    pub(crate) errorstack: Value,
}

/// The host of an interpreter whose state has been moved out (into or out
/// of a coroutine's stack): nowhere to write.
struct NoHost;

impl Host for NoHost {
    fn stdout(&mut self, _: &str) -> std::io::Result<()> {
        Ok(())
    }
    fn stderr(&mut self, _: &str) -> std::io::Result<()> {
        Ok(())
    }
    fn read_file(&mut self, path: &str) -> std::io::Result<String> {
        Err(std::io::Error::other(format!("no host to read {path}")))
    }
}

fn truncate_cmd(text: &str) -> String {
    const LIMIT: usize = 150;
    if text.len() <= LIMIT {
        return text.to_string();
    }
    let mut end = LIMIT;
    while !text.is_char_boundary(end) {
        end -= 1;
    }
    format!("{}...", &text[..end])
}

/// Splits `a(b)` into ("a", Some("b")).
pub(crate) fn split_var_name(name: &str) -> (&str, Option<&str>) {
    if name.ends_with(')')
        && let Some(open) = name.find('(')
    {
        return (&name[..open], Some(&name[open + 1..name.len() - 1]));
    }
    (name, None)
}

impl Interp {
    pub fn new(host: Box<dyn Host>) -> Interp {
        let mut interp = Interp::hollow(host);
        interp.frames.push(Frame::new(Rc::from(""), 0, 0, Vec::new()));
        interp.seed_rand(0);
        super::builtins::register_all(&mut interp);
        interp.inline_builtins = compile::INLINE_OPS
            .iter()
            .filter_map(|&n| match interp.commands.get(n) {
                Some(CommandKind::Native(f, _)) => Some((n, *f)),
                _ => None,
            })
            .collect();
        interp.set_tcl_globals();
        interp.eval_str(super::builtins::PARRAY).expect("parray's definition runs");
        interp.set_help("parray", "arrayName ?pattern?", "print an array's elements");
        interp.eval_str(super::builtins::UNKNOWN).expect("unknown's definition runs");
        interp.set_help("unknown", "cmdName ?arg ...?", "called for a command that does not exist");
        interp
    }

    /// An interpreter with no commands, variables or frames: what is left
    /// in place while the real one runs a coroutine on its own stack.
    pub(crate) fn hollow(host: Box<dyn Host>) -> Interp {
        Interp {
            commands: FxHashMap::default(),
            cmd_epoch: 0,
            inline_epoch: 0,
            inline_builtins: Vec::new(),
            frames: Vec::new(),
            cur: 0,
            depth: 0,
            levels: 0,
            max_depth: DEFAULT_MAX_DEPTH,
            max_commands: None,
            interrupt: None,
            commands_run: 0,
            host,
            rand_seed: 0,
            script_file: None,
            direct: false,
            help: BTreeMap::new(),
            packages: Default::default(),
            ns: Rc::from(""),
            namespaces: Default::default(),
            ensembles: Default::default(),
            exports: BTreeMap::new(),
            executable: String::new(),
            aliases: BTreeMap::new(),
            channels: Default::default(),
            tailcall: None,
            fs_policy: None,
            var_traces: Default::default(),
            cmd_traces: Default::default(),
            coroutines: Default::default(),
            current_coro: None,
            coro_base: 0,
            ns_paths: FxHashMap::default(),
            pools: Pools::default(),
            cmd_frames: Vec::new(),
            coro_cmd_base: 0,
            errorstack: Value::empty(),
        }
    }

    /// `hollow` with nowhere to write.
    pub(crate) fn placeholder() -> Interp {
        Interp::hollow(Box::new(NoHost))
    }

    // -- Commands ----------------------------------------------------------

    fn set_command(&mut self, name: String, cmd: CommandKind) {
        self.cmd_epoch += 1;
        self.touch_inline(&name);
        self.commands.insert(name, cmd);
    }

    /// Notes that the command under table key `key` changes: compiled
    /// bodies recompile if it is one of the commands they inline.
    pub(crate) fn touch_inline(&mut self, key: &str) {
        let tail = key.rsplit("::").next().unwrap_or(key);
        if compile::INLINE_OPS.contains(&tail) {
            self.inline_epoch += 1;
        }
    }

    /// The function of a builtin compiled code may call straight.
    pub(crate) fn builtin_fn(&self, name: &str) -> Option<NativeFn> {
        self.inline_builtins.iter().find(|(n, _)| *n == name).map(|(_, f)| *f)
    }

    /// Whether `name`, looked up here, is the builtin registered under
    /// that name (not a proc or another command renamed to it).
    pub(crate) fn is_original_builtin(&self, name: &str) -> bool {
        let Some((_, f)) = self.inline_builtins.iter().find(|(n, _)| *n == name) else {
            return false;
        };
        self.command_key(name).as_deref() == Some(name)
            && matches!(self.commands.get(name),
                Some(CommandKind::Native(g, _)) if std::ptr::fn_addr_eq(*f, *g))
    }

    pub fn register(&mut self, name: &str, f: NativeFn, usage: &str, summary: &str) {
        self.set_command(name.to_string(), CommandKind::Native(f, INLINE.contains(&name)));
        self.set_help(name, usage, summary);
    }

    /// A command without a help entry (`tcl::mathop::+` and the like).
    pub(crate) fn register_hidden(&mut self, name: &str, f: NativeFn) {
        self.set_command(name.to_string(), CommandKind::Native(f, false));
    }

    pub fn register_host(
        &mut self,
        name: &str,
        usage: &str,
        summary: &str,
        f: impl Fn(&mut Interp, &[Value]) -> TclResult + 'static,
    ) {
        self.set_command(name.to_string(), CommandKind::Host(Rc::new(f)));
        self.set_help(name, usage, summary);
    }

    /// Registers a command that takes exactly `arity` numbers.
    pub fn register_numeric(
        &mut self,
        name: &str,
        arity: usize,
        usage: &str,
        summary: &str,
        f: impl Fn(&mut Interp, &[Num]) -> Result<Option<Num>, Exception> + 'static,
    ) {
        let usage_full: Rc<str> = Rc::from(format!("{name} {usage}").trim_end());
        self.set_command(name.to_string(), CommandKind::Numeric(arity, usage_full, Rc::new(f)));
        self.set_help(name, usage, summary);
    }

    pub fn set_help(&mut self, name: &str, usage: &str, summary: &str) {
        self.help.insert(name.to_string(), (usage.to_string(), summary.to_string()));
    }

    /// (usage, summary) for a command, if documented.
    pub fn help(&self, name: &str) -> Option<(&str, &str)> {
        self.help.get(name).map(|(u, s)| (u.as_str(), s.as_str()))
    }

    pub fn help_names(&self) -> Vec<String> {
        self.help.keys().filter(|k| self.commands.contains_key(*k)).cloned().collect()
    }

    pub fn has_command(&self, name: &str) -> bool {
        self.resolve_command(name).is_some()
    }

    /// The command a name means here: `::a::b` absolutely; otherwise in
    /// the current namespace first, then the global one.
    #[inline]
    pub(crate) fn resolve_command(&self, name: &str) -> Option<&CommandKind> {
        if let Some(abs) = name.strip_prefix("::") {
            return self.commands.get(abs);
        }
        if !self.ns.is_empty()
            && let Some(c) = self.commands.get(&format!("{}::{name}", self.ns))
        {
            return Some(c);
        }
        if !self.ns_paths.is_empty()
            && let Some(c) = self.command_on_path(name)
        {
            return Some(c);
        }
        self.commands.get(name)
    }

    /// A command found through the current namespace's `namespace path`.
    #[cold]
    fn command_on_path(&self, name: &str) -> Option<&CommandKind> {
        self.commands.get(&self.path_key(name)?)
    }

    /// The table key of the first command `name` names along the current
    /// namespace's `namespace path`.
    fn path_key(&self, name: &str) -> Option<String> {
        let path = self.ns_paths.get(&*self.ns)?;
        path.iter()
            .map(|ns| if ns.is_empty() { name.to_string() } else { format!("{ns}::{name}") })
            .find(|k| self.commands.contains_key(k))
    }

    /// The table key of the command a name means here.
    pub(crate) fn command_key(&self, name: &str) -> Option<String> {
        if let Some(abs) = name.strip_prefix("::") {
            return self.commands.contains_key(abs).then(|| abs.to_string());
        }
        if !self.ns.is_empty() {
            let k = format!("{}::{name}", self.ns);
            if self.commands.contains_key(&k) {
                return Some(k);
            }
        }
        if !self.ns_paths.is_empty()
            && let Some(k) = self.path_key(name)
        {
            return Some(k);
        }
        self.commands.contains_key(name).then(|| name.to_string())
    }

    pub(crate) fn has_exact_command(&self, key: &str) -> bool {
        self.commands.contains_key(key)
    }

    /// `namespace import`: the command under a second name.
    /// Whether two table keys name the same command (an import of it).
    pub(crate) fn same_command(&self, a: &str, b: &str) -> bool {
        match (self.commands.get(a), self.commands.get(b)) {
            (Some(CommandKind::Proc(x)), Some(CommandKind::Proc(y))) => Rc::ptr_eq(x, y),
            (Some(CommandKind::Native(x, _)), Some(CommandKind::Native(y, _))) => {
                std::ptr::fn_addr_eq(*x, *y)
            }
            (Some(CommandKind::Host(x)), Some(CommandKind::Host(y))) => Rc::ptr_eq(x, y),
            _ => false,
        }
    }

    pub(crate) fn copy_command(&mut self, from: &str, to: &str) {
        if let Some(c) = self.commands.get(from).cloned() {
            self.set_command(to.to_string(), c);
        }
    }

    /// `namespace delete`: the commands and variables under a prefix.
    pub(crate) fn forget_prefix(&mut self, prefix: &str) {
        self.cmd_epoch += 1;
        self.inline_epoch += 1;
        self.commands.retain(|k, _| !k.starts_with(prefix));
        self.frames[0].vars_mut().retain(|k, _| !k.starts_with(prefix));
    }

    pub(crate) fn mark_ensemble(&mut self, key: &str) {
        self.ensembles.insert(key.to_string());
    }

    pub(crate) fn is_ensemble(&self, name: &str) -> bool {
        self.command_key(name).is_some_and(|k| self.ensembles.contains(&k))
    }

    /// A variable's qualified name (without the leading `::`) as
    /// `namespace which -variable` gives it.
    pub(crate) fn qualify_var(&self, name: &str) -> String {
        let (frame, key, fallback) = self.var_place(name);
        if frame == 0
            && !self.frames[0].vars().is_some_and(|v| v.contains_key(&*key))
            && let Some(f) = fallback
        {
            return f.to_string();
        }
        key.into_owned()
    }

    /// The table key a command made under `name` gets (`proc`,
    /// `coroutine`), refused when its namespace does not exist.
    pub(crate) fn new_command_key(&self, name: &str) -> Result<String, Exception> {
        let key = self.qualify_command(name);
        if let Some((ns, _)) = key.rsplit_once("::")
            && !ns.is_empty()
            && !self.namespaces.contains(ns)
        {
            return Err(Exception::error(format!(
                "can't create procedure \"{name}\": unknown namespace"
            )));
        }
        Ok(key)
    }

    /// The table key a command defined under `name` gets here.
    pub(crate) fn qualify_command(&self, name: &str) -> String {
        match name.strip_prefix("::") {
            Some(abs) => abs.to_string(),
            None if self.ns.is_empty() => name.to_string(),
            None => format!("{}::{name}", self.ns),
        }
    }

    pub fn command_names(&self) -> Vec<String> {
        let mut v: Vec<String> = self.commands.keys().cloned().collect();
        v.sort();
        v
    }

    pub(crate) fn proc_names(&self) -> Vec<String> {
        let mut v: Vec<String> = self
            .commands
            .iter()
            .filter(|(_, c)| matches!(c, CommandKind::Proc(_)))
            .map(|(k, _)| k.clone())
            .collect();
        v.sort();
        v
    }

    pub(crate) fn get_proc(&self, name: &str) -> Option<Rc<Proc>> {
        match self.resolve_command(name) {
            Some(CommandKind::Proc(p)) => Some(p.clone()),
            _ => None,
        }
    }

    pub(crate) fn define_proc(&mut self, p: Proc) {
        let name = p.name.clone();
        if !self.cmd_traces.is_empty() {
            self.fire_replace_traces(&name);
        }
        self.set_command(name, CommandKind::Proc(Rc::new(p)));
    }

    pub(crate) fn rename_command(&mut self, old: &str, new: &str) -> Result<(), Exception> {
        self.cmd_epoch += 1;
        self.touch_inline(old);
        self.touch_inline(new);
        let cmd = self.commands.remove(old).ok_or_else(|| {
            Exception::error(format!("can't rename \"{old}\": command doesn't exist"))
        })?;
        if !new.is_empty() {
            if self.commands.contains_key(new) {
                self.commands.insert(old.to_string(), cmd);
                return Err(Exception::error(format!(
                    "can't rename to \"{new}\": command already exists"
                )));
            }
            self.commands.insert(new.to_string(), cmd);
        }
        if !self.cmd_traces.is_empty() {
            self.fire_rename_traces(old, new);
        }
        if new.is_empty() {
            // A deleted coroutine's stack unwinds when it is dropped.
            self.delete_coroutine(old);
        }
        Ok(())
    }

    // -- I/O through the host -----------------------------------------------

    pub fn write_stdout(&mut self, s: &str) -> Result<(), Exception> {
        self.host.stdout(s).map_err(|e| stdout_error(&e))
    }

    pub fn write_stderr(&mut self, s: &str) -> Result<(), Exception> {
        self.host.stderr(s).map_err(|e| Exception::error(format!("error writing \"stderr\": {e}")))
    }

    /// Flushes buffered output; a failure shows at the end (`flush_checked`).
    pub fn flush(&mut self) {
        self.channels.flush_all();
        let _ = self.host.flush();
    }

    /// Fences file access: `policy(path, access)` is asked before a script
    /// reads or writes a file, and its error message is the script's.
    pub fn set_fs_policy(&mut self, policy: FsPolicy) {
        self.fs_policy = Some(policy);
    }

    /// Whether the host's policy lets scripts reach `path`.
    pub fn check_access(&self, path: &str, access: Access) -> Result<(), Exception> {
        match &self.fs_policy {
            Some(p) => p(path, access)
                .map_err(|why| Exception::error(why).with_error_code("TCL SAFE ACCESS")),
            None => Ok(()),
        }
    }

    /// Flushes buffered output, as an error if it cannot be written (the
    /// end of a script: output lost to a full disk is an error, as in tclsh).
    pub fn flush_checked(&mut self) -> Result<(), Exception> {
        self.host.flush().map_err(|e| stdout_error(&e))
    }

    // -- Random numbers (Tcl's own generator, so `srand` matches tclsh) -------

    pub(crate) fn seed_rand(&mut self, seed: i64) {
        let mut s = seed & 0x7fff_ffff;
        if s == 0 || s == 0x7fff_ffff {
            s ^= 123_459_876;
        }
        self.rand_seed = s;
    }

    pub(crate) fn next_rand(&mut self) -> f64 {
        const IA: i64 = 16807;
        const IM: i64 = 2_147_483_647;
        const IQ: i64 = 127_773;
        const IR: i64 = 2836;
        let tmp = self.rand_seed / IQ;
        self.rand_seed = IA * (self.rand_seed - tmp * IQ) - IR * tmp;
        if self.rand_seed < 0 {
            self.rand_seed += IM;
        }
        self.rand_seed as f64 * (1.0 / IM as f64)
    }

    // -- Evaluation -----------------------------------------------------------

    /// The parsed form of a script value (cached on the value).
    pub(crate) fn script_of(v: &Value) -> Rc<Script> {
        let (file, line, cont) = match &*v.rep() {
            Rep::Script(s) => return s.clone(),
            Rep::Origin(o) => (o.file.clone(), o.line, o.cont.clone()),
            _ => (None, 1, None),
        };
        let s = Rc::new(Script::parse_with(Rc::from(v.as_str()), file, line, cont));
        v.set_rep(Rep::Script(s.clone()));
        s
    }

    /// Evaluates a script held in a value, as its own evaluation unit
    /// (what Tcl compiles separately: a proc body, a script for `eval`).
    pub fn eval(&mut self, script: &Value) -> TclResult {
        let s = Interp::script_of(script);
        let unit = self.unit_of(script, s.true_first_line());
        self.eval_unit(&s, unit)
    }

    /// `eval` for `uplevel`, which knows where a script came from only
    /// when a directly evaluated command has it as a literal word.
    pub(crate) fn eval_registered(&mut self, script: &Value) -> TclResult {
        let s = Interp::script_of(script);
        let unit = self.registered_unit(script, s.true_first_line());
        self.eval_unit(&s, unit)
    }

    /// Evaluates a parsed script as a unit of its own, counting its lines
    /// as `unit` says (`info frame`).
    fn eval_unit(&mut self, s: &Rc<Script>, unit: Unit) -> TclResult {
        self.begin_unit(unit);
        self.eval_begun_unit(s)
    }

    fn eval_begun_unit(&mut self, s: &Rc<Script>) -> TclResult {
        let direct = std::mem::replace(&mut self.direct, false);
        let r = self.eval_script(s);
        self.direct = direct;
        self.end_unit_frame();
        r.map_err(|e| end_unit(e, s.first_line))
    }

    /// Evaluates the body of a command that Tcl compiles into the script
    /// around it (`if`, `while`, `catch`...; `foreach` and the like only
    /// inside procs): an error in it is logged as part of that script.
    /// A body that is not a literal word of the command (`if 1 $body`)
    /// cannot be compiled so, and runs as a unit of its own, as in Tcl.
    pub(crate) fn eval_inline(&mut self, script: &Value) -> TclResult {
        if self.inline_is_unit(script) {
            return self.eval(script);
        }
        self.eval_in_unit(script)
    }

    /// Whether `eval_inline` runs `script` as a unit of its own (where
    /// Tcl invokes the command instead of compiling it, and its errors
    /// name the body they came from).
    pub(crate) fn inline_is_unit(&self, script: &Value) -> bool {
        self.direct || !self.is_current_literal(script)
    }

    /// Runs a script as part of the current unit; the command running
    /// there is the same again afterwards (a loop asks of its body each
    /// turn whether it is a literal word of the loop).
    fn eval_in_unit(&mut self, script: &Value) -> TclResult {
        let s = Interp::script_of(script);
        let at = self.take_at();
        let r = self.eval_script(&s);
        self.put_at(at);
        r
    }

    /// Evaluates a loop body: inline inside a proc; outside, a unit of
    /// its own that names itself, as `("foreach" body line 2)`.
    pub(crate) fn eval_body(&mut self, script: &Value, what: &str) -> TclResult {
        if self.in_proc_body() && !self.direct && self.is_current_literal(script) {
            return self.eval_in_unit(script);
        }
        self.eval(script).map_err(|e| super::builtins::with_body_line(e, what))
    }

    /// Evaluates a `switch` arm: inline inside a proc (the arms of a
    /// literal list are compiled too); outside, a unit of its own.
    pub(crate) fn eval_arm(&mut self, script: &Value, what: &str) -> TclResult {
        if self.in_proc_body() && !self.direct {
            return self.eval_in_unit(script);
        }
        self.eval(script).map_err(|e| super::builtins::with_body_line(e, what))
    }

    pub fn eval_str(&mut self, src: &str) -> TclResult {
        self.eval(&Value::from(src))
    }

    /// Evaluates `src` in the global frame (as `uplevel #0`).
    pub fn eval_global(&mut self, src: &str) -> TclResult {
        self.in_frame(0, |i| i.eval_str(src))
    }

    pub(crate) fn eval_script(&mut self, s: &Rc<Script>) -> TclResult {
        let mut result = Value::empty();
        for (i, cmd) in s.cmds.iter().enumerate() {
            // Drop the previous result first so `lappend` can grow in place.
            drop(std::mem::take(&mut result));
            match self.eval_command(cmd, || At::Cmd(s.clone(), i as u32)) {
                Ok(v) => result = v,
                Err(mut e) => {
                    self.add_trace(
                        &mut e,
                        s.text(cmd),
                        cmd.line,
                        s.first_line,
                        &s.file,
                        self.direct,
                    );
                    return Err(e);
                }
            }
        }
        if let Some(pe) = &s.error {
            let text = &s.src[pe.cmd_start as usize..(pe.pos as usize).min(s.src.len())];
            let mut e = Exception::error(pe.msg.clone());
            self.add_trace(&mut e, text, pe.line, s.first_line, &s.file, self.direct);
            return Err(e);
        }
        Ok(result)
    }

    /// Runs a whole source file (or stdin) command by command, without
    /// building the whole parse tree first: a mesh of a million commands
    /// streams through in constant memory.
    pub(crate) fn eval_command(&mut self, cmd: &Command, at: impl FnOnce() -> At) -> TclResult {
        let mut argv: SmallVec<[Value; 8]> = SmallVec::new();
        for w in &cmd.words {
            match w {
                Word::Expand(inner) => {
                    let v = self.eval_word(inner)?;
                    argv.extend(v.as_list()?.iter().cloned());
                }
                _ => argv.push(self.eval_word(w)?),
            }
        }
        if argv.is_empty() {
            return Ok(Value::empty());
        }
        self.note_at(at());
        self.invoke(&argv)
    }

    /// `subst`: the parts' values joined; a `break` in a command ends the
    /// result there, a `continue` substitutes nothing, and `return` (or
    /// any other code) substitutes its value.
    pub(crate) fn subst(&mut self, parts: &[Part]) -> TclResult {
        let mut out = String::new();
        for p in parts {
            match p {
                Part::Lit(s) => out.push_str(s),
                Part::Var(name) => out.push_str(self.get_var_name(name)?.as_str()),
                Part::Local(i, name) => out.push_str(self.read_local(*i, name)?.as_str()),
                Part::Cmd(_) | Part::Compiled(_) => match self.eval_part_cmd(p) {
                    Ok(v) => out.push_str(v.as_str()),
                    Err(e) => match e.code {
                        Code::Error | Code::Exit(_) => return Err(e),
                        Code::Break => break,
                        Code::Continue => {}
                        Code::Return | Code::Other(_) => out.push_str(e.value.as_str()),
                    },
                },
            }
        }
        Ok(Value::from_string(out))
    }

    /// A word's value: literals and compiled locals here, the rest in
    /// `eval_word_tree` (so the common words cost no call).
    #[inline]
    pub(crate) fn eval_word(&mut self, w: &Word) -> TclResult {
        match w {
            Word::Lit(v) => Ok(v.clone()),
            Word::Local(i, name) => self.read_local(*i, name),
            // Not through `eval_word_tree`: its frame would sit on the
            // native stack under every call made inside the `[...]`.
            Word::Compiled(b) => self.run_nested(b),
            _ => self.eval_word_tree(w),
        }
    }

    fn eval_word_tree(&mut self, w: &Word) -> TclResult {
        match w {
            Word::Lit(v) => Ok(v.clone()),
            Word::Var(name) => self.get_var_name(name),
            Word::Cmd(s) => self.eval_nested(s),
            Word::Local(i, name) => self.read_local(*i, name),
            Word::LocalElem(i, name, key) => {
                let key = self.eval_word(key)?;
                self.read_local_elem(*i, name, &key)
            }
            Word::Compiled(b) => self.run_nested(b),
            Word::Concat(parts) => {
                let mut out = compact_str::CompactString::const_new("");
                for p in parts {
                    let v;
                    let piece = match p {
                        Part::Lit(s) => &**s,
                        Part::Var(name) => {
                            v = self.get_var_name(name)?;
                            v.as_str()
                        }
                        Part::Local(i, name) => {
                            v = self.read_local(*i, name)?;
                            v.as_str()
                        }
                        Part::Cmd(_) | Part::Compiled(_) => {
                            v = self.eval_part_cmd(p)?;
                            v.as_str()
                        }
                    };
                    check_len(out.len() + piece.len())?;
                    out.push_str(piece);
                }
                Ok(Value::from_compact(out))
            }
            Word::Expand(inner) => self.eval_word_tree(inner),
        }
    }

    /// A command substitution in a word of several parts.
    fn eval_part_cmd(&mut self, p: &Part) -> TclResult {
        match p {
            Part::Cmd(s) => self.eval_nested(s),
            Part::Compiled(b) => self.run_nested(b),
            _ => unreachable!("a command part"),
        }
    }

    fn eval_nested(&mut self, s: &Rc<Script>) -> TclResult {
        self.enter()?;
        let r = self.eval_script(s);
        self.depth -= 1;
        r
    }

    /// Undoes a successful `enter`.
    pub(crate) fn leave(&mut self) {
        self.depth -= 1;
    }

    pub(crate) fn enter(&mut self) -> Result<(), Exception> {
        if self.depth >= MAX_NATIVE_DEPTH {
            return Err(too_deep());
        }
        self.poll()?;
        // What the levels below hold (each nested body's text and parse,
        // 20,000 nested `if`s took 3 GB) is checked on the way down: the
        // check after each command comes only once they have all returned.
        crate::mem::check()?;
        self.depth += 1;
        Ok(())
    }

    /// Ctrl-C and the command budget: checked at each command, and at
    /// each turn of a compiled loop.
    #[inline]
    pub(crate) fn poll(&mut self) -> Result<(), Exception> {
        if let Some(flag) = self.interrupt
            && flag.load(std::sync::atomic::Ordering::Relaxed)
        {
            return Err(Exception::error("interrupted").with_error_code(INTERRUPT_CODE));
        }
        if let Some(max) = self.max_commands {
            self.commands_run += 1;
            if self.commands_run > max {
                return Err(Exception::error(format!("command limit of {max} reached")));
            }
        }
        Ok(())
    }

    /// Calls a command with its words already substituted.
    pub fn invoke(&mut self, argv: &[Value]) -> TclResult {
        let found = self.resolve_command(argv[0].as_str());
        let cmd = match found {
            Some(c) => c.clone(),
            None if argv[0].as_str() != "unknown" && self.resolve_command("unknown").is_some() => {
                // A script's `unknown` handler gets the whole command.
                let mut words = Vec::with_capacity(argv.len() + 1);
                words.push(Value::from("unknown"));
                words.extend(argv.iter().cloned());
                return self.invoke(&words).map_err(|mut e| {
                    // The command that failed is the one not found.
                    if let Some(stack) = e.ext.as_mut().and_then(|x| x.errorstack.as_mut())
                        && stack.len() == 2
                    {
                        stack[1] = inner_context(argv, &Exception::error(""));
                    }
                    e
                });
            }
            None => {
                return Err(Exception::error(format!(
                    "invalid command name \"{}\"",
                    argv[0].as_str()
                ))
                .with_error_code(&format!("TCL LOOKUP COMMAND {}", argv[0].as_str())));
            }
        };
        self.invoke_cmd(&cmd, argv)
    }

    /// Starts an error's `-errorstack` with the command that raised it.
    #[inline]
    pub(crate) fn note_inner(&self, argv: &[Value], r: &mut TclResult) {
        if let Err(e) = r {
            self.note_inner_error(argv, e);
        }
    }

    #[cold]
    #[inline(never)]
    fn note_inner_error(&self, argv: &[Value], e: &mut Exception) {
        if e.code == Code::Error && e.errorstack().is_none() && !e.logged && !self.direct {
            let inner = inner_context(argv, e);
            e.ext_mut().errorstack = Some(vec![Value::from("INNER"), inner]);
        }
    }

    /// Calls the command `argv[0]` resolved to.
    pub(crate) fn invoke_cmd(&mut self, cmd: &CommandKind, argv: &[Value]) -> TclResult {
        self.enter()?;
        let mark = crate::mem::mark();
        let level = !matches!(cmd, CommandKind::Native(_, true));
        if level {
            if self.levels >= self.max_depth {
                self.depth -= 1;
                return Err(too_deep());
            }
            self.levels += 1;
        }
        let mut r = if self.cmd_traces.is_empty() {
            self.dispatch(cmd, argv)
        } else {
            let key = self.command_key(argv[0].as_str());
            self.invoke_traced(key, argv, cmd)
        };
        self.note_inner(argv, &mut r);
        // `tailcall`: the proc has returned; its successor runs here, in
        // the caller's frame, as a loop (a tail-recursive proc runs in
        // constant depth).
        if r.is_ok() && self.tailcall.is_some() {
            r = self.run_tailcalls(level);
        }
        self.depth -= 1;
        self.levels -= level as usize;
        if crate::mem::grew_past(mark) || value::has_pending() {
            return after_growth(r);
        }
        r
    }

    /// `tailcall`s left by the command just run, one after the other.
    #[cold]
    #[inline(never)]
    fn run_tailcalls(&mut self, level: bool) -> TclResult {
        let mut r = Ok(Value::empty());
        while r.is_ok()
            && let Some(next) = self.tailcall.take()
        {
            r = match self.resolve_command(next[0].as_str()).cloned() {
                Some(CommandKind::Proc(p)) => self.call_proc(&p, &next),
                Some(_) => {
                    self.depth -= 1;
                    self.levels -= level as usize;
                    let r = self.invoke(&next);
                    self.depth += 1;
                    self.levels += level as usize;
                    r
                }
                None => {
                    Err(Exception::error(format!("invalid command name \"{}\"", next[0].as_str())))
                }
            };
        }
        r
    }

    #[inline]
    pub(crate) fn dispatch(&mut self, cmd: &CommandKind, argv: &[Value]) -> TclResult {
        match cmd {
            CommandKind::Native(f, _) => f(self, argv),
            CommandKind::Host(f) => f(self, argv),
            CommandKind::Numeric(arity, usage, f) => call_numeric(self, *arity, usage, f, argv),
            CommandKind::Proc(p) => self.call_proc(p, argv),
        }
    }

    /// Calls a lambda: `argv` is `apply`'s words (`apply`, the lambda
    /// term, the arguments), as `info level 0` shows them.
    pub(crate) fn call_lambda(&mut self, p: Proc, argv: &[Value]) -> TclResult {
        self.call_proc(&Rc::new(p), argv)
    }

    fn call_proc(&mut self, p: &Rc<Proc>, argv: &[Value]) -> TclResult {
        let compiled = if p.lambda.is_none() { self.compiled_body(p) } else { None };
        // The common call: a compiled proc given exactly its parameters.
        if let Some(c) = &compiled
            && !p.variadic
            && argv.len() == p.params.len() + 1
        {
            return self.call_compiled(p, c, argv);
        }
        self.call_proc_general(p, compiled, argv)
    }

    /// `call_proc`'s common case, kept lean: its frame sits on the native
    /// stack under each Tcl level.
    fn call_compiled(&mut self, p: &Rc<Proc>, c: &CompiledProc, argv: &[Value]) -> TclResult {
        let mut frame = self.proc_frame(p, argv);
        let mut slots = self.pools.slots.pop().unwrap_or_default();
        slots.extend(argv[1..].iter().map(|v| Slot::Val(v.clone())));
        slots.resize_with(c.names.len(), || Slot::Empty);
        frame.slots = slots;
        frame.names = Some(c.names.clone());
        let (saved, saved_ns) = self.push_proc_frame(p, frame);
        let r = self.run_compiled(c);
        self.ns = saved_ns;
        if !self.var_traces.is_empty() {
            return self.leave_proc_frame(saved, p, &argv[0], r);
        }
        if let Some(f) = self.frames.pop() {
            self.pools.recycle(f);
        }
        self.cur = saved;
        match r {
            Ok(v) => Ok(v),
            Err(e) => proc_exit(p, &argv[0], e),
        }
    }

    /// A new frame for a call of `p` with the words `argv`, one level
    /// below the current one (its variables not bound yet).
    #[inline(always)]
    fn proc_frame(&mut self, p: &Rc<Proc>, argv: &[Value]) -> Frame {
        let level = self.frames[self.cur].level + 1;
        let mut objv = self.pools.objv.pop().unwrap_or_default();
        objv.extend_from_slice(argv);
        let mut frame = Frame::new(p.ns.clone(), level, self.cur, objv);
        frame.proc = Some(p.clone());
        frame
    }

    /// Makes `frame` the current one, in `p`'s namespace; returns what to
    /// restore after: the caller's frame and namespace.
    #[inline(always)]
    fn push_proc_frame(&mut self, p: &Proc, frame: Frame) -> (usize, Rc<str>) {
        self.frames.push(frame);
        let saved = self.cur;
        self.cur = self.frames.len() - 1;
        (saved, std::mem::replace(&mut self.ns, p.ns.clone()))
    }

    /// A proc's frame left, in general: the unset traces of its locals
    /// fire in the caller's frame (`saved`), and the result is what the
    /// caller of proc `name` sees.
    #[inline(never)]
    fn leave_proc_frame(
        &mut self,
        saved: usize,
        p: &Proc,
        name: &Value,
        r: TclResult,
    ) -> TclResult {
        let dying =
            if self.var_traces.is_empty() { Vec::new() } else { self.traced_locals(self.cur) };
        if let Some(f) = self.frames.pop() {
            self.pools.recycle(f);
        }
        self.cur = saved;
        if !dying.is_empty() {
            self.fire_frame_unset_traces(dying);
        }
        match r {
            Ok(v) => Ok(v),
            Err(e) => proc_exit(p, name, e),
        }
    }

    /// Every other call of a proc or lambda: defaults, `args`, a wrong
    /// number of arguments, a lambda, a body that does not compile.
    #[inline(never)]
    fn call_proc_general(
        &mut self,
        p: &Rc<Proc>,
        compiled: Option<Rc<CompiledProc>>,
        argv: &[Value],
    ) -> TclResult {
        // The words before the arguments: the name, or `apply` and the term.
        let skip = if p.lambda.is_some() { 2 } else { 1 };
        let mut frame = self.proc_frame(p, argv);
        if let Err(e) = self.bind_params(&mut frame, p, compiled.as_deref(), argv, skip) {
            self.pools.recycle(frame);
            return Err(e);
        }
        let (saved, saved_ns) = self.push_proc_frame(p, frame);
        let r = match &compiled {
            Some(c) => self.run_compiled(c),
            None => self.run_proc_script(p),
        };
        self.ns = saved_ns;
        self.leave_proc_frame(saved, p, &argv[skip - 1], r)
    }

    /// A proc's parameters bound in its new frame, in general: defaults,
    /// `args`, a body not compiled (its locals then by name).
    #[inline(never)]
    fn bind_params(
        &mut self,
        frame: &mut Frame,
        p: &Proc,
        compiled: Option<&CompiledProc>,
        argv: &[Value],
        skip: usize,
    ) -> Result<(), Exception> {
        let n_args = argv.len() - skip;
        let n_fixed = p.params.len() - p.variadic as usize;
        if n_args > n_fixed && !p.variadic {
            return Err(proc_usage(p, &argv[0]));
        }
        let mut slots = match compiled {
            Some(_) => self.pools.slots.pop().unwrap_or_default(),
            None => Vec::new(),
        };
        for (i, (name, default)) in p.params.iter().enumerate() {
            let v = if i == n_fixed {
                let rest =
                    if n_args > n_fixed { argv[n_fixed + skip..].to_vec() } else { Vec::new() };
                Value::from_list(rest)
            } else if i < n_args {
                argv[i + skip].clone()
            } else if let Some(d) = default {
                d.clone()
            } else {
                if compiled.is_some() && self.pools.slots.len() < Pools::MAX {
                    slots.clear();
                    self.pools.slots.push(slots);
                }
                return Err(proc_usage(p, &argv[0]));
            };
            match compiled {
                Some(_) => slots.push(Slot::Val(v)),
                None => {
                    frame.vars_mut().insert(name.clone(), Rc::new(RefCell::new(Var::Scalar(v))));
                }
            }
        }
        if let Some(c) = compiled {
            slots.resize_with(c.names.len(), || Slot::Empty);
            frame.slots = slots;
            frame.names = Some(c.names.clone());
        }
        Ok(())
    }

    /// A proc or lambda body run as a script (not compiled).
    #[inline(never)]
    fn run_proc_script(&mut self, p: &Proc) -> TclResult {
        let s = Interp::script_of(&p.body);
        let unit = match &p.lambda {
            Some(term) => self.lambda_unit(term, &p.body),
            None => Unit::body(&s, p.in_file),
        };
        self.begin_body_unit(unit);
        self.eval_begun_unit(&s)
    }

    /// A proc's compiled body, compiled now if it is not yet (or no
    /// longer) current.
    fn compiled_body(&mut self, p: &Proc) -> Option<Rc<CompiledProc>> {
        if let Some(c) = &*p.compiled.borrow()
            && c.is_current(self)
        {
            return Some(c.clone());
        }
        self.compile_body_now(p)
    }

    /// `compiled_body`'s slow path, kept out of line so that the frame of
    /// every proc call does not carry the compiler's locals.
    #[cold]
    #[inline(never)]
    fn compile_body_now(&mut self, p: &Proc) -> Option<Rc<CompiledProc>> {
        // Command names resolve as in the proc's own namespace.
        let ns = std::mem::replace(&mut self.ns, p.ns.clone());
        let c = compile::compile_proc(self, p);
        self.ns = ns;
        let c = Rc::new(c?);
        *p.compiled.borrow_mut() = Some(c.clone());
        Some(c)
    }

    /// Runs a compiled proc body as `eval` runs a script: a unit of its own.
    fn run_compiled(&mut self, c: &CompiledProc) -> TclResult {
        self.begin_compiled_body_unit();
        let direct = std::mem::replace(&mut self.direct, false);
        let r = self.run_body(&c.body, true);
        self.direct = direct;
        self.end_unit_frame();
        match r {
            Ok(Outcome::Normal(v)) => Ok(v.unwrap_or_default()),
            Ok(Outcome::Return(v)) => Ok(v),
            Ok(Outcome::Break) => Err(Exception::flow(Code::Break, Value::empty())),
            Ok(Outcome::Continue) => Err(Exception::flow(Code::Continue, Value::empty())),
            Err(e) => Err(end_unit(e, c.body.first_line())),
        }
    }

    /// Evaluates an expression held in a value (parsed form cached).
    pub fn eval_expr(&mut self, e: &Value) -> TclResult {
        let ast = self.expr_of(e)?;
        self.eval_expr_ast(&ast)
    }

    /// Evaluates a parsed expression as `expr` does.
    pub(crate) fn eval_expr_ast(&mut self, ast: &Expr) -> TclResult {
        self.enter()?;
        let op = self.expr_unit(ast);
        self.depth -= 1;
        expr_result(op?)
    }

    /// An expression's operand. Evaluated directly (the main script's
    /// top level), Tcl compiles an expression on its own, so its command
    /// substitutions run in a unit of their own (`info frame`).
    #[inline]
    fn expr_unit(&mut self, ast: &Expr) -> Result<Operand, Exception> {
        if !self.direct {
            return expr::eval(self, ast);
        }
        self.begin_unit(Unit::eval(1));
        self.direct = false;
        let r = expr::eval(self, ast);
        self.direct = true;
        self.end_unit_frame();
        // The command around it logs itself again.
        r.map_err(|mut e| {
            e.logged = false;
            e
        })
    }

    #[inline]
    pub fn eval_cond(&mut self, e: &Value) -> Result<bool, Exception> {
        let ast = self.expr_of(e)?;
        self.eval_cond_ast(&ast)
    }

    /// A parsed condition's truth (`if`, `while`, `for`).
    #[inline]
    pub(crate) fn eval_cond_ast(&mut self, ast: &Expr) -> Result<bool, Exception> {
        self.enter()?;
        let v = self.expr_unit(ast);
        self.depth -= 1;
        cond_truth(v?)
    }

    pub(crate) fn expr_of(&mut self, v: &Value) -> Result<Rc<Expr>, Exception> {
        let (file, line) = match &*v.rep() {
            Rep::Expr(e) => return Ok(e.clone()),
            Rep::Origin(o) => (o.file.clone(), o.line),
            _ => (None, 1),
        };
        let e = Rc::new(expr::parse(v.as_str(), file, line)?);
        v.set_rep(Rep::Expr(e.clone()));
        Ok(e)
    }

    // -- Variables --------------------------------------------------------------

    /// Where a variable name lives: its frame and key there, and for a
    /// name relative to the current namespace the global key to fall back
    /// to when reading. Namespace variables live in the global frame under
    /// their qualified names (`ns::x`, without the leading `::`).
    fn var_place<'a>(&self, name: &'a str) -> (usize, std::borrow::Cow<'a, str>, Option<&'a str>) {
        use std::borrow::Cow;
        if let Some(rest) = name.strip_prefix("::") {
            return (0, Cow::Borrowed(rest.trim_start_matches(':')), None);
        }
        let in_ns_frame = self.cur == 0 && !self.ns.is_empty();
        if !name.contains("::") && !in_ns_frame {
            return (self.cur, Cow::Borrowed(name), None);
        }
        if self.ns.is_empty() {
            return (0, Cow::Borrowed(name), None);
        }
        if name.contains("::") || in_ns_frame {
            return (0, Cow::Owned(format!("{}::{name}", self.ns)), Some(name));
        }
        (self.cur, Cow::Borrowed(name), None)
    }

    fn frame_for(&self, name: &str) -> (usize, String) {
        let (frame, key, _) = self.var_place(name);
        (frame, key.into_owned())
    }

    pub(crate) fn find_var(&mut self, name: &str) -> Option<VarCell> {
        let (frame, key, fallback) = self.var_place(name);
        match self.frames[frame].get(&key) {
            Some(c) => Some(c),
            None => fallback.and_then(|f| self.frames[0].vars()?.get(f).cloned()),
        }
    }

    pub(crate) fn var_cell(&mut self, name: &str) -> VarCell {
        if let Some(c) = self.find_var(name) {
            return c;
        }
        let (frame, local) = self.frame_for(name);
        let cell = Rc::new(RefCell::new(Var::Undefined));
        self.frames[frame].insert(Rc::from(local), cell.clone());
        cell
    }

    fn get_var_name(&mut self, name: &VarName) -> TclResult {
        match name {
            VarName::Scalar(n) => self.get_scalar_or_elem(n, None),
            VarName::Elem(n, idx) => {
                let idx = self.eval_word(idx)?;
                self.get_scalar_or_elem(n, Some(idx.as_str()))
            }
        }
    }

    /// Reads a variable given as `name` or `name(index)`.
    pub fn get_var(&mut self, name: &str) -> TclResult {
        let (base, idx) = split_var_name(name);
        self.get_scalar_or_elem(base, idx)
    }

    fn get_scalar_or_elem(&mut self, name: &str, idx: Option<&str>) -> TclResult {
        let full = || match idx {
            Some(i) => format!("{name}({i})"),
            None => name.to_string(),
        };
        let Some(cell) = self.find_var(name) else {
            return Err(Exception::error(format!("can't read \"{}\": no such variable", full()))
                .with_error_code(&format!("TCL LOOKUP VARNAME {name}")));
        };
        if !self.var_traces.is_empty() {
            self.traced_access(&cell, name, idx, super::builtins::trace::READ)?;
        }
        let var = cell.borrow();
        match (&*var, idx) {
            (Var::Scalar(v), None) => Ok(v.clone()),
            (Var::Elem(array, key), None) => {
                let (array, key) = (array.clone(), key.clone());
                drop(var);
                let a = array.borrow();
                match &*a {
                    Var::Array(a) => a.get(&*key).cloned().ok_or_else(|| {
                        Exception::error(format!("can't read \"{name}\": no such variable"))
                    }),
                    _ => Err(Exception::error(format!("can't read \"{name}\": no such variable"))),
                }
            }
            (Var::Array(_), None) => {
                Err(Exception::error(format!("can't read \"{name}\": variable is array"))
                    .with_error_code("TCL READ VARNAME"))
            }
            (Var::Array(a), Some(i)) => a.get(i).cloned().ok_or_else(|| {
                Exception::error(format!("can't read \"{}\": no such element in array", full()))
            }),
            (Var::Scalar(_), Some(_)) => {
                Err(Exception::error(format!("can't read \"{}\": variable isn't array", full())))
            }
            (Var::Undefined | Var::Elem(..), _) => {
                Err(Exception::error(format!("can't read \"{}\": no such variable", full()))
                    .with_error_code(&format!("TCL LOOKUP VARNAME {name}")))
            }
        }
    }

    /// Runs the traces on a variable that is being accessed.
    #[cold]
    pub(crate) fn traced_access(
        &mut self,
        cell: &VarCell,
        name: &str,
        idx: Option<&str>,
        op: u8,
    ) -> Result<(), Exception> {
        let (cell, idx) = deref_elem(cell.clone(), idx);
        self.fire_var_traces(&cell, name, idx.as_deref(), op)
    }

    /// After a traced write: the write traces, then the value the variable
    /// holds now (a trace may change it), or the empty string.
    #[cold]
    fn after_write(&mut self, name: &str, v: Value) -> TclResult {
        let (base, idx) = split_var_name(name);
        let Some(cell) = self.find_var(base) else { return Ok(v) };
        self.traced_access(&cell, base, idx, super::builtins::trace::WRITE)?;
        let (cell, idx) = deref_elem(cell, idx);
        Ok(match (&*cell.borrow(), idx.as_deref()) {
            (Var::Scalar(v), None) => v.clone(),
            (Var::Array(a), Some(i)) => a.get(i).cloned().unwrap_or_default(),
            _ => Value::empty(),
        })
    }

    /// Sets a variable given as `name` or `name(index)`; returns the value.
    pub fn set_var(&mut self, name: &str, v: Value) -> TclResult {
        if name.ends_with("tcl_precision") {
            set_precision(name, &v)?;
        }
        let r = self.set_var_untraced(name, v)?;
        if self.var_traces.is_empty() {
            return Ok(r);
        }
        self.after_write(name, r)
    }

    fn set_var_untraced(&mut self, name: &str, v: Value) -> TclResult {
        let (base, idx) = split_var_name(name);
        let cell = self.var_cell(base);
        let is_link = idx.is_none() && matches!(*cell.borrow(), Var::Elem(..));
        let (cell, idx) =
            if is_link { deref_elem(cell, idx) } else { (cell, idx.map(Cow::Borrowed)) };
        let idx = idx.as_deref();
        let mut var = cell.borrow_mut();
        match idx {
            None => match &mut *var {
                Var::Array(_) => {
                    Err(Exception::error(format!("can't set \"{name}\": variable is array")))
                }
                slot => {
                    *slot = Var::Scalar(v.clone());
                    Ok(v)
                }
            },
            Some(i) => match &mut *var {
                Var::Scalar(_) | Var::Elem(..) => {
                    Err(Exception::error(format!("can't set \"{name}\": variable isn't array")))
                }
                Var::Array(a) => {
                    match a.get_mut(i) {
                        Some(slot) => *slot = v.clone(),
                        None => {
                            a.insert(i.to_string(), v.clone());
                        }
                    }
                    Ok(v)
                }
                slot => {
                    let mut a = ArrayMap::default();
                    a.insert(i.to_string(), v.clone());
                    *slot = Var::Array(a);
                    Ok(v)
                }
            },
        }
    }

    /// Changes a variable's value in place (for `append`, `lappend`, `incr`),
    /// creating it from `init` when it does not exist.
    pub(crate) fn update_var(
        &mut self,
        name: &str,
        init: Option<Value>,
        f: &mut dyn FnMut(&mut Value) -> Result<(), Exception>,
    ) -> TclResult {
        let r = self.update_var_untraced(name, init, f)?;
        if self.var_traces.is_empty() {
            return Ok(r);
        }
        self.after_write(name, r)
    }

    fn update_var_untraced(
        &mut self,
        name: &str,
        init: Option<Value>,
        f: &mut dyn FnMut(&mut Value) -> Result<(), Exception>,
    ) -> TclResult {
        let (base, idx) = split_var_name(name);
        let (cell, idx) = deref_elem(self.var_cell(base), idx);
        let idx = idx.as_deref();
        let mut var = cell.borrow_mut();
        let missing = || Exception::error(format!("can't read \"{name}\": no such variable"));
        let slot: &mut Value = match (&mut *var, idx) {
            (Var::Scalar(v), None) => v,
            (Var::Array(_), None) => {
                return Err(Exception::error(format!("can't set \"{name}\": variable is array")));
            }
            (Var::Scalar(_) | Var::Elem(..), Some(_)) => {
                return Err(Exception::error(format!(
                    "can't set \"{name}\": variable isn't array"
                )));
            }
            (Var::Elem(..), None) => unreachable!("deref_elem followed the link"),
            (Var::Array(a), Some(i)) => {
                if !a.contains_key(i) {
                    a.insert(i.to_string(), init.ok_or_else(missing)?);
                }
                a.get_mut(i).expect("inserted above")
            }
            (slot @ Var::Undefined, i) => {
                let v = init.ok_or_else(missing)?;
                *slot = match i {
                    None => Var::Scalar(v),
                    Some(i) => Var::Array(ArrayMap::from_iter([(i.to_string(), v)])),
                };
                match (slot, i) {
                    (Var::Scalar(v), None) => v,
                    (Var::Array(a), Some(i)) => a.get_mut(i).expect("just created"),
                    _ => unreachable!("slot was just assigned"),
                }
            }
        };
        f(slot)?;
        Ok(slot.clone())
    }

    pub fn unset_var(&mut self, name: &str) -> Result<(), Exception> {
        let (base, idx) = split_var_name(name);
        let err = || {
            Exception::error(format!("can't unset \"{name}\": no such variable"))
                .with_error_code(&format!("TCL LOOKUP VARNAME {base}"))
        };
        let found = self.find_var(base).ok_or_else(err)?;
        if idx.is_none() && matches!(*found.borrow(), Var::Elem(..)) {
            // Unsetting the alias unsets the element; the alias stays.
            let (array, key) = deref_elem(found, None);
            let key = key.expect("an element link");
            let r = match &mut *array.borrow_mut() {
                Var::Array(a) => a.shift_remove(&*key).map(|_| ()).ok_or_else(err),
                _ => Err(err()),
            };
            if r.is_ok() && !self.var_traces.is_empty() {
                self.fire_unset_traces(&array, base, Some(&key));
            }
            return r;
        }
        let cell = found;
        let mut var = cell.borrow_mut();
        match (&mut *var, idx) {
            (Var::Undefined, _) => {
                drop(var);
                if !self.var_traces.is_empty() {
                    // A traced variable that is not set: its unset traces
                    // run all the same.
                    self.fire_unset_traces(&cell, base, None);
                }
                return Err(err());
            }
            (Var::Array(a), Some(i)) => {
                if a.shift_remove(i).is_none() {
                    return Err(Exception::error(format!(
                        "can't unset \"{name}\": no such element in array"
                    )));
                }
                drop(var);
                if !self.var_traces.is_empty() {
                    self.fire_unset_traces(&cell, base, Some(i));
                }
                return Ok(());
            }
            (Var::Scalar(_) | Var::Elem(..), Some(_)) => {
                return Err(Exception::error(format!(
                    "can't unset \"{name}\": variable isn't array"
                )));
            }
            (slot, None) => *slot = Var::Undefined,
        }
        drop(var);
        if !self.var_traces.is_empty() {
            self.fire_unset_traces(&cell, base, None);
            if !matches!(*cell.borrow(), Var::Undefined) {
                // An unset trace set it again.
                return Ok(());
            }
        }
        // A variable another frame links to (`upvar`, `global`) stays as
        // an undefined slot, so the link holds: setting it again sets the
        // linked variable, as in Tcl.
        if Rc::strong_count(&cell) <= 2 {
            let (frame, local) = self.frame_for(base);
            self.frames[frame].remove(&local);
        }
        Ok(())
    }

    pub fn var_exists(&mut self, name: &str) -> bool {
        let (base, idx) = split_var_name(name);
        let Some(cell) = self.find_var(base) else { return false };
        let (cell, idx) = deref_elem(cell, idx);
        let idx = idx.as_deref();
        let var = cell.borrow();
        match (&*var, idx) {
            (Var::Scalar(_), None) | (Var::Array(_), None) => true,
            (Var::Array(a), Some(i)) => a.contains_key(i),
            _ => false,
        }
    }

    /// The frame index for a Tcl level spec (`1`, `#0`), relative to now.
    pub(crate) fn resolve_level(&self, spec: &str) -> Result<usize, Exception> {
        let bad = || Exception::error(format!("bad level \"{spec}\""));
        // Integers as Tcl reads them (`-0`, `0x1`, blanks around).
        let int = |s: &str| {
            super::number::parse_int(s).and_then(|n| usize::try_from(n).ok()).ok_or_else(bad)
        };
        if let Some(abs) = spec.strip_prefix('#') {
            let n = int(abs)?;
            let mut f = self.cur;
            loop {
                if self.frames[f].level == n {
                    return Ok(f);
                }
                if f == 0 || self.frames[f].level < n {
                    return Err(bad());
                }
                f = self.frames[f].caller;
            }
        }
        let n = int(spec)?;
        let mut f = self.cur;
        for _ in 0..n {
            if self.frames[f].level == 0 {
                return Err(bad());
            }
            f = self.frames[f].caller;
        }
        Ok(f)
    }

    /// Makes `local` in the current frame an alias of `other` in `frame`.
    pub(crate) fn link_var(
        &mut self,
        frame: usize,
        other: &str,
        local: &str,
    ) -> Result<(), Exception> {
        let (frame, other) = match other.strip_prefix("::") {
            Some(rest) => (0, rest),
            None => (frame, other),
        };
        let (other, elem) = split_var_name(other);
        if split_var_name(local).1.is_some() {
            return Err(Exception::error(format!(
                "bad variable name \"{local}\": can't create a scalar variable that looks like an array element"
            )));
        }
        let cell = match self.frames[frame].get(other) {
            Some(c) => c,
            None => {
                let c = Rc::new(RefCell::new(Var::Undefined));
                self.frames[frame].insert(Rc::from(other), c.clone());
                c
            }
        };
        if let Some(k) = elem
            && matches!(*cell.borrow(), Var::Scalar(_))
        {
            return Err(Exception::error(format!(
                "can't access \"{other}({k})\": variable isn't array"
            )));
        }
        let cell = match elem {
            Some(k) => Rc::new(RefCell::new(Var::Elem(cell, Rc::from(k)))),
            None => cell,
        };
        if frame == self.cur && elem.is_none() && other == local {
            return Err(Exception::error("can't upvar from variable to itself"));
        }
        if let Some(existing) = self.frames[self.cur].get(local) {
            if Rc::ptr_eq(&existing, &cell) {
                return Ok(());
            }
            // A link may be moved to another variable; a variable stays.
            if !matches!(*existing.borrow(), Var::Undefined)
                && !self.frames[self.cur].links().iter().any(|l| &**l == local)
            {
                return Err(Exception::error(format!("variable \"{local}\" already exists")));
            }
        }
        let local: Rc<str> = Rc::from(local);
        self.frames[self.cur].add_link(local.clone());
        self.frames[self.cur].insert(local, cell);
        Ok(())
    }

    /// Runs `f` with the frame at index `frame` as the current one.
    pub(crate) fn in_frame(
        &mut self,
        frame: usize,
        f: impl FnOnce(&mut Interp) -> TclResult,
    ) -> TclResult {
        let saved = self.cur;
        self.cur = frame;
        // Code runs in the namespace of the frame it runs in (`uplevel`).
        let ns = std::mem::replace(&mut self.ns, self.frames[frame].ns.clone());
        let r = f(self);
        self.ns = ns;
        self.cur = saved;
        r
    }

    pub(crate) fn level(&self) -> usize {
        self.frames[self.cur].level
    }

    /// The globals every Tcl 8.6 interpreter has: `tcl_version`,
    /// `tcl_patchLevel`, `tcl_platform`, `tcl_precision` (0: shortest), and
    /// an empty `auto_path` and `env` (the host fills them).
    fn set_tcl_globals(&mut self) {
        use super::builtins::{TCL_PATCHLEVEL, TCL_VERSION};
        let set = |i: &mut Interp, name: &str, v: &str| {
            let _ = i.set_var(name, Value::from(v));
        };
        set(self, "tcl_version", TCL_VERSION);
        set(self, "tcl_precision", "0");
        set(self, "tcl_patchLevel", TCL_PATCHLEVEL);
        let byte_order = if cfg!(target_endian = "little") { "littleEndian" } else { "bigEndian" };
        let pointer = std::mem::size_of::<usize>().to_string();
        for (k, v) in [
            ("byteOrder", byte_order),
            ("engine", "Tcl"),
            ("machine", std::env::consts::ARCH),
            ("os", if cfg!(target_os = "linux") { "Linux" } else { std::env::consts::OS }),
            ("osVersion", ""),
            ("pathSeparator", if cfg!(windows) { ";" } else { ":" }),
            ("platform", if cfg!(windows) { "windows" } else { "unix" }),
            ("pointerSize", &pointer),
            ("threaded", "1"),
            ("user", ""),
            ("wordSize", &pointer),
        ] {
            set(self, &format!("tcl_platform({k})"), v);
        }
        set(self, "auto_path", "");
        // A script runs non-interactively; the REPL sets it to 1.
        set(self, "tcl_interactive", "0");
        // No script library ships with rayshell; TCL_LIBRARY names one.
        set(self, "tcl_library", &std::env::var("TCL_LIBRARY").unwrap_or_default());
    }

    /// Commands run so far (`info cmdcount`).
    pub(crate) fn commands_run(&self) -> u64 {
        self.commands_run
    }
}

/// `expr`'s result: the operand as a value; NaN is a domain error.
pub(crate) fn expr_result(op: Operand) -> TclResult {
    let nan = match &op {
        Operand::Int(_) => false,
        Operand::Dbl(d) => d.is_nan(),
        Operand::Big(_) => false,
        Operand::Str(v) => matches!(v.as_num(), Some(Num::Double(d)) if d.is_nan()),
    };
    let v = op.into_value();
    if nan {
        return Err(Exception::error("domain error: argument not in valid range")
            .with_error_code("ARITH DOMAIN {domain error: argument not in valid range}"));
    }
    Ok(v)
}

/// A condition's truth (`if`, `while`, `for`).
#[inline]
pub(crate) fn cond_truth(v: Operand) -> Result<bool, Exception> {
    match v {
        Operand::Int(i) => Ok(i != 0),
        Operand::Dbl(d) => Ok(d != 0.0),
        Operand::Big(_) => Ok(true),
        Operand::Str(v) => v.as_bool(),
    }
}

#[inline(never)]
fn call_numeric(
    interp: &mut Interp,
    arity: usize,
    usage: &str,
    f: &NumericFn,
    argv: &[Value],
) -> TclResult {
    if argv.len() != arity + 1 {
        return Err(Exception::wrong_args(usage));
    }
    let mut nums: SmallVec<[Num; 8]> = SmallVec::new();
    for (i, v) in argv[1..].iter().enumerate() {
        nums.push(v.as_num().ok_or_else(|| {
            // Name the command and the argument, as the usage spells it.
            let mut words = usage.split_whitespace();
            let name = words.next().unwrap_or("");
            let arg = words.nth(i).unwrap_or("?");
            Exception::error(format!("{name}: {arg}: expected number but got \"{}\"", v.as_str()))
        })?);
    }
    Ok(match f(interp, &nums)? {
        Some(n) => Value::from_num(n),
        None => Value::empty(),
    })
}

/// `set tcl_precision N`: doubles print with N significant digits
/// (0, the default, is the shortest that reads back), as Tcl's own trace
/// on the variable does it.
#[cold]
fn set_precision(name: &str, v: &Value) -> Result<(), Exception> {
    if name != "tcl_precision" && name != "::tcl_precision" {
        return Ok(());
    }
    match v.as_str().trim().parse::<usize>() {
        Ok(n) if n <= 17 => {
            super::number::set_precision(n);
            Ok(())
        }
        _ => Err(Exception::error(format!("can't set \"{name}\": improper value for precision"))),
    }
}

fn too_deep() -> Exception {
    Exception::error("too many nested evaluations (infinite loop?)")
}

/// The error for output that could not be written to stdout.
fn stdout_error(e: &std::io::Error) -> Exception {
    // As Tcl words it: "no space left on device", not Rust's "(os error 28)".
    let text = e.to_string();
    let why = text.split(" (os error").next().unwrap_or(&text).to_lowercase();
    let err = Exception::error(format!("error writing \"stdout\": {why}"));
    // Tcl's errorCode for a reader that went away.
    if e.kind() == std::io::ErrorKind::BrokenPipe {
        err.with_error_code("POSIX EPIPE {broken pipe}")
    } else {
        err
    }
}

/// A command's result when it left a string form that could not be made,
/// or took the heap past the budget: an error, unless one is already on its
/// way (with its trace) or the script is exiting.
#[cold]
#[inline(never)]
pub(crate) fn after_growth(r: TclResult) -> TclResult {
    let pending = value::take_pending();
    match r {
        Err(e) if matches!(e.code, Code::Error | Code::Exit(_)) => Err(e),
        r => match pending {
            Some(e) => Err(e),
            None => crate::mem::check().map_err(Exception::from).and(r),
        },
    }
}

pub(crate) fn too_long() -> Exception {
    Exception::error(format!(
        "string too long: rayshell values are limited to {MAX_VALUE_LEN} bytes"
    ))
}

/// Checks a string of `n` bytes against the value cap and the budget.
#[inline]
pub(crate) fn check_len(n: usize) -> Result<(), Exception> {
    // Small growth is left to the check after each command.
    if n < 1 << 16 {
        return Ok(());
    }
    if n > MAX_VALUE_LEN {
        return Err(too_long());
    }
    Ok(crate::mem::reserve(n)?)
}

/// The most elements a list may have (64 Mi: a runaway `lappend` loop
/// stops at a few GiB, not when the machine runs out).
pub const MAX_LIST_LEN: usize = 1 << 26;

/// Checks a list of `n` elements against the list cap and the budget (the
/// elements' own bytes are the caller's to check).
pub(crate) fn check_list_len(n: usize) -> Result<(), Exception> {
    if n > MAX_LIST_LEN {
        return Err(Exception::error(format!(
            "list too long: rayshell lists are limited to {MAX_LIST_LEN} elements"
        )));
    }
    if n < 1 << 13 {
        return Ok(());
    }
    Ok(crate::mem::reserve_n(n, std::mem::size_of::<Value>())?)
}

/// Logs a failing command into errorInfo as Tcl does: once per
/// evaluation unit (the innermost command of a proc body, say, and not the
/// commands around it in that body), but every command when evaluating
/// `direct`ly (a source file's top level, where Tcl compiles nothing).
impl Interp {
    /// Logs the command an error passed through (`add_trace_text`), and
    /// where it left from in `-errorstack`: the first logging notes the
    /// failing command, each logging in a proc's body that call, and one
    /// under `uplevel` how many levels up it ran (TclLogCommandInfo).
    pub(crate) fn add_trace(
        &self,
        e: &mut Exception,
        text: &str,
        line: u32,
        first_line: u32,
        file: &Option<Rc<str>>,
        direct: bool,
    ) {
        if e.code == Code::Error && !e.logged {
            let stack = e.ext_mut().errorstack.get_or_insert_with(|| {
                vec![Value::from("INNER"), Value::from(text.trim_end_matches([' ', '\t']))]
            });
            let top = self.frames.len() - 1;
            let f = &self.frames[top];
            if f.objv.is_empty() {
                // The global frame (or a coroutine's start): nothing to say.
            } else if self.cur != top {
                stack.push(Value::from("UP"));
                stack.push(Value::from_int((f.level - self.frames[self.cur].level) as i64));
            } else {
                stack.push(Value::from("CALL"));
                stack.push(Value::from_list(f.objv.clone()));
            }
        }
        add_trace_text(e, text, line, first_line, file, direct);
    }
}

/// The innermost command of an error in compiled code, as Tcl's
/// `-errorstack` names it: the instruction and its operands (`error msg`
/// compiles to `returnImm`, reading a variable to `loadStk`, a call to
/// `invokeStk1`).
fn inner_context(argv: &[Value], e: &Exception) -> Value {
    let mut words = Vec::with_capacity(argv.len() + 1);
    if matches!(argv[0].as_str(), "error" | "throw" | "return") {
        let opts = Value::from_list(e.return_opts().to_vec());
        words.extend([Value::from("returnImm"), e.value.clone(), opts]);
    } else if argv.len() == 2 && argv[0].as_str() == "set" {
        return Value::from("loadStk");
    } else {
        words.push(Value::from("invokeStk1"));
        words.extend(argv.iter().cloned());
    }
    Value::from_list(words)
}

fn add_trace_text(
    e: &mut Exception,
    text: &str,
    line: u32,
    first_line: u32,
    file: &Option<Rc<str>>,
    direct: bool,
) {
    if e.code != Code::Error {
        // break/continue/return: no trace, but remember where, in case it
        // ends up outside any loop or proc ("file:line: invoked break ...").
        if e.loc.is_none() && file.is_some() {
            e.loc = Some(Loc { file: file.clone(), line });
        }
        return;
    }
    if e.abs_line == 0 || direct {
        e.abs_line = line;
        e.script_line = line + 1 - first_line;
    }
    if e.loc.is_none() && file.is_some() {
        e.loc = Some(Loc { file: file.clone(), line });
    }
    if !e.logged {
        let text = truncate_cmd(text);
        if e.traced {
            e.trace.push_str("\n    invoked from within\n\"");
        } else {
            e.trace.push_str("\n    while executing\n\"");
            e.traced = true;
        }
        e.trace.push_str(&text);
        e.trace.push('"');
    }
    e.logged = !direct;
}

/// An error leaving an evaluation unit whose text starts at `first_line`:
/// its line within the unit (for `(procedure "f" line N)`), and the next
/// unit out logs its own command again.
#[cold]
#[inline(never)]
fn end_unit(mut e: Exception, first_line: u32) -> Exception {
    if e.abs_line > 0 {
        e.script_line = (e.abs_line + 1).saturating_sub(first_line).max(1);
    }
    e.logged = false;
    e.abs_line = 0;
    e
}

/// What leaves a proc's body, as the caller sees it: `return` ends here,
/// an error gains the proc's line, `break` and `continue` are errors.
#[cold]
#[inline(never)]
fn proc_exit(p: &Proc, name: &Value, mut e: Exception) -> TclResult {
    match e.code {
        Code::Return => finish_return(e),
        Code::Error => {
            let what = if p.lambda.is_some() { "lambda term" } else { "procedure" };
            let t = format!(
                "\n    ({what} \"{}\" line {})",
                truncate_cmd(name.as_str()),
                e.script_line
            );
            e.trace.push_str(&t);
            Err(e)
        }
        Code::Break => Err(Exception::error("invoked \"break\" outside of a loop")),
        Code::Continue => Err(Exception::error("invoked \"continue\" outside of a loop")),
        Code::Exit(_) | Code::Other(_) => Err(e),
    }
}

fn proc_usage(p: &Proc, name: &Value) -> Exception {
    let mut usage =
        if p.lambda.is_some() { "apply lambdaExpr".to_string() } else { name.as_str().to_string() };
    for (i, (param, default)) in p.params.iter().enumerate() {
        if p.variadic && i == p.params.len() - 1 {
            usage.push_str(" ?arg ...?");
        } else if default.is_some() {
            usage.push_str(&format!(" ?{param}?"));
        } else {
            usage.push_str(&format!(" {param}"));
        }
    }
    Exception::wrong_args(&usage)
}

/// Applies `return -level`: one level is used up at each proc boundary.
pub(crate) fn finish_return(mut e: Exception) -> TclResult {
    if e.level > 1 {
        e.level -= 1;
        return Err(e);
    }
    let e = e.into_data();
    // Where the `return` was stays known: an error (or a bad code) that
    // ends the script is reported at its line.
    match e.return_code {
        None => Ok(e.value),
        Some(Code::Error) => {
            let mut err = Exception::error(e.value.as_str().to_string());
            err.error_code = e.error_code;
            err.ext = e.ext;
            err.loc = e.loc;
            if e.traced {
                err.trace = e.trace;
                err.traced = true;
            }
            Err(err)
        }
        Some(code) => {
            let mut err = Exception::flow(code, e.value);
            err.loc = e.loc;
            Err(err)
        }
    }
}
