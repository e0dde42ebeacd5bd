//! Compiled proc bodies: a proc's body, and the literal bodies of the
//! `if`, `while`, `for` and `foreach` in it, become a tree of `Op`s in which
//! local variables are slot indices and the commands Tcl compiles inline
//! (`set`, `incr`, `append`, `lappend`, `if`, `while`, `for`, `foreach`,
//! `expr`, `return`, `break`, `continue`) run without an argument vector,
//! a command lookup or a name hash. Every other command is a call site that
//! caches the command its name resolves to, checked against `cmd_epoch`.
//!
//! The compiled form is an optimisation only, never a second semantics:
//! each `Op` keeps the parsed command it came from, and runs that command
//! the ordinary way (`Interp::eval_command`) whenever the fast path might
//! differ: a command Tcl compiles was redefined since (`inline_epoch`, as
//! Tcl's compile epoch), or a variable or command trace exists. Variables
//! are reached by name as before from everywhere else (`upvar`, `uplevel`,
//! `info vars`, traces): `Frame::get` looks a name up among the slots first.
//!
//! The shape follows Tcl's own bytecode compiler (tclCompCmds.c: which
//! commands compile, the compiled-local table of a proc) and molt's plain
//! tree-walking style; it is a tree, not bytecode, so that errors keep
//! exactly the command text and line the interpreter reports.

use std::cell::RefCell;
use std::rc::Rc;

use smallvec::SmallVec;

use super::cmdframe::At;
use super::error::{Code, Exception, TclResult};
use super::eval::{CommandKind, Interp, Proc, Var, cond_truth, expr_result};
use super::expr::{self, BinOp, Expr, Func, Operand, UnOp};
use super::number::Num;
use super::parser::{Command, Part, Script, VarName, Word};
use super::value::{Rep, Value};

/// The commands compiled inline. Redefining any of them (in any
/// namespace) bumps `Interp::inline_epoch` and so recompiles.
pub(crate) const INLINE_OPS: &[&str] = &[
    "set", "incr", "append", "lappend", "if", "while", "for", "foreach", "expr", "return", "break",
    "continue",
];

/// Nesting of literal bodies compiled inline; deeper ones run as ordinary
/// commands (so compiling never recurses without a bound).
const MAX_NESTING: usize = 16;

/// A proc's compiled body and its local-variable table.
pub(crate) struct CompiledProc {
    /// Slot names: the parameters first, then the locals in the order the
    /// body first names them.
    pub(crate) names: Rc<[Rc<str>]>,
    pub(crate) body: Body,
}

impl Body {
    pub(crate) fn first_line(&self) -> u32 {
        self.script.first_line
    }

    pub(crate) fn script(&self) -> &Script {
        &self.script
    }
}

impl CompiledProc {
    /// Whether nothing it inlines has changed since it was compiled.
    pub(crate) fn is_current(&self, interp: &Interp) -> bool {
        self.body.epoch == interp.inline_epoch
    }
}

/// A compiled script: its source (for errorInfo and the slow path) and
/// one `Op` per command.
pub(crate) struct Body {
    script: Rc<Script>,
    ops: Vec<Op>,
    /// The `inline_epoch` it was compiled in.
    epoch: u64,
}

/// How a compiled body ended, other than by an error.
pub(crate) enum Outcome {
    Normal(Value),
    Return(Value),
    Break,
    Continue,
}

/// What a loop does after its body.
enum Step {
    Go,
    Stop,
    /// Leave the loop's command with this outcome (`return`).
    Out(Outcome),
}

/// A local variable: its slot, and its name (for messages and the slow
/// path).
type Local = (u32, Rc<str>);

