//! `coroutine`, `yield`, `yieldto` and `info coroutine`, as Tcl 8.6 has
//! them: `coroutine name cmd ?arg ...?` runs `cmd` at the global level
//! until it yields; `name ?value?` resumes it (the `yield` returns
//! `value`) and returns what it yields next, or its result when it ends,
//! which deletes the command.
//!
//! The evaluator recurses on the native stack, so a coroutine gets a
//! native stack of its own: a stackful generator (the `generator` crate).
//! The interpreter's state is moved, by value, to whichever side runs:
//! the resumer sends it in and the coroutine hands it back at each
//! `yield`, so both sides work on one `Interp` through plain `&mut`. At a
//! yield the coroutine's call frames are lifted off the frame stack and
//! put back, at the resumer's depth, when it resumes.

use std::rc::Rc;

use rustc_hash::FxHashMap;

use super::check_args;
use crate::interp::error::{Code, Exception, TclResult};
use crate::interp::eval::{Interp, MAX_NATIVE_DEPTH};
use crate::interp::value::Value;

pub(crate) const COMMANDS: &[super::Entry] = &[
    (
        "coroutine",
        cmd_coroutine,
        "name cmd ?arg ...?",
        "run a command as a coroutine that can yield and be resumed",
    ),
    ("yield", cmd_yield, "?value?", "suspend the running coroutine, handing out a value"),
    (
        "yieldto",
        cmd_yieldto,
        "command ?arg ...?",
        "suspend the running coroutine; its resumer runs a command in its place",
    ),
];

/// Each coroutine's own native stack (mapped lazily: untouched pages cost
/// nothing), and the evaluator depth it may use there. A release build
/// was measured to fit the main thread's whole `MAX_NATIVE_DEPTH` (12,000)
/// into 64 MiB; 4,000 in 128 MiB leaves room for unoptimized builds. A
/// proc that recurses through `expr` reaches about 660 levels inside a
/// coroutine (1,000 outside, Tcl's limit).
const STACK_BYTES: usize = 128 << 20;
const CORO_DEPTH: usize = 4000;
/// Live coroutines at most (each holds a mapped stack).
const MAX_COROUTINES: usize = 10_000;
/// What the budget counts for each live coroutine's stack, which the
/// allocator does not see: a coroutine that recursed a little touches
/// about this much (45 of them held 376 MB).
const CORO_CHARGE: usize = 8 << 20;

