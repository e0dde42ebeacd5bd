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
use super::eval::{CommandKind, Interp, NativeFn, Proc, Slot, Var, cond_truth, expr_result};
use super::expr::{self, BinOp, Expr, Func, Operand, UnOp};
use super::number::Num;
use super::parser::{Part, Script, VarName, Word};
use super::value::{Rep, Value};

/// The commands compiled inline. Redefining any of them (in any
/// namespace) bumps `Interp::inline_epoch` and so recompiles.
pub(crate) const INLINE_OPS: &[&str] = &[
    "set", "incr", "append", "lappend", "if", "while", "for", "foreach", "expr", "return", "break",
    "continue", "string", "llength", "lindex", "lrange", "list", "join", "split", "concat",
];

/// The builtins that only compute a value from their words (they run no
/// script; only `string is -failindex` sets a variable, by name, which
/// finds the slot): a compiled call to one goes straight to
/// its function, without the command table, a nesting level or a frame
/// record (as Tcl compiles them to instructions).
const DIRECT_OPS: &[&str] =
    &["string", "llength", "lindex", "lrange", "list", "join", "split", "concat"];

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
    /// Per op: whether it may run commands (calls, substitutions), after
    /// which the fast paths must be checked again.
    runs_code: Vec<bool>,
    /// The `inline_epoch` it was compiled in.
    epoch: u64,
}

/// How a compiled body ended, other than by an error. A normal end
/// carries the body's result only when its runner asked for it (a loop
/// body's is thrown away, so it is never made).
pub(crate) enum Outcome {
    Normal(Option<Value>),
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
    },
    /// A builtin of `DIRECT_OPS`, called straight.
    Direct(NativeFn, Vec<Word>),
    Get(Local),
    Set(Local, Word),
    /// `set a(k)`, `set a(k) v`, `incr a(k) ?n?` on a local array.
    GetElem(Local, Word),
    SetElem(Local, Word, Word),
    IncrElem(Local, Word, Word),
    /// `append` (false) or `lappend` (true) to an element of a local array.
    AppendElem(bool, Local, Word, Vec<Word>),
    /// `set x [expr {...}]`: the number straight into the slot; the
    /// substituted script is kept for errorInfo.
    SetExpr(Local, CExpr, Rc<Script>),
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
    /// `foreach` in general: for each list, the variables it fills.
    ForeachN(Vec<(Vec<Local>, Word)>, Body),
    Expr(CExpr),
    Return(Option<Word>),
    /// `return [expr {...}]`: the expression, and the script of the
    /// `[...]` for errors (as `SetExpr`).
    ReturnExpr(CExpr, Rc<Script>),
    Break,
    Continue,
}

impl Op {
    /// Whether running it may run commands, which could redefine a
    /// builtin or set a trace.
    fn runs_code(&self) -> bool {
        match self {
            Op::Call { .. } => true,
            Op::Direct(_, ws) => ws.iter().any(word_runs_code),
            Op::Get(_) | Op::Break | Op::Continue | Op::Return(None) => false,
            Op::Set(_, w) | Op::Return(Some(w)) | Op::GetElem(_, w) => word_runs_code(w),
            Op::SetElem(_, k, w) | Op::IncrElem(_, k, w) => word_runs_code(k) || word_runs_code(w),
            Op::AppendElem(_, _, k, ws) => word_runs_code(k) || ws.iter().any(word_runs_code),
            Op::SetExpr(_, e, _) | Op::Expr(e) | Op::ReturnExpr(e, _) => e.runs_code(),
            Op::Incr(_, By::Word(w)) => word_runs_code(w),
            Op::Incr(..) => false,
            Op::Append(_, ws) | Op::Lappend(_, ws) => ws.iter().any(word_runs_code),
            Op::If { arms, otherwise } => {
                arms.iter().any(|(e, b)| e.runs_code() || b.runs_any())
                    || otherwise.as_ref().is_some_and(Body::runs_any)
            }
            Op::For { start, test, next, body } => {
                start.as_ref().is_some_and(Body::runs_any)
                    || test.runs_code()
                    || next.as_ref().is_some_and(Body::runs_any)
                    || body.runs_any()
            }
            Op::Foreach(_, w, b) => word_runs_code(w) || b.runs_any(),
            Op::ForeachN(lists, b) => lists.iter().any(|(_, w)| word_runs_code(w)) || b.runs_any(),
        }
    }
}

impl Body {
    fn runs_any(&self) -> bool {
        self.script.error.is_some() || self.runs_code.iter().any(|&r| r)
    }
}

impl CExpr {
    fn runs_code(&self) -> bool {
        match self {
            CExpr::Int(_) | CExpr::Dbl(_) | CExpr::Lit(_) | CExpr::Local(..) => false,
            CExpr::CmpLI(..) => false,
            CExpr::Word(w) => word_runs_code(w),
            CExpr::Unary(_, x) => x.runs_code(),
            CExpr::Binary(_, a, b) | CExpr::And(a, b) | CExpr::Or(a, b) => {
                a.runs_code() || b.runs_code()
            }
            CExpr::Ternary(c, a, b) => c.runs_code() || a.runs_code() || b.runs_code(),
            // A math function may be a proc (`tcl::mathfunc::f`).
            CExpr::Call(..) | CExpr::Custom(..) => true,
        }
    }
}