enum Op {
    /// Any command: the words, and the command the first one last
    /// resolved to (with the `cmd_epoch` of that resolution).
    Call {
        words: Vec<Word>,
        cache: RefCell<Option<(u64, CommandKind)>>,
        /// Its index among its body's commands (`info frame`).
        at: u32,
    },
    Get(Local),
    Set(Local, Word),
    Incr(Local, By),
    Append(Local, Vec<Word>),
    Lappend(Local, Vec<Word>),
    If {
        arms: Vec<(CExpr, Body)>,
        otherwise: Option<Body>,
    },
    /// `for`, and `while` (no start or next script).
    For {
        start: Option<Body>,
        test: CExpr,
        next: Option<Body>,
        body: Body,
    },
    Foreach(Local, Word, Body),
    Expr(CExpr),
    Return(Option<Word>),
    Break,
    Continue,
}

/// `incr`'s amount.
enum By {
    One,
    /// A literal integer, read once at compile time.
    Const(i64),
    Word(Word),
}

/// A compiled expression: `expr`'s tree with locals read by slot, as
/// plain numbers when they hold one.
enum CExpr {
    Lit(Operand),
    Local(u32, Rc<str>),
    Word(Word),
    Unary(UnOp, Box<CExpr>),
    Binary(BinOp, Box<CExpr>, Box<CExpr>),
    And(Box<CExpr>, Box<CExpr>),
    Or(Box<CExpr>, Box<CExpr>),
    Ternary(Box<CExpr>, Box<CExpr>, Box<CExpr>),
    Call(Func, Vec<CExpr>),
    Custom(Rc<str>, Vec<CExpr>),
}

/// Errors are boxed inside compiled code, so the common outcomes travel
/// in registers.
type Run<T> = Result<T, Box<Exception>>;

struct Compiler<'a> {
    interp: &'a Interp,
    names: Vec<Rc<str>>,
    depth: usize,
}

/// Whether a variable name can be a slot: a plain local name.
pub(crate) fn is_local_name(name: &str) -> bool {
    !name.is_empty() && !name.contains("::") && !name.contains('(') && name != "tcl_precision"
}