thread_local! {
    static MAKING_STACK: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

/// Whether this thread is mapping a coroutine's stack, whose failure is a
/// panic of the generator crate that `coroutine` turns into an error: a
/// host's panic hook should not print it.
pub fn making_a_stack() -> bool {
    MAKING_STACK.with(|m| m.get())
}

/// What a resumer sends in: the interpreter, the value `yield` returns
/// (or the words to run, at the start), and the frame index where the
/// coroutine's frames go now.
struct Resume {
    interp: Box<Interp>,
    arg: Vec<Value>,
    base: usize,
    /// The coroutine is being deleted: its `yield` unwinds it instead.
    kill: bool,
}

/// What a coroutine hands back: the interpreter and the value it yields
/// or its result, or a command to run in its place (`yieldto`).
struct Reply {
    interp: Box<Interp>,
    result: TclResult,
    yield_to: Option<Vec<Value>>,
}

type Gen = generator::Generator<'static, Resume, Reply>;

/// The suspended coroutines (a running one's slot is empty), and whether
/// each waits in `yieldto` (which takes any number of values back).
#[derive(Default)]
pub(crate) struct Coroutines {
    gens: FxHashMap<Rc<str>, (Option<Gen>, bool)>,
}

impl Interp {
    /// A deleted coroutine: a suspended one is resumed so that its
    /// `yield` unwinds it, as Tcl rewinds it (its procs return, their
    /// variables' unset traces run); a running one ends at its next yield.
    pub(crate) fn delete_coroutine(&mut self, key: &str) {
        let Some((Some(co), _)) = self.coroutines.gens.remove(key) else { return };
        let _ = switch_into(self, &Rc::from(key), co, Vec::new(), true);
    }
}

/// The interpreter registers each side keeps for itself across a switch.
struct Registers {
    cur: usize,
    ns: Rc<str>,
    depth: usize,
    levels: usize,
    direct: bool,
    coro: Option<Rc<str>>,
    base: usize,
    cmd_base: usize,
}

impl Registers {
    fn save(i: &Interp) -> Registers {
        Registers {
            cur: i.cur,
            ns: i.ns.clone(),
            depth: i.depth,
            levels: i.levels,
            direct: i.direct,
            coro: i.current_coro.clone(),
            base: i.coro_base,
            cmd_base: i.coro_cmd_base,
        }
    }

    fn restore(self, i: &mut Interp) {
        i.cur = self.cur;
        i.ns = self.ns;
        i.depth = self.depth;
        i.levels = self.levels;
        i.direct = self.direct;
        i.current_coro = self.coro;
        i.coro_base = self.base;
        i.coro_cmd_base = self.cmd_base;
    }
}

/// The coroutine's own stack starts here: the words come in with the
/// first resume, and the result goes out as the generator's return.
#[allow(deprecated)] // the free-function API reaches the running generator from any depth
fn coro_main() -> Reply {
    let Some(Resume { interp: mut ip, arg: words, .. }) = generator::get_yield::<Resume>() else {
        unreachable!("a coroutine is always started with its words")
    };
    // It runs at the global level, in the global namespace, with the
    // native depth it has room for on this stack.
    ip.cur = 0;
    ip.ns = Rc::from("");
    ip.depth = MAX_NATIVE_DEPTH - CORO_DEPTH;
    ip.levels = 0;
    ip.direct = false;
    let result = match ip.invoke(&words) {
        Err(mut e) if e.code == Code::Error => {
            // The command the coroutine ran, as the resumer's trace shows it.
            let text = Value::from_list(words).as_str().to_string();
            e.trace.push_str(&format!("\n    invoked from within\n\"{text}\""));
            Err(e)
        }
        r => r,
    };
    Reply { interp: ip, result, yield_to: None }
}

/// Hands the interpreter to a coroutine until it yields or ends.
fn switch_into(
    interp: &mut Interp,
    key: &Rc<str>,
    mut co: Gen,
    arg: Vec<Value>,
    kill: bool,
) -> (Gen, TclResult, Option<Vec<Value>>) {
    let saved = Registers::save(interp);
    interp.current_coro = Some(key.clone());
    interp.coro_base = interp.frames.len();
    interp.coro_cmd_base = interp.cmd_frames.len();
    let base = interp.coro_base;
    let state = Box::new(std::mem::replace(interp, Interp::placeholder()));
    let reply = co.send(Resume { interp: state, arg, base, kill });
    let Reply { interp: state, result, yield_to } = reply;
    *interp = *state;
    saved.restore(interp);
    (co, result, yield_to)
}

/// Runs the coroutine `key` until it yields or ends; `arg` is what its
/// `yield` returns (the words to run, the first time).
fn resume(interp: &mut Interp, key: &Rc<str>, arg: Vec<Value>) -> TclResult {
    let name = key.clone();
    let co = match interp.coroutines.gens.get_mut(key).map(|s| s.0.take()) {
        Some(Some(g)) => g,
        Some(None) => {
            return Err(Exception::error(format!("coroutine \"{name}\" is already running"))
                .with_error_code("TCL COROUTINE BUSY"));
        }
        None => return Err(Exception::error(format!("invalid command name \"{name}\""))),
    };
    let (co, result, yield_to) = switch_into(interp, key, co, arg, false);
    if co.is_done() {
        interp.coroutines.gens.remove(key);
        let _ = interp.rename_command(key, "");
    } else if let Some(slot) = interp.coroutines.gens.get_mut(key) {
        *slot = (Some(co), yield_to.is_some());
    }
    match yield_to {
        Some(words) => interp.invoke(&words),
        None => result,
    }
}

/// Suspends the running coroutine with `reply` for its resumer; returns
/// what the resumer sends back.
#[allow(deprecated)] // see coro_main
fn suspend(
    interp: &mut Interp,
    result: TclResult,
    yield_to: Option<Vec<Value>>,
) -> Result<Vec<Value>, Exception> {
    let base = interp.coro_base;
    let frames = interp.frames.split_off(base.min(interp.frames.len()));
    let cmd_frames = interp.cmd_frames.split_off(interp.coro_cmd_base.min(interp.cmd_frames.len()));
    let mine = Registers::save(interp);
    let state = Box::new(std::mem::replace(interp, Interp::placeholder()));
    let back = generator::yield_::<Resume, Reply>(Reply { interp: state, result, yield_to });
    let Some(Resume { interp: state, arg, base: new_base, kill }) = back else {
        unreachable!("a coroutine is resumed with a value")
    };
    *interp = *state;
    // Its frames go back on top of the resumer's, their links moved along.
    let at = |i: usize| if i >= base { i - base + new_base } else { i };
    for mut f in frames {
        f.caller = at(f.caller);
        interp.frames.push(f);
    }
    let cmd_base = interp.cmd_frames.len();
    for mut f in cmd_frames {
        f.frame = at(f.frame);
        interp.cmd_frames.push(f);
    }
    let cur = at(mine.cur);
    mine.restore(interp);
    interp.cur = cur;
    interp.coro_base = new_base;
    interp.coro_cmd_base = cmd_base;
    if kill {
        return Err(Exception::flow(Code::Exit(0), Value::from("coroutine deleted")));
    }
    Ok(arg)
}

fn cmd_coroutine(interp: &mut Interp, argv: &[Value]) -> TclResult {
    check_args(argv, 3, usize::MAX, "name cmd ?arg ...?")?;
    if interp.coroutines.gens.len() >= MAX_COROUTINES {
        return Err(Exception::error(format!(
            "too many coroutines: rayshell keeps at most {MAX_COROUTINES} alive"
        )));
    }
    // The budget must have room for every live coroutine's stack, this
    // one's included, beside the heap in use: what it touches, or under an
    // address-space limit (where a mapping counts whole) all of it.
    let charge = if crate::mem::address_limited() { STACK_BYTES } else { CORO_CHARGE };
    crate::mem::reserve(charge.saturating_mul(interp.coroutines.gens.len() + 1))?;
    let key: Rc<str> = Rc::from(interp.new_command_key(argv[1].as_str())?);
    // A failure to map the stack is an error, not a crash (the generator
    // crate panics; the host's panic hook stays quiet meanwhile).
    MAKING_STACK.with(|m| m.set(true));
    let co =
        std::panic::catch_unwind(|| generator::Gn::<Resume>::new_opt(STACK_BYTES / 8, coro_main));
    MAKING_STACK.with(|m| m.set(false));
    let co =
        co.map_err(|_| Exception::error("couldn't create a coroutine: no memory for its stack"))?;
    let k = key.clone();
    interp.register_host(&key, "?value?", "resume the coroutine", move |i, argv| {
        let in_yieldto = i.coroutines.gens.get(&k).is_some_and(|s| s.1);
        if in_yieldto {
            return resume(i, &k, argv[1..].to_vec());
        }
        if argv.len() > 2 {
            return Err(Exception::wrong_args(&format!("{} ?arg?", argv[0].as_str())));
        }
        resume(i, &k, vec![argv.get(1).cloned().unwrap_or_default()])
    });
    interp.coroutines.gens.insert(key.clone(), (Some(co), false));
    // The command is found from here, though it runs at the global level.
    let mut words = argv[2..].to_vec();
    if let Some(k) = interp.command_key(words[0].as_str())
        && k != words[0].as_str()
    {
        words[0] = Value::from_string(format!("::{k}"));
    }
    resume(interp, &key, words)
}

fn not_in_coroutine(what: &str) -> Exception {
    Exception::error(format!("{what} can only be called in a coroutine"))
        .with_error_code("TCL COROUTINE ILLEGAL_YIELD")
}

fn cmd_yield(interp: &mut Interp, argv: &[Value]) -> TclResult {
    check_args(argv, 1, 2, "?value?")?;
    if interp.current_coro.is_none() {
        return Err(not_in_coroutine("yield"));
    }
    let v = argv.get(1).cloned().unwrap_or_default();
    let mut arg = suspend(interp, Ok(v), None)?;
    Ok(arg.pop().unwrap_or_default())
}

fn cmd_yieldto(interp: &mut Interp, argv: &[Value]) -> TclResult {
    check_args(argv, 2, usize::MAX, "command ?arg ...?")?;
    if interp.current_coro.is_none() {
        return Err(not_in_coroutine("yieldto"));
    }
    let args = suspend(interp, Ok(Value::empty()), Some(argv[1..].to_vec()))?;
    Ok(Value::from_list(args))
}

/// `info coroutine`: the running coroutine's full name, or nothing.
pub(crate) fn info_coroutine(interp: &Interp) -> Value {
    match &interp.current_coro {
        Some(k) => Value::from_string(format!("::{k}")),
        None => Value::empty(),
    }
}