/// Whether evaluating a word may run commands.
fn word_runs_code(w: &Word) -> bool {
    match w {
        Word::Lit(_) | Word::Local(..) => false,
        Word::LocalElem(_, _, i) => word_runs_code(i),
        Word::Var(VarName::Scalar(_)) => false,
        Word::Var(VarName::Elem(_, i)) => word_runs_code(i),
        Word::Cmd(_) | Word::Compiled(_) => true,
        Word::Concat(parts) => parts.iter().any(|p| match p {
            Part::Lit(_) | Part::Local(..) | Part::Var(VarName::Scalar(_)) => false,
            Part::Var(VarName::Elem(_, i)) => word_runs_code(i),
            Part::Cmd(_) | Part::Compiled(_) => true,
        }),
        Word::Expand(w) => word_runs_code(w),
    }
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
    Int(i64),
    Dbl(f64),
    Lit(Operand),
    /// A local compared with an integer (`$i < 1000`): the loop test.
    CmpLI(BinOp, u32, Rc<str>, i64),
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
type Run<T> = Result<T, Exception>;

struct Compiler<'a> {
    interp: &'a Interp,
    names: Vec<Rc<str>>,
    depth: usize,
}

/// Whether a variable name can be a slot: a plain local name.
pub(crate) fn is_local_name(name: &str) -> bool {
    !name.is_empty() && !name.contains("::") && !name.contains('(') && name != "tcl_precision"
}