impl Compiler<'_> {
    fn slot(&mut self, name: &str) -> Local {
        match self.names.iter().position(|n| &**n == name) {
            Some(i) => (i as u32, self.names[i].clone()),
            None => {
                self.names.push(Rc::from(name));
                ((self.names.len() - 1) as u32, self.names[self.names.len() - 1].clone())
            }
        }
    }

    /// The slot of a literal variable-name word, if it names a local.
    fn local_word(&mut self, w: &Word) -> Option<Local> {
        match w {
            Word::Lit(v) if is_local_name(v.as_str()) => Some(self.slot(v.as_str())),
            _ => None,
        }
    }

    fn body(&mut self, script: Rc<Script>) -> Body {
        self.depth += 1;
        let ops =
            script.cmds.iter().enumerate().map(|(i, c)| self.command(&c.words, i as u32)).collect();
        self.depth -= 1;
        Body { script, ops, epoch: self.interp.inline_epoch }
    }

    /// A literal word's script, compiled, when nesting allows.
    fn nested(&mut self, w: &Word) -> Option<Body> {
        match w {
            Word::Lit(v) if self.depth < MAX_NESTING => Some(self.body(Interp::script_of(v))),
            _ => None,
        }
    }

    fn expr(&mut self, w: &Word) -> Option<CExpr> {
        let Word::Lit(v) = w else { return None };
        let (file, line) = match &*v.rep() {
            Rep::Origin(f, l, _) => (f.clone(), *l),
            _ => (None, 1),
        };
        let e = expr::parse(v.as_str(), file, line).ok()?;
        Some(self.expr_tree(&e))
    }

    fn expr_tree(&mut self, e: &Expr) -> CExpr {
        let b = |c: &mut Self, x: &Expr| Box::new(c.expr_tree(x));
        match e {
            Expr::Lit(o) => CExpr::Lit(o.clone()),
            Expr::Word(w) => match self.word(w) {
                Word::Local(i, n) => CExpr::Local(i, n),
                w => CExpr::Word(w),
            },
            Expr::Unary(op, x) => CExpr::Unary(*op, b(self, x)),
            Expr::Binary(op, x, y) => CExpr::Binary(*op, b(self, x), b(self, y)),
            Expr::And(x, y) => CExpr::And(b(self, x), b(self, y)),
            Expr::Or(x, y) => CExpr::Or(b(self, x), b(self, y)),
            Expr::Ternary(c, x, y) => CExpr::Ternary(b(self, c), b(self, x), b(self, y)),
            Expr::Call(f, args) => {
                CExpr::Call(*f, args.iter().map(|a| self.expr_tree(a)).collect())
            }
            Expr::Custom(n, args) => {
                CExpr::Custom(n.clone(), args.iter().map(|a| self.expr_tree(a)).collect())
            }
        }
    }

    /// A word with its local variables as slots and its command
    /// substitutions compiled.
    fn word(&mut self, w: &Word) -> Word {
        match w {
            Word::Lit(v) => Word::Lit(v.clone()),
            Word::Var(name) => match self.var_name(name) {
                Ok(local) => local,
                Err(name) => Word::Var(name),
            },
            Word::Cmd(s) if self.depth < MAX_NESTING => {
                Word::Compiled(Rc::new(self.body(s.clone())))
            }
            Word::Cmd(s) => Word::Cmd(s.clone()),
            Word::Concat(parts) => Word::Concat(parts.iter().map(|p| self.part(p)).collect()),
            Word::Expand(inner) => Word::Expand(Box::new(self.word(inner))),
            Word::Local(i, n) => Word::Local(*i, n.clone()),
            Word::Compiled(b) => Word::Compiled(b.clone()),
        }
    }

    /// `$name` as a slot read (`Ok`), or the name kept (`Err`).
    fn var_name(&mut self, name: &VarName) -> Result<Word, VarName> {
        match name {
            VarName::Scalar(n) if is_local_name(n) => Ok(Word::Local(self.slot(n).0, n.clone())),
            VarName::Scalar(n) => Err(VarName::Scalar(n.clone())),
            VarName::Elem(n, idx) => Err(VarName::Elem(n.clone(), Box::new(self.word(idx)))),
        }
    }

    fn part(&mut self, p: &Part) -> Part {
        match p {
            Part::Lit(s) => Part::Lit(s.clone()),
            Part::Var(name) => match self.var_name(name) {
                Ok(Word::Local(i, n)) => Part::Local(i, n),
                Ok(_) => unreachable!("var_name makes locals only"),
                Err(name) => Part::Var(name),
            },
            Part::Cmd(s) if self.depth < MAX_NESTING => {
                Part::Compiled(Rc::new(self.body(s.clone())))
            }
            Part::Cmd(s) => Part::Cmd(s.clone()),
            Part::Local(i, n) => Part::Local(*i, n.clone()),
            Part::Compiled(b) => Part::Compiled(b.clone()),
        }
    }

    fn call(&mut self, words: &[Word], at: u32) -> Op {
        let words = words.iter().map(|w| self.word(w)).collect();
        Op::Call { words, cache: RefCell::new(None), at }
    }

    /// Whether `name` here means the builtin of that name.
    fn is_builtin(&self, name: &str) -> bool {
        self.interp.is_original_builtin(name)
    }

    fn command(&mut self, words: &[Word], at: u32) -> Op {
        let Some(Word::Lit(first)) = words.first() else { return self.call(words, at) };
        let name = first.as_str();
        if !INLINE_OPS.contains(&name)
            || words.iter().any(|w| matches!(w, Word::Expand(_)))
            || !self.is_builtin(name)
        {
            return self.call(words, at);
        }
        self.inline(name, words).unwrap_or_else(|| self.call(words, at))
    }

    /// A command compiled inline, when its words have the shape that
    /// allows it (the others, errors included, run as ordinary calls).
    fn inline(&mut self, name: &str, w: &[Word]) -> Option<Op> {
        Some(match (name, w.len()) {
            ("set", 2) => Op::Get(self.local_word(&w[1])?),
            ("set", 3) => {
                let slot = self.local_word(&w[1])?;
                Op::Set(slot, self.word(&w[2]))
            }
            ("incr", 2 | 3) => {
                let slot = self.local_word(&w[1])?;
                let by = match w.get(2) {
                    None => By::One,
                    Some(Word::Lit(v)) => match v.as_integer() {
                        Ok(Num::Int(k)) => By::Const(k),
                        _ => By::Word(Word::Lit(v.clone())),
                    },
                    Some(x) => By::Word(self.word(x)),
                };
                Op::Incr(slot, by)
            }
            ("append", 3..) => {
                let slot = self.local_word(&w[1])?;
                Op::Append(slot, w[2..].iter().map(|x| self.word(x)).collect())
            }
            ("lappend", 3..) => {
                let slot = self.local_word(&w[1])?;
                Op::Lappend(slot, w[2..].iter().map(|x| self.word(x)).collect())
            }
            ("expr", 2) => Op::Expr(self.expr(&w[1])?),
            ("while", 3) => {
                let test = self.expr(&w[1])?;
                Op::For { start: None, test, next: None, body: self.nested(&w[2])? }
            }
            ("for", 5) => {
                let start = Some(self.nested(&w[1])?);
                let test = self.expr(&w[2])?;
                let next = Some(self.nested(&w[3])?);
                Op::For { start, test, next, body: self.nested(&w[4])? }
            }
            ("foreach", 4) => {
                let Word::Lit(var) = &w[1] else { return None };
                // One plain name (a list of one element that is itself).
                let items = var.as_list().ok()?;
                if items.len() != 1 || items[0].as_str() != var.as_str() {
                    return None;
                }
                let slot = self.local_word(&w[1])?;
                let list = self.word(&w[2]);
                Op::Foreach(slot, list, self.nested(&w[3])?)
            }
            ("if", _) => self.if_op(w)?,
            ("return", 1) => Op::Return(None),
            ("return", 2) => Op::Return(Some(self.word(&w[1]))),
            ("break", 1) => Op::Break,
            ("continue", 1) => Op::Continue,
            _ => return None,
        })
    }

    /// `if` with every word literal and a well-formed shape.
    fn if_op(&mut self, w: &[Word]) -> Option<Op> {
        let mut lits = Vec::with_capacity(w.len());
        for x in w {
            match x {
                Word::Lit(v) => lits.push(v.clone()),
                _ => return None,
            }
        }
        super::builtins::check_if(&lits).ok()?;
        let mut arms = Vec::new();
        let mut i = 1;
        loop {
            let test = self.expr(&w[i])?;
            i += 1;
            if lits[i].as_str() == "then" {
                i += 1;
            }
            arms.push((test, self.nested(&w[i])?));
            i += 1;
            match lits.get(i).map(Value::as_str) {
                None => return Some(Op::If { arms, otherwise: None }),
                Some("elseif") => i += 1,
                Some("else") => {
                    return Some(Op::If { arms, otherwise: Some(self.nested(&w[i + 1])?) });
                }
                Some(_) => return Some(Op::If { arms, otherwise: Some(self.nested(&w[i])?) }),
            }
        }
    }
}

/// Compiles a proc's body (`None` when its parameters cannot be slots).
pub(crate) fn compile_proc(interp: &Interp, p: &Proc) -> Option<CompiledProc> {
    let mut c = Compiler { interp, names: Vec::new(), depth: 0 };
    for (name, _) in &p.params {
        if !is_local_name(name) || c.names.iter().any(|n| n == name) {
            return None;
        }
        c.names.push(name.clone());
    }
    let body = c.body(Interp::script_of(&p.body));
    Some(CompiledProc { names: c.names.into(), body })
}

/// A value as an operand: a plain number when it is one with no string
/// yet (so its string would be the canonical one), otherwise the value.
#[inline]
fn operand_ref(v: &Value) -> Operand {
    match v.pure_number() {
        Some(Num::Int(i)) => Operand::Int(i),
        Some(Num::Double(d)) => Operand::Dbl(d),
        _ => Operand::Str(v.clone()),
    }
}

#[inline]
fn operand_of(v: Value) -> Operand {
    operand_ref(&v)
}

impl Interp {
    /// Whether a compiled body may take its fast paths now: nothing the
    /// compiler relied on has been redefined, and no trace wants to see
    /// each variable access or command.
    #[inline]
    fn fast(&self, epoch: u64) -> bool {
        self.inline_epoch == epoch && self.var_traces.is_empty() && self.cmd_traces.is_empty()
    }