/// Whether a `foreach` variable word is one plain name: a literal that
/// is a list of one element, itself.
fn one_name(w: &Word) -> bool {
    let Word::Lit(var) = w else { return false };
    var.as_list().is_ok_and(|items| items.len() == 1 && items[0].as_str() == var.as_str())
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

    /// A variable-name word that names an element of a local array
    /// (`a(1)`, `a($k)`, `a(x$i)`): the array's slot and the index word.
    fn elem_word(&mut self, w: &Word) -> Option<(Local, Word)> {
        match w {
            Word::Lit(v) => {
                let (base, idx) = super::eval::split_var_name(v.as_str());
                let idx = idx?;
                is_local_name(base).then(|| (self.slot(base), Word::Lit(Value::from(idx))))
            }
            Word::Concat(parts) => {
                let (Some(Part::Lit(first)), Some(Part::Lit(last))) = (parts.first(), parts.last())
                else {
                    return None;
                };
                if parts.len() < 2 || !last.ends_with(')') {
                    return None;
                }
                let open = first.find('(')?;
                if !is_local_name(&first[..open]) {
                    return None;
                }
                let local = self.slot(&first[..open]);
                // The index: the parts between the parentheses, compiled.
                let mut key = Vec::new();
                if open + 1 < first.len() {
                    key.push(Part::Lit(first[open + 1..].to_string()));
                }
                for p in &parts[1..parts.len() - 1] {
                    key.push(self.part(p));
                }
                if last.len() > 1 {
                    key.push(Part::Lit(last[..last.len() - 1].to_string()));
                }
                let key = match key.len() {
                    0 => Word::Lit(Value::empty()),
                    1 => match key.pop() {
                        Some(Part::Lit(s)) => Word::Lit(Value::from(s)),
                        Some(Part::Var(n)) => Word::Var(n),
                        Some(Part::Cmd(s)) => Word::Cmd(s),
                        Some(Part::Local(i, n)) => Word::Local(i, n),
                        Some(Part::Compiled(b)) => Word::Compiled(b),
                        None => unreachable!("one part"),
                    },
                    _ => Word::Concat(key),
                };
                Some((local, key))
            }
            _ => None,
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
        let ops: Vec<Op> = script.cmds.iter().map(|c| self.command(&c.words)).collect();
        self.depth -= 1;
        let runs_code = ops.iter().map(Op::runs_code).collect();
        Body { script, ops, runs_code, epoch: self.interp.inline_epoch }
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
            Rep::Origin(o) => (o.file.clone(), o.line),
            _ => (None, 1),
        };
        let e = expr::parse(v.as_str(), file, line).ok()?;
        Some(self.expr_tree(&e))
    }

    fn expr_tree(&mut self, e: &Expr) -> CExpr {
        let b = |c: &mut Self, x: &Expr| Box::new(c.expr_tree(x));
        match e {
            Expr::Lit(Operand::Int(i)) => CExpr::Int(*i),
            Expr::Lit(Operand::Dbl(d)) => CExpr::Dbl(*d),
            Expr::Lit(o) => CExpr::Lit(o.clone()),
            Expr::Word(w) => match self.word(w) {
                Word::Local(i, n) => CExpr::Local(i, n),
                w => CExpr::Word(w),
            },
            Expr::Unary(op, x) => CExpr::Unary(*op, b(self, x)),
            Expr::Binary(op, x, y) => {
                let (x, y) = (self.expr_tree(x), self.expr_tree(y));
                match (op, x, y) {
                    (
                        BinOp::Lt | BinOp::Le | BinOp::Gt | BinOp::Ge | BinOp::Eq | BinOp::Ne,
                        CExpr::Local(i, n),
                        CExpr::Int(k),
                    ) => CExpr::CmpLI(*op, i, n, k),
                    (op, x, y) => CExpr::Binary(*op, Box::new(x), Box::new(y)),
                }
            }
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
            Word::LocalElem(i, n, k) => Word::LocalElem(*i, n.clone(), Box::new(self.word(k))),
            Word::Compiled(b) => Word::Compiled(b.clone()),
        }
    }

    /// `$name` as a slot read (`Ok`), or the name kept (`Err`).
    fn var_name(&mut self, name: &VarName) -> Result<Word, VarName> {
        match name {
            VarName::Scalar(n) if is_local_name(n) => Ok(Word::Local(self.slot(n).0, n.clone())),
            VarName::Scalar(n) => Err(VarName::Scalar(n.clone())),
            VarName::Elem(n, idx) if is_local_name(n) => {
                Ok(Word::LocalElem(self.slot(n).0, n.clone(), Box::new(self.word(idx))))
            }
            VarName::Elem(n, idx) => Err(VarName::Elem(n.clone(), Box::new(self.word(idx)))),
        }
    }

    fn part(&mut self, p: &Part) -> Part {
        match p {
            Part::Lit(s) => Part::Lit(s.clone()),
            Part::Var(name) => match self.var_name(name) {
                Ok(Word::Local(i, n)) => Part::Local(i, n),
                // An element in a longer word is read by name.
                Ok(Word::LocalElem(_, n, k)) => Part::Var(VarName::Elem(n, k)),
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

    fn call(&mut self, words: &[Word]) -> Op {
        let words = words.iter().map(|w| self.word(w)).collect();
        Op::Call { words, cache: RefCell::new(None) }
    }

    /// Whether `name` here means the builtin of that name.
    fn is_builtin(&self, name: &str) -> bool {
        self.interp.is_original_builtin(name)
    }

    fn command(&mut self, words: &[Word]) -> Op {
        let Some(Word::Lit(first)) = words.first() else { return self.call(words) };
        let name = first.as_str();
        if !INLINE_OPS.contains(&name)
            || words.iter().any(|w| matches!(w, Word::Expand(_)))
            || !self.is_builtin(name)
        {
            return self.call(words);
        }
        self.inline(name, words).unwrap_or_else(|| self.call(words))
    }

    /// A command compiled inline, when its words have the shape that
    /// allows it (the others, errors included, run as ordinary calls).
    fn inline(&mut self, name: &str, w: &[Word]) -> Option<Op> {
        Some(match (name, w.len()) {
            ("set", 2) if self.local_word(&w[1]).is_none() => {
                let (slot, key) = self.elem_word(&w[1])?;
                Op::GetElem(slot, key)
            }
            ("set", 3) if self.local_word(&w[1]).is_none() => {
                let (slot, key) = self.elem_word(&w[1])?;
                Op::SetElem(slot, key, self.word(&w[2]))
            }
            ("incr", 2 | 3) if self.local_word(&w[1]).is_none() => {
                let (slot, key) = self.elem_word(&w[1])?;
                let by = match w.get(2) {
                    None => Word::Lit(Value::from_int(1)),
                    Some(x) => self.word(x),
                };
                Op::IncrElem(slot, key, by)
            }
            ("set", 2) => Op::Get(self.local_word(&w[1])?),
            ("set", 3) => {
                let slot = self.local_word(&w[1])?;
                if let Some((e, script)) = self.expr_subst(&w[2]) {
                    return Some(Op::SetExpr(slot, e, script));
                }
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
            ("append" | "lappend", 3..) if self.local_word(&w[1]).is_none() => {
                let (slot, key) = self.elem_word(&w[1])?;
                let words = w[2..].iter().map(|x| self.word(x)).collect();
                Op::AppendElem(name == "lappend", slot, key, words)
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
            // One plain name (a list of one element that is itself); any
            // other variable list is the general form below.
            ("foreach", 4) if one_name(&w[1]) => {
                let slot = self.local_word(&w[1])?;
                let list = self.word(&w[2]);
                Op::Foreach(slot, list, self.nested(&w[3])?)
            }
            ("foreach", n) if n >= 4 && n % 2 == 0 => {
                let mut lists = Vec::new();
                for pair in w[1..n - 1].chunks(2) {
                    let Word::Lit(vars) = &pair[0] else { return None };
                    let names = vars.as_list().ok()?;
                    // An empty variable list is the builtin's error.
                    if names.is_empty() || !names.iter().all(|v| is_local_name(v.as_str())) {
                        return None;
                    }
                    let locals = names.iter().map(|v| self.slot(v.as_str())).collect();
                    lists.push((locals, self.word(&pair[1])));
                }
                Op::ForeachN(lists, self.nested(&w[n - 1])?)
            }
            ("if", _) => self.if_op(w)?,
            (n, _) if DIRECT_OPS.contains(&n) => {
                let f = match (n, w.get(1)) {
                    ("string", Some(Word::Lit(sub))) => match sub.as_str() {
                        "length" => super::builtins::string_length,
                        "index" => super::builtins::string_index,
                        "range" => super::builtins::string_range,
                        _ => self.interp.builtin_fn(n)?,
                    },
                    _ => self.interp.builtin_fn(n)?,
                };
                Op::Direct(f, w.iter().map(|x| self.word(x)).collect())
            }
            ("return", 1) => Op::Return(None),
            ("return", 2) => match self.expr_subst(&w[1]) {
                Some((e, script)) => Op::ReturnExpr(e, script),
                None => Op::Return(Some(self.word(&w[1]))),
            },
            ("break", 1) => Op::Break,
            ("continue", 1) => Op::Continue,
            _ => return None,
        })
    }

    /// A word that is exactly `[expr {...}]` (the builtin, a literal
    /// expression): the expression compiled, and the script for errors.
    fn expr_subst(&mut self, w: &Word) -> Option<(CExpr, Rc<Script>)> {
        let Word::Cmd(s) = w else { return None };
        let [cmd] = &s.cmds[..] else { return None };
        if s.error.is_some() || cmd.words.len() != 2 {
            return None;
        }
        match &cmd.words[0] {
            Word::Lit(v) if v.as_str() == "expr" && self.is_builtin("expr") => {}
            _ => return None,
        }
        Some((self.expr(&cmd.words[1])?, s.clone()))
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

/// An expression's result for a slot (`expr_result`'s rules: a NaN is an
/// error), numbers unboxed.
#[inline]
fn slot_of_result(op: Operand) -> Result<Slot, Exception> {
    Ok(match op {
        Operand::Int(i) => Slot::Int(i),
        Operand::Dbl(d) if !d.is_nan() => Slot::Dbl(d),
        op => Slot::Val(expr_result(op)?),
    })
}

impl Interp {
    /// Whether a compiled body may take its fast paths now: nothing the
    /// compiler relied on has been redefined, and no trace wants to see
    /// each variable access or command.
    #[inline]
    fn fast(&self, epoch: u64) -> bool {
        self.inline_epoch == epoch && self.var_traces.is_empty() && self.cmd_traces.is_empty()
    }

    /// Runs a compiled body inline (errors logged as in `eval_script`);
    /// `want`: whether its result is used (else `Normal(None)`).
    #[inline(always)]
    pub(crate) fn run_body(&mut self, b: &Body, want: bool) -> Run<Outcome> {
        if b.ops.is_empty() && b.script.error.is_none() {
            return Ok(Outcome::Normal(want.then(Value::empty)));
        }
        self.run_body_some(b, want)
    }

    #[inline(never)]
    fn run_body_some(&mut self, b: &Body, want: bool) -> Run<Outcome> {
        // A body of one command (most loop bodies and `[...]`): no loop.
        if let ([op], None) = (&b.ops[..], &b.script.error)
            && self.fast(b.epoch)
        {
            return self.run_op(op, &b.script, 0, want).map_err(|e| self.log_op(e, b, 0));
        }
        self.run_body_all(b, want)
    }

    /// An error leaving the `[expr {...}]` of a `SetExpr` or `ReturnExpr`:
    /// the trace its own script would add.
    #[cold]
    fn subst_error(&self, mut e: Exception, s: &Script) -> Exception {
        let cmd = &s.cmds[0];
        self.add_trace(&mut e, s.text(cmd), cmd.line, s.first_line, &s.file, false);
        e
    }

    /// An error leaving command `i` of a body: its trace.
    #[cold]
    fn log_op(&self, mut e: Exception, b: &Body, i: usize) -> Exception {
        let s = &b.script;
        let cmd = &s.cmds[i];
        self.add_trace(&mut e, s.text(cmd), cmd.line, s.first_line, &s.file, false);
        e
    }

    fn run_body_all(&mut self, b: &Body, want: bool) -> Run<Outcome> {
        let last = b.ops.len().wrapping_sub(1);
        let mut result = None;
        // Checked again only after an op that may have run commands.
        let mut fast = self.fast(b.epoch);
        for (i, op) in b.ops.iter().enumerate() {
            let want_this = want && i == last;
            let r = if fast {
                let r = self.run_op(op, &b.script, i as u32, want_this);
                if b.runs_code[i] {
                    fast = self.fast(b.epoch);
                }
                r
            } else {
                let at = || At::Cmd(b.script.clone(), i as u32);
                let cmd = &b.script.cmds[i];
                self.eval_command(cmd, at).map(|v| Outcome::Normal(Some(v)))
            };
            match r {
                Ok(Outcome::Normal(v)) => {
                    if want_this {
                        result = v;
                    }
                }
                Ok(other) => return Ok(other),
                Err(e) => return Err(self.log_op(e, b, i)),
            }
        }
        if let Some(pe) = &b.script.error {
            let s = &b.script;
            let text = &s.src[pe.cmd_start as usize..(pe.pos as usize).min(s.src.len())];
            let mut e = Exception::error(pe.msg.clone());
            self.add_trace(&mut e, text, pe.line, s.first_line, &s.file, false);
            return Err(e);
        }
        if want && result.is_none() {
            result = Some(Value::empty());
        }
        Ok(Outcome::Normal(result))
    }

    /// A compiled `[...]`: its `return`, `break` or `continue` leave as
    /// the exceptions the uncompiled script would raise.
    pub(crate) fn run_nested(&mut self, b: &Body) -> TclResult {
        // The common substitutions of one command each take a fast path,
        // out of line so that this frame stays small: it sits on the
        // native stack under every call made inside the `[...]`, and a
        // deep recursion runs out of L1 cache on the frames of its levels.
        if let ([op], None) = (&b.ops[..], &b.script.error)
            && self.fast(b.epoch)
        {
            match op {
                // `[expr {...}]`, the most common substitution.
                Op::Expr(e) => return self.nested_expr(e, b),
                // A pure builtin (`[lindex $l 3]`, `[string length $s]`):
                // it runs no script, so it is no nesting level either.
                Op::Direct(f, words) => return self.nested_direct(*f, words, b),
                // One call (`[fib $n]`): what `run_body` would do for it.
                Op::Call { words, cache } => {
                    self.enter()?;
                    let r = self.run_call(words, cache, &b.script, 0);
                    self.leave();
                    return r.map_err(|e| self.log_op(e, b, 0));
                }
                _ => {}
            }
        }
        self.nested_body(b)
    }

    #[inline(never)]
    fn nested_expr(&mut self, e: &CExpr, b: &Body) -> TclResult {
        self.ceval(e).and_then(expr_result).map_err(|e| self.log_op(e, b, 0))
    }

    #[inline(never)]
    fn nested_direct(&mut self, f: NativeFn, words: &[Word], b: &Body) -> TclResult {
        self.poll()?;
        self.run_direct(f, words).map_err(|e| self.log_op(e, b, 0))
    }

    /// A `DIRECT_OPS` command of a body (out of line: its argument vector
    /// would widen the frame of every body that runs a call).
    #[inline(never)]
    fn direct_op(&mut self, f: NativeFn, words: &[Word]) -> TclResult {
        self.run_direct(f, words)
    }

    /// A `[...]` of any other body, a nesting level of its own.
    #[inline(never)]
    fn nested_body(&mut self, b: &Body) -> TclResult {
        self.enter()?;
        let r = self.run_body(b, true);
        self.leave();
        match r? {
            Outcome::Normal(v) => Ok(v.unwrap_or_default()),
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

    /// A pure builtin called with no lookup and no level (`DIRECT_OPS`).
    #[inline(always)]
    fn run_direct(&mut self, f: NativeFn, words: &[Word]) -> TclResult {
        let argv = self.eval_words8(words)?;
        let mark = crate::mem::mark();
        let mut r = f(self, &argv);
        self.note_inner(&argv, &mut r);
        if crate::mem::grew_past(mark) || super::value::has_pending() {
            return super::eval::after_growth(r);
        }
        r
    }

    /// One command. Inline ops are not a nesting level and do not
    /// recurse beyond the compiled nesting (`MAX_NESTING`), so they skip
    /// `enter`; loops `poll` for Ctrl-C and the command budget each turn.
    /// The caller checked `fast`: no trace exists as the op starts (one
    /// that substitutes a command checks again before it touches a slot).
    #[inline(always)]
    fn run_op(&mut self, op: &Op, script: &Rc<Script>, at: u32, want: bool) -> Run<Outcome> {
        match op {
            Op::Incr((i, name), by) => {
                let by = match by {
                    By::One => 1,
                    By::Const(k) => *k,
                    By::Word(w) => match self.eval_word(w)?.as_integer()? {
                        Num::Int(k) => k,
                        big => return Ok(Outcome::Normal(Some(self.incr_var(name, big)?))),
                    },
                };
                self.incr_local(*i, name, by, want)
            }
            Op::SetExpr((i, name), e, s) => {
                let r =
                    self.ceval(e).and_then(slot_of_result).map_err(|e| self.subst_error(e, s))?;
                self.store_local(*i, name, r, want)
            }
            Op::ReturnExpr(e, s) => {
                let v = self.ceval(e).and_then(expr_result).map_err(|e| self.subst_error(e, s))?;
                Ok(Outcome::Return(v))
            }
            Op::Set((i, name), w) => {
                let v = self.eval_word(w)?;
                let v = self.set_local(*i, name, v)?;
                Ok(Outcome::Normal(want.then_some(v)))
            }
            Op::Call { words, cache } => {
                Ok(Outcome::Normal(Some(self.run_call(words, cache, script, at)?)))
            }
            Op::Direct(f, words) => Ok(Outcome::Normal(Some(self.direct_op(*f, words)?))),
            Op::Append(..) | Op::Lappend(..) | Op::AppendElem(..) => {
                let mark = crate::mem::mark();
                let r = self.run_inline(op, want);
                // The memory budget, as `invoke` checks it.
                if crate::mem::grew_past(mark) || super::value::has_pending() {
                    super::eval::after_growth(Ok(Value::empty()))?;
                }
                r
            }
            _ => self.run_inline(op, want),
        }
    }

    fn run_inline(&mut self, op: &Op, want: bool) -> Run<Outcome> {
        Ok(match op {
            Op::Call { .. }
            | Op::Direct(..)
            | Op::Set(..)
            | Op::SetExpr(..)
            | Op::ReturnExpr(..)
            | Op::Incr(..) => {
                unreachable!("run_op runs these")
            }
            Op::Get((i, name)) => Outcome::Normal(Some(self.read_local(*i, name)?)),
            Op::GetElem((i, name), key) => {
                let key = self.eval_word(key)?;
                Outcome::Normal(Some(self.read_local_elem(*i, name, &key)?))
            }
            Op::SetElem((i, name), key, w) => {
                let key = self.eval_word(key)?;
                let v = self.eval_word(w)?;
                let mark = crate::mem::mark();
                let v = self.set_local_elem(*i, name, &key, v)?;
                if crate::mem::grew_past(mark) {
                    super::eval::after_growth(Ok(Value::empty()))?;
                }
                Outcome::Normal(want.then_some(v))
            }
            Op::AppendElem(list, (i, name), key, words) => {
                let change = if *list {
                    super::builtins::append_elements
                } else {
                    super::builtins::append_strings
                };
                let key = self.eval_word(key)?;
                let vals = self.eval_words(words)?;
                let v = self.update_local_elem(*i, name, &key, &mut |v| change(v, &vals))?;
                Outcome::Normal(want.then_some(v))
            }
            Op::IncrElem((i, name), key, by) => {
                let key = self.eval_word(key)?;
                let by = self.eval_word(by)?.as_integer()?;
                let v = self.incr_local_elem(*i, name, &key, by)?;
                Outcome::Normal(want.then_some(v))
            }
            Op::Append((i, name), words) | Op::Lappend((i, name), words) => {
                let change = match op {
                    Op::Append(..) => super::builtins::append_strings,
                    _ => super::builtins::append_elements,
                };
                // One value (the usual `lappend l $x`, `append s $x`):
                // moved in, no vector.
                if let [w] = &words[..] {
                    let mut one = Some(self.eval_word(w)?);
                    let list = matches!(op, Op::Lappend(..));
                    let mut push = |v: &mut Value| match one.take() {
                        Some(x) if list => super::builtins::append_element(v, x),
                        Some(x) => super::builtins::append_strings(v, &[x]),
                        None => Ok(()),
                    };
                    return Ok(Outcome::Normal(self.update_local(*i, name, want, &mut push)?));
                }
                let vals = self.eval_words(words)?;
                Outcome::Normal(self.update_local(*i, name, want, &mut |v| change(v, &vals))?)
            }
            Op::Expr(e) => Outcome::Normal(Some(expr_result(self.ceval(e)?)?)),
            Op::If { arms, otherwise } => {
                for (test, body) in arms {
                    if self.ctest(test)? {
                        return self.run_body(body, want);
                    }
                }
                match otherwise {
                    Some(body) => return self.run_body(body, want),
                    None => Outcome::Normal(want.then(Value::empty)),
                }
            }
            Op::For { start, test, next, body } => {
                if let Some(start) = start {
                    match self.run_body(start, false)? {
                        Outcome::Normal(_) => {}
                        // What `for` does with the code of its start script.
                        out => return Ok(out),
                    }
                }
                while self.ctest(test)? {
                    self.poll()?;
                    match self.run_loop_body(body)? {
                        Step::Go => {}
                        Step::Stop => break,
                        Step::Out(out) => return Ok(out),
                    }
                    // `break` in the next clause ends the loop, as in Tcl.
                    if let Some(next) = next {
                        match self.run_body(next, false)? {
                            Outcome::Normal(_) => {}
                            Outcome::Break => break,
                            out => return Ok(out),
                        }
                    }
                }
                Outcome::Normal(want.then(Value::empty))
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
                Outcome::Normal(want.then(Value::empty))
            }
            Op::ForeachN(lists, body) => {
                // Every list word first, then each read as a list, as Tcl does.
                let mut values: SmallVec<[Value; 4]> = SmallVec::new();
                for (_, w) in lists {
                    values.push(self.eval_word(w)?);
                }
                let mut items: SmallVec<[Rc<Vec<Value>>; 4]> = SmallVec::new();
                for v in &values {
                    items.push(v.as_list()?);
                }
                let turns = lists
                    .iter()
                    .zip(&items)
                    .map(|((vars, _), l)| l.len().div_ceil(vars.len()))
                    .max()
                    .unwrap_or(0);
                for turn in 0..turns {
                    self.poll()?;
                    for ((vars, _), l) in lists.iter().zip(&items) {
                        for (j, (i, name)) in vars.iter().enumerate() {
                            let v = l.get(turn * vars.len() + j).cloned().unwrap_or_default();
                            self.set_local(*i, name, v)?;
                        }
                    }
                    match self.run_loop_body(body)? {
                        Step::Go => {}
                        Step::Stop => break,
                        Step::Out(out) => return Ok(out),
                    }
                }
                Outcome::Normal(want.then(Value::empty))
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
    #[inline(always)]
    fn run_loop_body(&mut self, body: &Body) -> Run<Step> {
        Ok(match self.run_body(body, false) {
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

    fn eval_words8(&mut self, words: &[Word]) -> Result<SmallVec<[Value; 8]>, Exception> {
        let mut argv = SmallVec::new();
        for w in words {
            argv.push(self.eval_word(w)?);
        }
        Ok(argv)
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
        self.note_cmd(script, at);
        if expanded || !matches!(words[0], Word::Lit(_)) {
            return self.invoke(&argv);
        }
        let cached = match &*cache.borrow() {
            Some((epoch, cmd)) if *epoch == self.cmd_epoch => Some(cmd.clone()),
            _ => None,
        };
        // Called from where the clone was made (a move of the enum into
        // another stack slot is a stall: a wide load over narrow stores).
        if let Some(cmd) = &cached {
            return self.invoke_cmd(cmd, &argv);
        }
        self.resolve_and_invoke(cache, &argv)
    }

    /// A call site's first call, or its first since a command changed.
    #[inline(never)]
    fn resolve_and_invoke(
        &mut self,
        cache: &RefCell<Option<(u64, CommandKind)>>,
        argv: &[Value],
    ) -> TclResult {
        match self.resolve_command(argv[0].as_str()) {
            Some(cmd) => {
                let cmd = cmd.clone();
                *cache.borrow_mut() = Some((self.cmd_epoch, cmd.clone()));
                self.invoke_cmd(&cmd, argv)
            }
            None => self.invoke(argv),
        }
    }

    /// A condition's truth: a comparison of two integers without making
    /// a result, the rest through `ctest_tree`.
    #[inline(always)]
    fn ctest(&mut self, e: &CExpr) -> Run<bool> {
        if let CExpr::CmpLI(op, i, _, k) = e
            && let Some(x) = self.local_int(*i)
        {
            return Ok(compare(*op, x, *k));
        }
        self.ctest_tree(e)
    }

    #[inline(never)]
    fn ctest_tree(&mut self, e: &CExpr) -> Run<bool> {
        if let CExpr::Binary(op, a, b) = e {
            let x = self.ceval(a)?;
            let y = self.ceval(b)?;
            if let (Operand::Int(p), Operand::Int(q)) = (&x, &y) {
                let (p, q) = (*p, *q);
                if let BinOp::Lt | BinOp::Le | BinOp::Gt | BinOp::Ge | BinOp::Eq | BinOp::Ne = op {
                    return Ok(compare(*op, p, q));
                }
                if let Some(r) = expr::binary_small(*op, p, q) {
                    return cond_truth(r);
                }
            }
            return cond_truth(expr::binary(*op, x, y)?);
        }
        cond_truth(self.ceval(e)?)
    }

    /// Evaluates a compiled expression (`expr::eval`'s rules, with the
    /// 64-bit integer operators inline): literals and locals here, the
    /// rest in `ceval_tree` (so the common leaves cost no call).
    #[inline(always)]
    fn ceval(&mut self, e: &CExpr) -> Run<Operand> {
        match e {
            CExpr::Int(i) => Ok(Operand::Int(*i)),
            CExpr::Dbl(d) => Ok(Operand::Dbl(*d)),
            CExpr::Local(i, name) => Ok(self.local_operand(*i, name)?),
            _ => self.ceval_tree(e),
        }
    }

    fn ceval_tree(&mut self, e: &CExpr) -> Run<Operand> {
        Ok(match e {
            CExpr::CmpLI(op, i, name, k) => match self.local_int(*i) {
                Some(x) => Operand::Int(compare(*op, x, *k) as i64),
                None => {
                    let x = self.local_operand(*i, name)?;
                    expr::binary(*op, x, Operand::Int(*k))?
                }
            },
            CExpr::Int(i) => Operand::Int(*i),
            CExpr::Dbl(d) => Operand::Dbl(*d),
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
                if let (Some(p), Some(q)) = (expr::quick_int(&x), expr::quick_int(&y))
                    && let Some(r) = expr::binary_small(*op, p, q)
                {
                    return Ok(r);
                }
                match (&x, &y) {
                    // Doubles: the arithmetic Tcl does, without `Num`s.
                    (Operand::Dbl(p), Operand::Dbl(q)) => {
                        if let Some(r) = dbl_binary(*op, *p, *q) {
                            return Ok(r);
                        }
                    }
                    // An integer a double holds exactly.
                    (Operand::Dbl(p), Operand::Int(q)) if q.unsigned_abs() <= 1 << 53 => {
                        if let Some(r) = dbl_binary(*op, *p, *q as f64) {
                            return Ok(r);
                        }
                    }
                    (Operand::Int(p), Operand::Dbl(q)) if p.unsigned_abs() <= 1 << 53 => {
                        if let Some(r) = dbl_binary(*op, *p as f64, *q) {
                            return Ok(r);
                        }
                    }
                    _ => {}
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

    /// A local's integer, when it plainly holds one (no trace).
    #[inline(always)]
    fn local_int(&self, i: u32) -> Option<i64> {
        if !self.var_traces.is_empty() {
            return None;
        }
        match &self.frames[self.cur].slots[i as usize] {
            Slot::Int(n) => Some(*n),
            Slot::Val(v) => v.cached_int(),
            _ => None,
        }
    }

    /// A local as an operand: a plain number when it holds one.
    #[inline(always)]
    fn local_operand(&mut self, i: u32, name: &str) -> Result<Operand, Exception> {
        if self.var_traces.is_empty() {
            match &self.frames[self.cur].slots[i as usize] {
                Slot::Int(n) => return Ok(Operand::Int(*n)),
                Slot::Dbl(d) => return Ok(Operand::Dbl(*d)),
                Slot::Val(v) => return Ok(operand_ref(v)),
                Slot::Cell(c) => {
                    if let Var::Scalar(v) = &*c.borrow() {
                        return Ok(operand_ref(v));
                    }
                }
                Slot::Empty => {}
            }
        }
        Ok(Operand::Str(self.get_var(name)?))
    }

    /// Reads local slot `i` as a value (by name when it is not a plain
    /// scalar, for the exact error or an element link). A number becomes
    /// the value the slot holds from then on, so later reads share it.
    #[inline]
    pub(crate) fn read_local(&mut self, i: u32, name: &str) -> TclResult {
        if self.var_traces.is_empty() {
            let slot = &mut self.frames[self.cur].slots[i as usize];
            match slot {
                Slot::Val(v) => return Ok(v.clone()),
                Slot::Int(n) => {
                    let v = Value::from_int(*n);
                    *slot = Slot::Val(v.clone());
                    return Ok(v);
                }
                Slot::Dbl(d) => {
                    let v = Value::from_f64(*d);
                    *slot = Slot::Val(v.clone());
                    return Ok(v);
                }
                Slot::Cell(c) => {
                    if let Var::Scalar(v) = &*c.borrow() {
                        return Ok(v.clone());
                    }
                }
                Slot::Empty => {}
            }
        }
        self.get_var(name)
    }

    /// Element `key` of the local array in slot `i` (by name for the
    /// exact error when it is not one).
    pub(crate) fn read_local_elem(&mut self, i: u32, name: &str, key: &Value) -> TclResult {
        if self.var_traces.is_empty()
            && let Slot::Cell(c) = &self.frames[self.cur].slots[i as usize]
            && let Var::Array(m) = &*c.borrow()
            && let Some(v) = m.get(key.as_str())
        {
            return Ok(v.clone());
        }
        self.get_var(&format!("{name}({})", key.as_str()))
    }

    /// `f` on element `key` of the local array in slot `i`, made (and the
    /// array with it) when it does not exist; `None` when the slot is
    /// not a plain local array or a trace exists (the caller goes by name).
    fn with_local_elem<R>(
        &mut self,
        i: u32,
        key: &Value,
        f: impl FnOnce(&mut Value) -> R,
    ) -> Option<R> {
        if !self.var_traces.is_empty() {
            return None;
        }
        let slot = &mut self.frames[self.cur].slots[i as usize];
        if let Slot::Empty = slot {
            *slot = Slot::Cell(Rc::new(RefCell::new(Var::Undefined)));
        }
        let Slot::Cell(c) = slot else { return None };
        let mut var = c.borrow_mut();
        if let Var::Undefined = *var {
            *var = Var::Array(super::eval::ArrayMap::default());
        }
        let Var::Array(m) = &mut *var else { return None };
        let x = match m.get_mut(key.as_str()) {
            Some(x) => x,
            None => m.entry(key.as_str().to_string()).or_default(),
        };
        Some(f(x))
    }

    /// Sets element `key` of the local array in slot `i`.
    fn set_local_elem(&mut self, i: u32, name: &str, key: &Value, v: Value) -> TclResult {
        if self.with_local_elem(i, key, |x| *x = v.clone()).is_some() {
            return Ok(v);
        }
        self.set_var(&format!("{name}({})", key.as_str()), v)
    }

    /// `append`/`lappend` to element `key` of the local array in slot `i`:
    /// `f` changes the element in place.
    fn update_local_elem(
        &mut self,
        i: u32,
        name: &str,
        key: &Value,
        f: &mut dyn FnMut(&mut Value) -> Result<(), Exception>,
    ) -> TclResult {
        if let Some(r) = self.with_local_elem(i, key, |x| f(x).map(|()| x.clone())) {
            return r;
        }
        self.update_var(&format!("{name}({})", key.as_str()), Some(Value::empty()), f)
    }

    /// `incr` of element `key` of the local array in slot `i`.
    fn incr_local_elem(&mut self, i: u32, name: &str, key: &Value, by: Num) -> TclResult {
        if let Num::Int(by) = by
            && self.var_traces.is_empty()
            && let Slot::Cell(c) = &self.frames[self.cur].slots[i as usize]
            && let Var::Array(m) = &mut *c.borrow_mut()
            && let Some(x) = m.get_mut(key.as_str())
            && let Ok(Num::Int(n)) = x.as_integer()
            && let Some(sum) = n.checked_add(by)
        {
            x.set_int(sum);
            return Ok(x.clone());
        }
        self.incr_var(&format!("{name}({})", key.as_str()), by)
    }

    /// Sets local slot `i` (by name for anything but a plain scalar).
    #[inline]
    fn set_local(&mut self, i: u32, name: &str, v: Value) -> TclResult {
        if self.var_traces.is_empty() {
            let slot = &mut self.frames[self.cur].slots[i as usize];
            match slot {
                Slot::Cell(c) => {
                    let mut var = c.borrow_mut();
                    if matches!(*var, Var::Scalar(_) | Var::Undefined) {
                        *var = Var::Scalar(v.clone());
                        return Ok(v);
                    }
                }
                _ => {
                    *slot = Slot::Val(v.clone());
                    return Ok(v);
                }
            }
        }
        self.set_var(name, v)
    }

    /// Stores an expression's result in local slot `i`.
    #[inline]
    fn store_local(&mut self, i: u32, name: &str, r: Slot, want: bool) -> Run<Outcome> {
        if self.var_traces.is_empty() {
            let slot = &mut self.frames[self.cur].slots[i as usize];
            if !matches!(slot, Slot::Cell(_)) {
                let v = want.then(|| match &r {
                    Slot::Int(n) => Value::from_int(*n),
                    Slot::Dbl(d) => Value::from_f64(*d),
                    Slot::Val(v) => v.clone(),
                    _ => unreachable!("a result is a number or a value"),
                });
                *slot = r;
                return Ok(Outcome::Normal(v));
            }
        }
        let v = match r {
            Slot::Int(n) => Value::from_int(n),
            Slot::Dbl(d) => Value::from_f64(d),
            Slot::Val(v) => v,
            _ => unreachable!("a result is a number or a value"),
        };
        let v = self.set_local(i, name, v)?;
        Ok(Outcome::Normal(want.then_some(v)))
    }

    #[inline(always)]
    fn incr_local(&mut self, i: u32, name: &str, by: i64, want: bool) -> Run<Outcome> {
        if self.var_traces.is_empty() {
            let slot = &mut self.frames[self.cur].slots[i as usize];
            // An integer, or a value read from one (`$i` keeps its value).
            let x = match slot {
                Slot::Int(x) => Some(*x),
                Slot::Val(v) => v.cached_int(),
                _ => None,
            };
            if let Some(sum) = x.and_then(|x| x.checked_add(by)) {
                *slot = Slot::Int(sum);
                if want {
                    return Ok(Outcome::Normal(Some(Value::from_int(sum))));
                }
                return Ok(Outcome::Normal(None));
            }
        }
        self.incr_local_slow(i, name, by, want)
    }

    #[inline(never)]
    fn incr_local_slow(&mut self, i: u32, name: &str, by: i64, want: bool) -> Run<Outcome> {
        if self.var_traces.is_empty() {
            let slot = &mut self.frames[self.cur].slots[i as usize];
            let x = match slot {
                // A string is read as an integer once (the value keeps it).
                Slot::Val(v) => match v.as_integer() {
                    Ok(Num::Int(x)) => Some(x),
                    _ => None,
                },
                _ => None,
            };
            if let Some(x) = x
                && let Some(sum) = x.checked_add(by)
            {
                *slot = Slot::Int(sum);
                return Ok(Outcome::Normal(want.then(|| Value::from_int(sum))));
            }
        }
        Ok(Outcome::Normal(Some(self.incr_var(name, Num::Int(by))?)))
    }

    /// `append`/`lappend` on local slot `i`: `f` changes its value in
    /// place (by name when it is not a plain scalar or does not exist).
    fn update_local(
        &mut self,
        i: u32,
        name: &str,
        want: bool,
        f: &mut dyn FnMut(&mut Value) -> Result<(), Exception>,
    ) -> Result<Option<Value>, Exception> {
        if self.var_traces.is_empty() {
            let slot = &mut self.frames[self.cur].slots[i as usize];
            match slot {
                Slot::Int(n) => *slot = Slot::Val(Value::from_int(*n)),
                Slot::Dbl(d) => *slot = Slot::Val(Value::from_f64(*d)),
                _ => {}
            }
            match slot {
                Slot::Val(v) => {
                    f(v)?;
                    return Ok(want.then(|| v.clone()));
                }
                Slot::Cell(c) => {
                    if let Var::Scalar(v) = &mut *c.borrow_mut() {
                        f(v)?;
                        return Ok(want.then(|| v.clone()));
                    }
                }
                _ => {}
            }
        }
        self.update_var(name, Some(Value::empty()), f).map(|v| want.then_some(v))
    }
}

/// An integer comparison's truth.
#[inline(always)]
fn compare(op: BinOp, x: i64, y: i64) -> bool {
    match op {
        BinOp::Lt => x < y,
        BinOp::Le => x <= y,
        BinOp::Gt => x > y,
        BinOp::Ge => x >= y,
        BinOp::Eq => x == y,
        _ => x != y,
    }
}

/// Tcl's double arithmetic and comparisons, without `Num`s: `None` for
/// what needs more (division by zero, `**`, a NaN or infinite result).
#[inline]
fn dbl_binary(op: BinOp, x: f64, y: f64) -> Option<Operand> {
    if x.is_nan() || y.is_nan() {
        return None;
    }
    let r = match op {
        BinOp::Add => x + y,
        BinOp::Sub => x - y,
        BinOp::Mul => x * y,
        BinOp::Div if y != 0.0 => x / y,
        BinOp::Lt => return Some(Operand::Int((x < y) as i64)),
        BinOp::Gt => return Some(Operand::Int((x > y) as i64)),
        BinOp::Le => return Some(Operand::Int((x <= y) as i64)),
        BinOp::Ge => return Some(Operand::Int((x >= y) as i64)),
        BinOp::Eq => return Some(Operand::Int((x == y) as i64)),
        BinOp::Ne => return Some(Operand::Int((x != y) as i64)),
        _ => return None,
    };
    r.is_finite().then_some(Operand::Dbl(r))
}