    /// Runs a compiled body inline (errors logged as in `eval_script`).
    #[inline]
    pub(crate) fn run_body(&mut self, b: &Body) -> Run<Outcome> {
        // A body of one command (most loop bodies and `[...]`): no loop.
        if let ([op], [cmd], None) = (&b.ops[..], &b.script.cmds[..], &b.script.error)
            && self.fast(b.epoch)
        {
            return self.run_one(op, cmd, &b.script);
        }
        self.run_body_all(b)
    }

    fn run_one(&mut self, op: &Op, cmd: &Command, s: &Rc<Script>) -> Run<Outcome> {
        self.run_op(op, s).map_err(|mut e| {
            self.add_trace(&mut e, s.text(cmd), cmd.line, s.first_line, &s.file, false);
            e
        })
    }

    fn run_body_all(&mut self, b: &Body) -> Run<Outcome> {
        let mut result = None;
        for (i, (op, cmd)) in b.ops.iter().zip(&b.script.cmds).enumerate() {
            // Drop the previous result first so `lappend` can grow in place.
            drop(result.take());
            let r = if self.fast(b.epoch) {
                self.run_op(op, &b.script)
            } else {
                let at = || At::Cmd(b.script.clone(), i as u32);
                self.eval_command(cmd, at).map(Outcome::Normal).map_err(Box::new)
            };
            match r {
                Ok(Outcome::Normal(v)) => result = Some(v),
                Ok(other) => return Ok(other),
                Err(mut e) => {
                    let s = &b.script;
                    self.add_trace(&mut e, s.text(cmd), cmd.line, s.first_line, &s.file, false);
                    return Err(e);
                }
            }
        }
        if let Some(pe) = &b.script.error {
            let s = &b.script;
            let text = &s.src[pe.cmd_start as usize..(pe.pos as usize).min(s.src.len())];
            let mut e = Exception::error(pe.msg.clone());
            self.add_trace(&mut e, text, pe.line, s.first_line, &s.file, false);
            return Err(Box::new(e));
        }
        Ok(Outcome::Normal(result.unwrap_or_else(Value::empty)))
    }

    /// A compiled `[...]`: its `return`, `break` or `continue` leave as
    /// the exceptions the uncompiled script would raise.
    pub(crate) fn run_nested(&mut self, b: &Body) -> TclResult {
        // `[expr {...}]`, the most common substitution, straight through.
        if let ([Op::Expr(e)], [cmd], None) = (&b.ops[..], &b.script.cmds[..], &b.script.error)
            && self.fast(b.epoch)
        {
            return self.ceval(e).and_then(|o| Ok(expr_result(o)?)).map_err(|mut e| {
                let s = &b.script;
                self.add_trace(&mut e, s.text(cmd), cmd.line, s.first_line, &s.file, false);
                *e
            });
        }
        self.enter()?;
        let r = self.run_body(b);
        self.leave();
        match r.map_err(|e| *e)? {
            Outcome::Normal(v) => Ok(v),
            Outcome::Return(v) => {
                // What `return v` raises (`cmd_return`): one level up.
                let mut e = Exception::flow(Code::Return, v);
                e.level = 1;
                Err(e)
            }
            Outcome::Break => Err(Exception::flow(Code::Break, Value::empty())),
            Outcome::Continue => Err(Exception::flow(Code::Continue, Value::empty())),
        }
    }

    /// One command. Inline ops are not a nesting level and do not
    /// recurse beyond the compiled nesting (`MAX_NESTING`), so they skip
    /// `enter`; loops `poll` for Ctrl-C and the command budget each turn.
    #[inline(always)]
    fn run_op(&mut self, op: &Op, script: &Rc<Script>) -> Run<Outcome> {
        match op {
            Op::Call { words, cache, at } => {
                Ok(Outcome::Normal(self.run_call(words, cache, script, *at)?))
            }
            Op::Incr((i, name), by) => {
                let by = match by {
                    By::One => Num::Int(1),
                    By::Const(k) => Num::Int(*k),
                    By::Word(w) => self.eval_word(w)?.as_integer()?,
                };
                Ok(Outcome::Normal(self.incr_local(*i, name, by)?))
            }
            Op::Set((i, name), w) => {
                let v = self.eval_word(w)?;
                Ok(Outcome::Normal(self.set_local(*i, name, v)?))
            }
            Op::Append(..) | Op::Lappend(..) => {
                let mark = crate::mem::mark();
                let r = self.run_inline(op);
                // The memory budget, as `invoke` checks it.
                if crate::mem::grew_past(mark) || super::value::has_pending() {
                    super::eval::after_growth(Ok(Value::empty()))?;
                }
                r
            }
            _ => self.run_inline(op),
        }
    }

    fn run_inline(&mut self, op: &Op) -> Run<Outcome> {
        let normal = Outcome::Normal;
        Ok(match op {
            Op::Call { .. } | Op::Set(..) | Op::Incr(..) => unreachable!("run_op runs these"),
            Op::Get((i, name)) => normal(self.read_local(*i, name)?),
            Op::Append((i, name), words) | Op::Lappend((i, name), words) => {
                let change = match op {
                    Op::Append(..) => super::builtins::append_strings,
                    _ => super::builtins::append_elements,
                };
                let vals = self.eval_words(words)?;
                normal(self.update_local(*i, name, &mut |v| change(v, &vals))?)
            }
            Op::Expr(e) => normal(expr_result(self.ceval(e)?)?),
            Op::If { arms, otherwise } => {
                for (test, body) in arms {
                    if cond_truth(self.ceval(test)?)? {
                        return self.run_body(body);
                    }
                }
                match otherwise {
                    Some(body) => return self.run_body(body),
                    None => normal(Value::empty()),
                }
            }
            Op::For { start, test, next, body } => {
                if let Some(start) = start {
                    match self.run_body(start)? {
                        Outcome::Normal(_) => {}
                        // What `for` does with the code of its start script.
                        out => return Ok(out),
                    }
                }
                while cond_truth(self.ceval(test)?)? {
                    self.poll()?;
                    match self.run_loop_body(body)? {
                        Step::Go => {}
                        Step::Stop => break,
                        Step::Out(out) => return Ok(out),
                    }
                    // `break` in the next clause ends the loop, as in Tcl.
                    if let Some(next) = next {
                        match self.run_body(next)? {
                            Outcome::Normal(_) => {}
                            Outcome::Break => break,
                            out => return Ok(out),
                        }
                    }
                }
                normal(Value::empty())
            }
            Op::Foreach((i, name), list, body) => {
                let items = self.eval_word(list)?.as_list()?;
                for item in items.iter() {
                    self.poll()?;
                    self.set_local(*i, name, item.clone())?;
                    match self.run_loop_body(body)? {
                        Step::Go => {}
                        Step::Stop => break,
                        Step::Out(out) => return Ok(out),
                    }
                }
                normal(Value::empty())
            }
            Op::Return(w) => Outcome::Return(match w {
                Some(w) => self.eval_word(w)?,
                None => Value::empty(),
            }),
            Op::Break => Outcome::Break,
            Op::Continue => Outcome::Continue,
        })
    }

    /// A loop's body, and what the loop does next.
    #[inline]
    fn run_loop_body(&mut self, body: &Body) -> Run<Step> {
        Ok(match self.run_body(body) {
            Ok(Outcome::Normal(_) | Outcome::Continue) => Step::Go,
            Ok(Outcome::Break) => Step::Stop,
            Ok(out @ Outcome::Return(_)) => Step::Out(out),
            Err(e) if e.code == Code::Break => Step::Stop,
            Err(e) if e.code == Code::Continue => Step::Go,
            Err(e) => return Err(e),
        })
    }

    fn eval_words(&mut self, words: &[Word]) -> Result<SmallVec<[Value; 4]>, Exception> {
        words.iter().map(|w| self.eval_word(w)).collect()
    }

    /// A call site: the words substituted, the command from the cache
    /// while no command has changed since it was resolved.
    fn run_call(
        &mut self,
        words: &[Word],
        cache: &RefCell<Option<(u64, CommandKind)>>,
        script: &Rc<Script>,
        at: u32,
    ) -> TclResult {
        let mut argv: SmallVec<[Value; 8]> = SmallVec::new();
        let mut expanded = false;
        for w in words {
            match w {
                Word::Expand(inner) => {
                    expanded = true;
                    let v = self.eval_word(inner)?;
                    argv.extend(v.as_list()?.iter().cloned());
                }
                _ => argv.push(self.eval_word(w)?),
            }
        }
        if argv.is_empty() {
            return Ok(Value::empty());
        }
        self.note_at(At::Cmd(script.clone(), at));
        if expanded || !matches!(words[0], Word::Lit(_)) {
            return self.invoke(&argv);
        }
        let cached = match &*cache.borrow() {
            Some((epoch, cmd)) if *epoch == self.cmd_epoch => Some(cmd.clone()),
            _ => None,
        };
        let cmd = match cached {
            Some(cmd) => cmd,
            None => match self.resolve_command(argv[0].as_str()) {
                Some(cmd) => {
                    let cmd = cmd.clone();
                    *cache.borrow_mut() = Some((self.cmd_epoch, cmd.clone()));
                    cmd
                }
                None => return self.invoke(&argv),
            },
        };
        self.invoke_cmd(cmd, &argv)
    }

    /// Evaluates a compiled expression (`expr::eval`'s rules, with the
    /// 64-bit integer operators inline): literals and locals here, the
    /// rest in `ceval_tree` (so the common leaves cost no call).
    #[inline(always)]
    fn ceval(&mut self, e: &CExpr) -> Run<Operand> {
        match e {
            CExpr::Lit(o) => Ok(o.clone()),
            CExpr::Local(i, name) => Ok(self.local_operand(*i, name)?),
            _ => self.ceval_tree(e),
        }
    }

    fn ceval_tree(&mut self, e: &CExpr) -> Run<Operand> {
        Ok(match e {
            CExpr::Lit(o) => o.clone(),
            CExpr::Local(i, name) => self.local_operand(*i, name)?,
            CExpr::Word(w) => operand_of(self.eval_word(w)?),
            CExpr::Unary(op, x) => {
                let x = self.ceval(x)?;
                expr::unary(*op, x)?
            }
            CExpr::Binary(op, a, b) => {
                let x = self.ceval(a)?;
                let y = self.ceval(b)?;
                if let (Operand::Int(p), Operand::Int(q)) = (&x, &y)
                    && let Some(r) = expr::binary_small(*op, *p, *q)
                {
                    return Ok(r);
                }
                expr::binary(*op, x, y)?
            }
            CExpr::And(a, b) => {
                let r = self.ceval(a)?.truth()? && self.ceval(b)?.truth()?;
                Operand::Int(r as i64)
            }
            CExpr::Or(a, b) => {
                let r = self.ceval(a)?.truth()? || self.ceval(b)?.truth()?;
                Operand::Int(r as i64)
            }
            CExpr::Ternary(c, a, b) => {
                if self.ceval(c)?.truth()? {
                    self.ceval(a)?
                } else {
                    self.ceval(b)?
                }
            }
            CExpr::Call(f, args) => {
                let mut vals = Vec::with_capacity(args.len());
                for a in args {
                    vals.push(self.ceval(a)?);
                }
                expr::call(self, *f, Func::NAMES[*f as usize], vals)?
            }
            CExpr::Custom(name, args) => {
                let mut argv = Vec::with_capacity(args.len() + 1);
                argv.push(Value::from(format!("tcl::mathfunc::{name}")));
                for a in args {
                    argv.push(self.ceval(a)?.into_value());
                }
                Operand::Str(self.invoke(&argv)?)
            }
        })
    }

    /// A local as an operand: a plain number when it holds one.
    #[inline]
    fn local_operand(&mut self, i: u32, name: &str) -> Result<Operand, Exception> {
        if self.var_traces.is_empty()
            && let Some(Some(cell)) = self.frames[self.cur].slots.get(i as usize)
            && let Var::Scalar(v) = &*cell.borrow()
        {
            return Ok(operand_ref(v));
        }
        Ok(Operand::Str(self.get_var(name)?))
    }

    /// Reads local slot `i` (by name when it is not a plain scalar, for
    /// the exact error or an element link).
    #[inline]
    pub(crate) fn read_local(&mut self, i: u32, name: &str) -> TclResult {
        if self.var_traces.is_empty()
            && let Some(Some(cell)) = self.frames[self.cur].slots.get(i as usize)
            && let Var::Scalar(v) = &*cell.borrow()
        {
            return Ok(v.clone());
        }
        self.get_var(name)
    }

    /// Sets local slot `i` (by name for anything but a plain scalar).
    #[inline]
    fn set_local(&mut self, i: u32, name: &str, v: Value) -> TclResult {
        if self.var_traces.is_empty() {
            match self.frames[self.cur].slots.get_mut(i as usize) {
                Some(slot @ None) => {
                    *slot = Some(Rc::new(RefCell::new(Var::Scalar(v.clone()))));
                    return Ok(v);
                }
                Some(Some(cell)) => {
                    let mut var = cell.borrow_mut();
                    if matches!(*var, Var::Scalar(_) | Var::Undefined) {
                        *var = Var::Scalar(v.clone());
                        return Ok(v);
                    }
                }
                None => {}
            }
        }
        self.set_var(name, v)
    }

    fn incr_local(&mut self, i: u32, name: &str, by: super::number::Num) -> TclResult {
        if let super::number::Num::Int(by) = by
            && self.var_traces.is_empty()
            && let Some(Some(cell)) = self.frames[self.cur].slots.get(i as usize)
            && let Var::Scalar(v) = &mut *cell.borrow_mut()
            && let Some(x) = v.cached_int()
            && let Some(sum) = x.checked_add(by)
        {
            if !v.set_int_in_place(sum) {
                *v = Value::from_int(sum);
            }
            return Ok(v.clone());
        }
        self.incr_var(name, by)
    }

    /// `append`/`lappend` on local slot `i`: `f` changes its value in
    /// place (by name when it is not a plain scalar or does not exist).
    fn update_local(
        &mut self,
        i: u32,
        name: &str,
        f: &mut dyn FnMut(&mut Value) -> Result<(), Exception>,
    ) -> TclResult {
        if self.var_traces.is_empty()
            && let Some(Some(cell)) = self.frames[self.cur].slots.get(i as usize)
            && let Var::Scalar(v) = &mut *cell.borrow_mut()
        {
            f(v)?;
            return Ok(v.clone());
        }
        self.update_var(name, Some(Value::empty()), f)
    }
}
