//! `expr`: Tcl 8.6 expressions. Tokens come from a logos lexer (numbers,
//! operators, names); `$var`, `[cmd]`, `"..."` and `{...}` operands reuse
//! the script parser. The result is an AST (`Expr`) cached on the value, so
//! a loop condition is parsed once. Evaluation follows Tcl's rules: 64-bit
//! integers and doubles, `==` numeric only when both sides are numbers,
//! lazy `&& || ?:`, floor division, and Tcl's error wording.

use std::rc::Rc;

use logos::Logos;
use num_bigint::BigInt;
use num_integer::{Integer, Roots};
use num_traits::{Signed, Zero};

use super::error::Exception;
use super::eval::Interp;
use super::number::{self, Num};
use super::parser::{Parser, Word};
use super::value::Value;

#[derive(Logos, Debug, PartialEq, Clone, Copy)]
enum Tok {
    #[regex(r"[0-9]+\.?[0-9]*([eE][+-]?[0-9]+)?")]
    #[regex(r"\.[0-9]+([eE][+-]?[0-9]+)?")]
    #[regex(r"0[xX][0-9a-fA-F]+|0[bB][01]+|0[oO][0-7]+")]
    Number,
    #[regex(r"[A-Za-z][A-Za-z0-9_]*")]
    Ident,
    #[token("**")]
    Pow,
    #[token("*")]
    Mul,
    #[token("/")]
    Div,
    #[token("%")]
    Mod,
    #[token("+")]
    Plus,
    #[token("-")]
    Minus,
    #[token("<<")]
    Shl,
    #[token(">>")]
    Shr,
    #[token("<")]
    Lt,
    #[token(">")]
    Gt,
    #[token("<=")]
    Le,
    #[token(">=")]
    Ge,
    #[token("==")]
    Eq,
    #[token("!=")]
    Ne,
    #[token("&&")]
    And,
    #[token("||")]
    Or,
    #[token("&")]
    BitAnd,
    #[token("|")]
    BitOr,
    #[token("^")]
    BitXor,
    #[token("~")]
    BitNot,
    #[token("!")]
    Not,
    #[token("?")]
    Question,
    #[token(":")]
    Colon,
    #[token("(")]
    LParen,
    #[token(")")]
    RParen,
    #[token(",")]
    Comma,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum BinOp {
    Pow,
    Mul,
    Div,
    Mod,
    Add,
    Sub,
    Shl,
    Shr,
    Lt,
    Gt,
    Le,
    Ge,
    Eq,
    Ne,
    StrEq,
    StrNe,
    In,
    Ni,
    BitAnd,
    BitXor,
    BitOr,
}

impl BinOp {
    fn symbol(self) -> &'static str {
        match self {
            BinOp::Pow => "**",
            BinOp::Mul => "*",
            BinOp::Div => "/",
            BinOp::Mod => "%",
            BinOp::Add => "+",
            BinOp::Sub => "-",
            BinOp::Shl => "<<",
            BinOp::Shr => ">>",
            BinOp::Lt => "<",
            BinOp::Gt => ">",
            BinOp::Le => "<=",
            BinOp::Ge => ">=",
            BinOp::Eq => "==",
            BinOp::Ne => "!=",
            BinOp::StrEq => "eq",
            BinOp::StrNe => "ne",
            BinOp::In => "in",
            BinOp::Ni => "ni",
            BinOp::BitAnd => "&",
            BinOp::BitXor => "^",
            BinOp::BitOr => "|",
        }
    }

    /// Binding power: higher binds tighter.
    fn precedence(self) -> u8 {
        match self {
            BinOp::Pow => 12,
            BinOp::Mul | BinOp::Div | BinOp::Mod => 11,
            BinOp::Add | BinOp::Sub => 10,
            BinOp::Shl | BinOp::Shr => 9,
            BinOp::Lt | BinOp::Gt | BinOp::Le | BinOp::Ge => 8,
            BinOp::Eq | BinOp::Ne => 7,
            BinOp::StrEq | BinOp::StrNe => 6,
            BinOp::In | BinOp::Ni => 5,
            BinOp::BitAnd => 4,
            BinOp::BitXor => 3,
            BinOp::BitOr => 2,
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum UnOp {
    Neg,
    Plus,
    Not,
    BitNot,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Func {
    Abs,
    Acos,
    Asin,
    Atan,
    Atan2,
    Bool,
    Ceil,
    Cos,
    Cosh,
    Double,
    Entier,
    Exp,
    Floor,
    Fmod,
    Hypot,
    Int,
    Isqrt,
    Log,
    Log10,
    Max,
    Min,
    Pow,
    Rand,
    Round,
    Sin,
    Sinh,
    Sqrt,
    Srand,
    Tan,
    Tanh,
    Wide,
}

impl Func {
    pub(crate) const NAMES: &[&str] = &[
        "abs", "acos", "asin", "atan", "atan2", "bool", "ceil", "cos", "cosh", "double", "entier",
        "exp", "floor", "fmod", "hypot", "int", "isqrt", "log", "log10", "max", "min", "pow",
        "rand", "round", "sin", "sinh", "sqrt", "srand", "tan", "tanh", "wide",
    ];

    pub(crate) fn from_name(name: &str) -> Option<Func> {
        Some(match name {
            "abs" => Func::Abs,
            "acos" => Func::Acos,
            "asin" => Func::Asin,
            "atan" => Func::Atan,
            "atan2" => Func::Atan2,
            "bool" => Func::Bool,
            "ceil" => Func::Ceil,
            "cos" => Func::Cos,
            "cosh" => Func::Cosh,
            "double" => Func::Double,
            "entier" => Func::Entier,
            "exp" => Func::Exp,
            "floor" => Func::Floor,
            "fmod" => Func::Fmod,
            "hypot" => Func::Hypot,
            "int" => Func::Int,
            "isqrt" => Func::Isqrt,
            "log" => Func::Log,
            "log10" => Func::Log10,
            "max" => Func::Max,
            "min" => Func::Min,
            "pow" => Func::Pow,
            "rand" => Func::Rand,
            "round" => Func::Round,
            "sin" => Func::Sin,
            "sinh" => Func::Sinh,
            "sqrt" => Func::Sqrt,
            "srand" => Func::Srand,
            "tan" => Func::Tan,
            "tanh" => Func::Tanh,
            "wide" => Func::Wide,
            _ => return None,
        })
    }

    /// (minimum, maximum) argument counts.
    fn arity(self) -> (usize, usize) {
        match self {
            Func::Rand => (0, 0),
            Func::Atan2 | Func::Fmod | Func::Hypot | Func::Pow => (2, 2),
            Func::Max | Func::Min => (1, usize::MAX),
            _ => (1, 1),
        }
    }
}

pub enum Expr {
    Lit(Operand),
    Word(Word),
    Unary(UnOp, Box<Expr>),
    Binary(BinOp, Box<Expr>, Box<Expr>),
    And(Box<Expr>, Box<Expr>),
    Or(Box<Expr>, Box<Expr>),
    Ternary(Box<Expr>, Box<Expr>, Box<Expr>),
    Call(Func, Vec<Expr>),
    /// A function of the script's own: the command `tcl::mathfunc::NAME`.
    Custom(Rc<str>, Vec<Expr>),
}

/// An operand during evaluation: numbers stay unboxed.
#[derive(Clone)]
pub enum Operand {
    Int(i64),
    Dbl(f64),
    Big(Rc<BigInt>),
    Str(Value),
}

impl Operand {
    pub(crate) fn from_value(v: Value) -> Operand {
        Operand::Str(v)
    }

    fn num(&self) -> Option<Num> {
        match self {
            Operand::Int(i) => Some(Num::Int(*i)),
            Operand::Dbl(d) => Some(Num::Double(*d)),
            Operand::Big(b) => Some(Num::Big(b.clone())),
            Operand::Str(v) => v.as_num(),
        }
    }

    #[inline]
    pub(crate) fn num_for(&self, op: &str) -> Result<Num, Exception> {
        match self.num() {
            Some(Num::Double(d)) if d.is_nan() => Err(Exception::error(format!(
                "can't use non-numeric floating-point value as operand of \"{op}\""
            ))),
            Some(n) => Ok(n),
            None => Err(self.type_error(op)),
        }
    }

    fn type_error(&self, op: &str) -> Exception {
        match self {
            Operand::Str(v) if v.as_str().is_empty() => {
                Exception::error(format!("can't use empty string as operand of \"{op}\""))
                    .with_error_code("ARITH DOMAIN {empty string}")
            }
            _ => Exception::error(format!("can't use non-numeric string as operand of \"{op}\""))
                .with_error_code("ARITH DOMAIN {non-numeric string}"),
        }
    }

    /// An integer operand of any size, for the bit and shift operators.
    #[inline]
    fn int_for(&self, op: &str) -> Result<Num, Exception> {
        match self.num_for(op)? {
            Num::Double(_) => Err(Exception::error(format!(
                "can't use floating-point value as operand of \"{op}\""
            ))),
            n => Ok(n),
        }
    }

    pub(crate) fn truth(&self) -> Result<bool, Exception> {
        match self {
            Operand::Int(i) => Ok(*i != 0),
            Operand::Dbl(d) if d.is_nan() => Err(not_a_number()),
            Operand::Dbl(d) => Ok(*d != 0.0),
            Operand::Big(_) => Ok(true),
            Operand::Str(v) => v.as_bool(),
        }
    }

    /// The operand's string, an integer's written into `buf`.
    fn str_for_compare<'a>(&'a self, buf: &'a mut itoa::Buffer) -> std::borrow::Cow<'a, str> {
        match self {
            Operand::Int(i) => std::borrow::Cow::Borrowed(buf.format(*i)),
            Operand::Str(v) => std::borrow::Cow::Borrowed(v.as_str()),
            _ => std::borrow::Cow::Owned(self.str_value().as_str().to_owned()),
        }
    }

    fn str_value(&self) -> Value {
        match self {
            Operand::Int(i) => Value::from_int(*i),
            Operand::Dbl(d) => Value::from_f64(*d),
            Operand::Big(b) => Value::from_num(Num::Big(b.clone())),
            Operand::Str(v) => v.clone(),
        }
    }

    #[inline]
    pub fn into_value(self) -> Value {
        match self {
            Operand::Int(i) => Value::from_int(i),
            Operand::Dbl(d) => Value::from_f64(d),
            Operand::Big(b) => Value::from_num(Num::Big(b)),
            Operand::Str(v) => match v.as_num() {
                Some(n) => Value::from_num(n),
                None => v,
            },
        }
    }
}

fn from_num(n: Num) -> Operand {
    match n {
        Num::Int(i) => Operand::Int(i),
        Num::Double(d) => Operand::Dbl(d),
        Num::Big(b) => Operand::Big(b),
    }
}

fn from_big(b: BigInt) -> Operand {
    from_num(Num::from_big(b))
}

// ---------------------------------------------------------------------------
// Parsing

/// Tcl's bareword characters.
fn is_bareword(c: u8) -> bool {
    c.is_ascii_alphanumeric() || c == b'_'
}

/// `eq ne in ni` at the start of `s`, when no letter follows them.
fn word_operator(s: &str) -> Option<BinOp> {
    let op = match s.get(..2)? {
        "eq" => BinOp::StrEq,
        "ne" => BinOp::StrNe,
        "in" => BinOp::In,
        "ni" => BinOp::Ni,
        _ => return None,
    };
    (!s.as_bytes().get(2).is_some_and(u8::is_ascii_alphabetic)).then_some(op)
}

struct ExprParser<'a> {
    src: &'a str,
    pos: usize,
    /// One token of lookahead: (token, start, end).
    peeked: Option<Option<(Tok, usize, usize)>>,
    script: Parser,
}

type PResult<T> = Result<T, Exception>;

impl<'a> ExprParser<'a> {
    fn syntax(&self, msg: &str, at: usize) -> Exception {
        let at = at.min(self.src.len());
        Exception::error(format!(
            "{msg} at _@_\nin expression \"{}_@_{}\"",
            &self.src[..at],
            &self.src[at..]
        ))
    }

    fn whole(&self, msg: &str) -> Exception {
        Exception::error(format!("{msg}\nin expression \"{}\"", self.src))
    }

    fn skip_ws(&mut self) {
        let b = self.src.as_bytes();
        while self.pos < b.len()
            && matches!(b[self.pos], b' ' | b'\t' | b'\n' | b'\r' | 0x0b | 0x0c)
        {
            self.pos += 1;
        }
    }

    /// The next operator-or-number token, without consuming it. Operands
    /// that start with `$ [ " {` are reported as `None` with their start.
    fn peek(&mut self) -> PResult<Option<(Tok, usize, usize)>> {
        if let Some(p) = self.peeked {
            return Ok(p);
        }
        self.skip_ws();
        let start = self.pos;
        if start >= self.src.len() {
            self.peeked = Some(None);
            return Ok(None);
        }
        if matches!(self.src.as_bytes()[start], b'$' | b'[' | b'"' | b'{') {
            self.peeked = Some(None);
            return Ok(None);
        }
        let mut lex = Tok::lexer(&self.src[start..]);
        match lex.next() {
            Some(Ok(t)) => {
                let span = lex.span();
                let (mut t, mut end) = (t, start + span.end);
                if t == Tok::Number && self.src.as_bytes().get(end).is_some_and(|&c| is_bareword(c))
                {
                    // A number run into letters: Tcl keeps the number when
                    // it has a `.` or sign in it or an operator follows
                    // (`3eq2`); otherwise the whole run is one bareword.
                    let text = &self.src.as_bytes()[start..end];
                    if text.iter().all(|&c| is_bareword(c))
                        && word_operator(&self.src[end..]).is_none()
                    {
                        t = Tok::Ident;
                        end += self.src.as_bytes()[end..]
                            .iter()
                            .take_while(|&&c| is_bareword(c))
                            .count();
                    }
                }
                let r = Some((t, start + span.start, end));
                self.peeked = Some(r);
                Ok(r)
            }
            _ => {
                let ch = self.src[start..].chars().next().unwrap_or(' ');
                Err(self.whole(&format!("invalid character \"{ch}\"")))
            }
        }
    }

    fn bump(&mut self, end: usize) {
        self.pos = end;
        self.peeked = None;
    }

    fn at_operand_sigil(&mut self) -> bool {
        self.skip_ws();
        matches!(self.peeked, None | Some(None))
            && self.pos < self.src.len()
            && matches!(self.src.as_bytes()[self.pos], b'$' | b'[' | b'"' | b'{')
    }

    fn bareword(&self, w: &str) -> Exception {
        Exception::error(format!(
            "invalid bareword \"{w}\"\nin expression \"{}\";\nshould be \"${w}\" or \"{{{w}}}\" or \"{w}(...)\" or ...",
            self.src
        ))
    }

    fn binop(&mut self) -> PResult<Option<(BinOp, usize)>> {
        let Some((t, s, e)) = self.peek()? else { return Ok(None) };
        let op = match t {
            Tok::Pow => BinOp::Pow,
            Tok::Mul => BinOp::Mul,
            Tok::Div => BinOp::Div,
            Tok::Mod => BinOp::Mod,
            Tok::Plus => BinOp::Add,
            Tok::Minus => BinOp::Sub,
            Tok::Shl => BinOp::Shl,
            Tok::Shr => BinOp::Shr,
            Tok::Lt => BinOp::Lt,
            Tok::Gt => BinOp::Gt,
            Tok::Le => BinOp::Le,
            Tok::Ge => BinOp::Ge,
            Tok::Eq => BinOp::Eq,
            Tok::Ne => BinOp::Ne,
            Tok::BitAnd => BinOp::BitAnd,
            Tok::BitOr => BinOp::BitOr,
            Tok::BitXor => BinOp::BitXor,
            Tok::Ident => match word_operator(&self.src[s..e]) {
                Some(op) => return Ok(Some((op, s + 2))),
                None => return Err(self.bareword(&self.src[s..e])),
            },
            _ => return Ok(None),
        };
        Ok(Some((op, e)))
    }

    fn parse_top(&mut self) -> PResult<Expr> {
        self.skip_ws();
        if self.pos >= self.src.len() {
            return Err(self.whole("empty expression"));
        }
        let e = self.ternary()?;
        if self.at_operand_sigil() {
            return Err(self.syntax("missing operator", self.pos));
        }
        match self.peek()? {
            None => Ok(e),
            Some((Tok::RParen, _, _)) => Err(self.whole("unbalanced close paren")),
            Some((_, s, _)) => Err(self.syntax("missing operator", s)),
        }
    }

    fn ternary(&mut self) -> PResult<Expr> {
        let cond = self.or()?;
        if let Some((Tok::Question, _, e)) = self.peek()? {
            self.bump(e);
            let a = self.ternary()?;
            match self.peek()? {
                Some((Tok::Colon, _, e)) => self.bump(e),
                _ => return Err(self.syntax("missing operator \":\"", self.pos)),
            }
            let b = self.ternary()?;
            return Ok(Expr::Ternary(Box::new(cond), Box::new(a), Box::new(b)));
        }
        Ok(cond)
    }

    fn or(&mut self) -> PResult<Expr> {
        let mut l = self.and()?;
        while let Some((Tok::Or, _, e)) = self.peek()? {
            self.bump(e);
            let r = self.and()?;
            l = Expr::Or(Box::new(l), Box::new(r));
        }
        Ok(l)
    }

    fn and(&mut self) -> PResult<Expr> {
        let mut l = self.binary(0)?;
        while let Some((Tok::And, _, e)) = self.peek()? {
            self.bump(e);
            let r = self.binary(0)?;
            l = Expr::And(Box::new(l), Box::new(r));
        }
        Ok(l)
    }

    /// Precedence climbing over the binary operators.
    fn binary(&mut self, min_prec: u8) -> PResult<Expr> {
        let mut l = self.unary()?;
        while let Some((op, end)) = self.binop()? {
            let prec = op.precedence();
            if prec < min_prec {
                break;
            }
            self.bump(end);
            // `**` is right-associative; the rest are left-associative.
            let next = if op == BinOp::Pow { prec } else { prec + 1 };
            let r = self.binary(next)?;
            l = Expr::Binary(op, Box::new(l), Box::new(r));
        }
        Ok(l)
    }

    fn unary(&mut self) -> PResult<Expr> {
        let op = match self.peek()? {
            Some((Tok::Minus, _, e)) => Some((UnOp::Neg, e)),
            Some((Tok::Plus, _, e)) => Some((UnOp::Plus, e)),
            Some((Tok::Not, _, e)) => Some((UnOp::Not, e)),
            Some((Tok::BitNot, _, e)) => Some((UnOp::BitNot, e)),
            _ => None,
        };
        if let Some((op, e)) = op {
            self.bump(e);
            let x = self.unary()?;
            return Ok(Expr::Unary(op, Box::new(x)));
        }
        self.primary()
    }

    fn primary(&mut self) -> PResult<Expr> {
        if self.at_operand_sigil() {
            return self.word_operand();
        }
        let Some((t, s, e)) = self.peek()? else {
            return Err(self.syntax("missing operand", self.pos));
        };
        match t {
            Tok::Number => {
                self.bump(e);
                let text = &self.src[s..e];
                match number::parse_num(text) {
                    Some(n) => Ok(Expr::Lit(from_num(n))),
                    None => Err(Exception::error(format!(
                        "invalid bareword \"{text}\"\nin expression \"{}\";\nshould be \"${text}\" or \"{{{text}}}\" or \"{text}(...)\" or ... (invalid octal number?)",
                        self.src
                    ))),
                }
            }
            Tok::LParen => {
                self.bump(e);
                let inner = self.ternary()?;
                match self.peek()? {
                    Some((Tok::RParen, _, e)) => {
                        self.bump(e);
                        Ok(inner)
                    }
                    _ if self.pos >= self.src.len() => Err(self.whole("unbalanced open paren")),
                    _ => Err(self.syntax("missing close paren", self.pos)),
                }
            }
            Tok::Ident => {
                let name = &self.src[s..e];
                self.bump(e);
                self.skip_ws();
                if self.src[self.pos..].starts_with('(') {
                    self.pos += 1;
                    return self.call(name.to_string());
                }
                let lower = name.to_ascii_lowercase();
                if number::parse_bool(name).is_some() && !matches!(lower.as_str(), "eq" | "ne")
                    || matches!(lower.as_str(), "inf" | "infinity" | "nan")
                {
                    if let Some(d) = number::parse_double(name) {
                        return Ok(Expr::Lit(Operand::Dbl(d)));
                    }
                    return Ok(Expr::Lit(Operand::Str(Value::from(name))));
                }
                Err(self.bareword(name))
            }
            _ => Err(self.syntax("missing operand", s)),
        }
    }

    fn call(&mut self, name: String) -> PResult<Expr> {
        let mut args = Vec::new();
        self.peeked = None;
        if let Some((Tok::RParen, _, e)) = self.peek()? {
            self.bump(e);
        } else {
            loop {
                args.push(self.ternary()?);
                match self.peek()? {
                    Some((Tok::Comma, _, e)) => self.bump(e),
                    Some((Tok::RParen, _, e)) => {
                        self.bump(e);
                        break;
                    }
                    _ if self.pos >= self.src.len() => {
                        return Err(self.whole("unbalanced open paren"));
                    }
                    _ => return Err(self.syntax("missing close paren", self.pos)),
                }
            }
        }
        Ok(match Func::from_name(&name) {
            Some(f) => Expr::Call(f, args),
            None => Expr::Custom(Rc::from(name.as_str()), args),
        })
    }

    fn word_operand(&mut self) -> PResult<Expr> {
        self.script.set_pos(self.pos);
        let w = self.script.expr_word().map_err(|e| self.whole(&e.msg))?;
        self.pos = self.script.pos();
        self.peeked = None;
        Ok(match w {
            Word::Lit(v) => Expr::Lit(Operand::Str(v)),
            w => Expr::Word(w),
        })
    }
}

/// Parses an expression.
pub fn parse(src: &str, file: Option<Rc<str>>, first_line: u32) -> Result<Expr, Exception> {
    let mut p = ExprParser {
        src,
        pos: 0,
        peeked: None,
        script: Parser::new(Rc::from(src), file, first_line),
    };
    p.parse_top()
}

// ---------------------------------------------------------------------------
// Evaluation

/// The most bits a bignum result may have (8 MiB, about 20 million decimal
/// digits): a guard against `1<<(1<<40)` and `10**(10**12)` exhausting
/// memory, far beyond what any scene needs.
const MAX_BIG_BITS: u64 = 1 << 26;

fn divide_by_zero() -> Exception {
    Exception::error("divide by zero").with_error_code("ARITH DIVZERO {divide by zero}")
}

fn not_a_number() -> Exception {
    Exception::error("floating point value is Not a Number")
}

fn too_large() -> Exception {
    Exception::error("integer value too large to represent")
}

fn check_double(d: f64) -> Result<Operand, Exception> {
    if d.is_nan() {
        return Err(Exception::error("domain error: argument not in valid range")
            .with_error_code("ARITH DOMAIN {domain error: argument not in valid range}"));
    }
    Ok(Operand::Dbl(d))
}

fn big(n: &Num) -> BigInt {
    n.to_bigint().unwrap_or_default()
}

/// An integer against a double, exactly (Tcl does not round the integer
/// to a double first). `None` when the double is NaN.
fn cmp_int_double(i: &Num, d: f64) -> Option<std::cmp::Ordering> {
    use std::cmp::Ordering;
    if d.is_nan() {
        return None;
    }
    if let Num::Int(i) = i
        && i.unsigned_abs() <= 1 << 53
    {
        return (*i as f64).partial_cmp(&d);
    }
    if d.is_infinite() {
        return Some(if d > 0.0 { Ordering::Less } else { Ordering::Greater });
    }
    let t = d.trunc();
    let whole = BigInt::from(t as i128);
    let whole = if t.abs() < 1.7e38 { whole } else { num_traits::FromPrimitive::from_f64(t)? };
    Some(big(i).cmp(&whole).then(if d > t {
        Ordering::Less
    } else if d < t {
        Ordering::Greater
    } else {
        Ordering::Equal
    }))
}

fn cmp_nums(x: &Num, y: &Num) -> Option<std::cmp::Ordering> {
    match (x, y) {
        (Num::Int(a), Num::Int(b)) => Some(a.cmp(b)),
        (Num::Double(a), Num::Double(b)) => a.partial_cmp(b),
        (Num::Double(a), i) => cmp_int_double(i, *a).map(std::cmp::Ordering::reverse),
        (i, Num::Double(b)) => cmp_int_double(i, *b),
        _ => Some(big(x).cmp(&big(y))),
    }
}

/// Numbers compare as numbers, anything else as strings. `None` when a
/// NaN is involved: every comparison is then false but `!=`.
fn compare(a: &Operand, b: &Operand) -> Option<std::cmp::Ordering> {
    match (a.num(), b.num()) {
        (Some(x), Some(y)) => cmp_nums(&x, &y),
        // As strings (`$n != {}`): an integer's digits made on the stack.
        _ => {
            let (mut p, mut q) = (itoa::Buffer::new(), itoa::Buffer::new());
            let (sa, sb) = (a.str_for_compare(&mut p), b.str_for_compare(&mut q));
            Some(sa.as_ref().cmp(sb.as_ref()))
        }
    }
}

fn int_pow(base: &Num, exp: &Num) -> Result<Operand, Exception> {
    let odd = |e: &Num| match e {
        Num::Int(i) => i & 1 == 1,
        _ => big(e).is_odd(),
    };
    let negative = match exp {
        Num::Int(e) => *e < 0,
        _ => big(exp).is_negative(),
    };
    if *exp == Num::Int(0) {
        return Ok(Operand::Int(1));
    }
    match base {
        Num::Int(0) if negative => {
            return Err(Exception::error("exponentiation of zero by negative power"));
        }
        Num::Int(b @ (0 | 1)) => return Ok(Operand::Int(*b)),
        Num::Int(-1) => return Ok(Operand::Int(if odd(exp) { -1 } else { 1 })),
        _ if negative => return Ok(Operand::Int(0)),
        _ => {}
    }
    let e = match exp {
        Num::Int(e) => u32::try_from(*e).ok(),
        _ => None,
    };
    let Some(e) = e else { return Err(Exception::error("exponent too large")) };
    if let Num::Int(b) = base
        && let Some(r) = b.checked_pow(e)
    {
        return Ok(Operand::Int(r));
    }
    let b = big(base);
    if b.bits().saturating_mul(e as u64) > MAX_BIG_BITS {
        return Err(Exception::error("exponent too large"));
    }
    Ok(from_big(num_traits::Pow::pow(b, e)))
}

/// `+ - * /` on two integers of any size; the 64-bit path first.
fn int_arith(op: BinOp, x: &Num, y: &Num) -> Result<Operand, Exception> {
    if let (Num::Int(a), Num::Int(b)) = (x, y) {
        let r = match op {
            BinOp::Add => a.checked_add(*b),
            BinOp::Sub => a.checked_sub(*b),
            BinOp::Mul => a.checked_mul(*b),
            _ => {
                if *b == 0 {
                    return Err(divide_by_zero());
                }
                // Floor division; only MIN / -1 overflows.
                a.checked_div(*b)
                    .map(|q| if a % b != 0 && ((*a < 0) != (*b < 0)) { q - 1 } else { q })
            }
        };
        if let Some(r) = r {
            return Ok(Operand::Int(r));
        }
    }
    let (a, b) = (big(x), big(y));
    Ok(from_big(match op {
        BinOp::Add => a + b,
        BinOp::Sub => a - b,
        BinOp::Mul => {
            if a.bits() + b.bits() > MAX_BIG_BITS {
                return Err(too_large());
            }
            a * b
        }
        _ => {
            if b.is_zero() {
                return Err(divide_by_zero());
            }
            a.div_floor(&b)
        }
    }))
}

fn int_mod(x: &Num, y: &Num) -> Result<Operand, Exception> {
    if let (Num::Int(a), Num::Int(b)) = (x, y) {
        if *b == 0 {
            return Err(divide_by_zero());
        }
        if *b == -1 {
            return Ok(Operand::Int(0));
        }
        return Ok(Operand::Int(a.mod_floor(b)));
    }
    let b = big(y);
    if b.is_zero() {
        return Err(divide_by_zero());
    }
    Ok(from_big(big(x).mod_floor(&b)))
}

fn shift(op: BinOp, x: &Num, y: &Num) -> Result<Operand, Exception> {
    let negative = match y {
        Num::Int(s) => *s < 0,
        _ => big(y).is_negative(),
    };
    if negative {
        return Err(Exception::error("negative shift argument"));
    }
    let s = match y {
        Num::Int(s) => *s as u64,
        _ => u64::MAX,
    };
    if op == BinOp::Shr {
        return Ok(match x {
            Num::Int(a) => Operand::Int(a >> s.min(63)),
            _ if s >= MAX_BIG_BITS => Operand::Int(if big(x).is_negative() { -1 } else { 0 }),
            _ => from_big(big(x) >> s),
        });
    }
    match x {
        Num::Int(0) => return Ok(Operand::Int(0)),
        Num::Int(a) if s < 63 && (a << s) >> s == *a => return Ok(Operand::Int(a << s)),
        _ => {}
    }
    let a = big(x);
    if a.bits().saturating_add(s) > MAX_BIG_BITS {
        return Err(too_large());
    }
    Ok(from_big(a << s))
}

fn bits(op: BinOp, x: &Num, y: &Num) -> Operand {
    if let (Num::Int(a), Num::Int(b)) = (x, y) {
        return Operand::Int(match op {
            BinOp::BitAnd => a & b,
            BinOp::BitOr => a | b,
            _ => a ^ b,
        });
    }
    let (a, b) = (big(x), big(y));
    from_big(match op {
        BinOp::BitAnd => a & b,
        BinOp::BitOr => a | b,
        _ => a ^ b,
    })
}

/// An operand's 64-bit integer when it is one already (no parsing).
#[inline]
pub(crate) fn quick_int(o: &Operand) -> Option<i64> {
    match o {
        Operand::Int(i) => Some(*i),
        Operand::Str(v) => v.cached_int(),
        _ => None,
    }
}

/// Two 64-bit integers: the operators that cannot overflow or whose
/// overflow is checked here, without building `Num`s.
#[inline]
pub(crate) fn binary_small(op: BinOp, x: i64, y: i64) -> Option<Operand> {
    Some(Operand::Int(match op {
        BinOp::Add => x.checked_add(y)?,
        BinOp::Sub => x.checked_sub(y)?,
        BinOp::Mul => x.checked_mul(y)?,
        BinOp::Mod if y > 0 => x.rem_euclid(y),
        BinOp::Lt => (x < y) as i64,
        BinOp::Gt => (x > y) as i64,
        BinOp::Le => (x <= y) as i64,
        BinOp::Ge => (x >= y) as i64,
        BinOp::Eq => (x == y) as i64,
        BinOp::Ne => (x != y) as i64,
        BinOp::BitAnd => x & y,
        BinOp::BitOr => x | y,
        BinOp::BitXor => x ^ y,
        _ => return None,
    }))
}

pub(crate) fn binary(op: BinOp, a: Operand, b: Operand) -> Result<Operand, Exception> {
    if let (Some(x), Some(y)) = (quick_int(&a), quick_int(&b))
        && let Some(r) = binary_small(op, x, y)
    {
        return Ok(r);
    }
    let sym = op.symbol();
    let is = |o: Option<std::cmp::Ordering>, f: fn(std::cmp::Ordering) -> bool| {
        Operand::Int(o.is_some_and(f) as i64)
    };
    Ok(match op {
        BinOp::Add | BinOp::Sub | BinOp::Mul | BinOp::Div | BinOp::Pow => {
            match (a.num_for(sym)?, b.num_for(sym)?) {
                (x @ (Num::Int(_) | Num::Big(_)), y @ (Num::Int(_) | Num::Big(_))) => {
                    if op == BinOp::Pow { int_pow(&x, &y)? } else { int_arith(op, &x, &y)? }
                }
                (x, y) => {
                    let (x, y) = (x.to_f64(), y.to_f64());
                    if op == BinOp::Pow && x == 0.0 && y < 0.0 {
                        return Err(Exception::error("exponentiation of zero by negative power"));
                    }
                    check_double(match op {
                        BinOp::Add => x + y,
                        BinOp::Sub => x - y,
                        BinOp::Mul => x * y,
                        BinOp::Div => x / y,
                        _ => x.powf(y),
                    })?
                }
            }
        }
        BinOp::Mod => int_mod(&a.int_for(sym)?, &b.int_for(sym)?)?,
        BinOp::Shl | BinOp::Shr => shift(op, &a.int_for(sym)?, &b.int_for(sym)?)?,
        BinOp::BitAnd | BinOp::BitOr | BinOp::BitXor => {
            bits(op, &a.int_for(sym)?, &b.int_for(sym)?)
        }
        BinOp::Lt => is(compare(&a, &b), std::cmp::Ordering::is_lt),
        BinOp::Gt => is(compare(&a, &b), std::cmp::Ordering::is_gt),
        BinOp::Le => is(compare(&a, &b), std::cmp::Ordering::is_le),
        BinOp::Ge => is(compare(&a, &b), std::cmp::Ordering::is_ge),
        BinOp::Eq => is(compare(&a, &b), std::cmp::Ordering::is_eq),
        BinOp::Ne => Operand::Int(!compare(&a, &b).is_some_and(std::cmp::Ordering::is_eq) as i64),
        BinOp::StrEq => Operand::Int((a.str_value().as_str() == b.str_value().as_str()) as i64),
        BinOp::StrNe => Operand::Int((a.str_value().as_str() != b.str_value().as_str()) as i64),
        BinOp::In | BinOp::Ni => {
            let needle = a.str_value();
            let list = b.str_value().as_list()?;
            let found = list.iter().any(|v| v.as_str() == needle.as_str());
            Operand::Int((found == (op == BinOp::In)) as i64)
        }
    })
}

pub(crate) fn unary(op: UnOp, x: Operand) -> Result<Operand, Exception> {
    Ok(match op {
        UnOp::Neg => match x.num_for("-")? {
            Num::Int(i) => match i.checked_neg() {
                Some(n) => Operand::Int(n),
                None => from_big(-BigInt::from(i)),
            },
            Num::Double(d) => Operand::Dbl(-d),
            Num::Big(b) => from_big(-(*b).clone()),
        },
        UnOp::Plus => from_num(x.num_for("+")?),
        UnOp::BitNot => match x.int_for("~")? {
            Num::Int(i) => Operand::Int(!i),
            n => from_big(-big(&n) - 1),
        },
        UnOp::Not => match x.num() {
            Some(Num::Double(d)) if d.is_nan() => return Err(x.num_for("!").unwrap_err()),
            Some(n) => Operand::Int(!n.truthy() as i64),
            None => match &x {
                Operand::Str(v) => match number::parse_bool(v.as_str()) {
                    Some(b) => Operand::Int(!b as i64),
                    None => return Err(x.type_error("!")),
                },
                _ => return Err(x.type_error("!")),
            },
        },
    })
}

/// A double's integer part, of any size.
fn entier(d: f64) -> Result<Num, Exception> {
    if !d.is_finite() {
        return Err(too_large());
    }
    let t = d.trunc();
    if (-9.223_372_036_854_776e18..9.223_372_036_854_776e18).contains(&t) {
        return Ok(Num::Int(t as i64));
    }
    let b: Option<BigInt> = num_traits::FromPrimitive::from_f64(t);
    b.map(Num::from_big).ok_or_else(too_large)
}

/// Calls a built-in math function (from `expr` or as a
/// `tcl::mathfunc` command), checking its argument count.
pub(crate) fn call(
    interp: &mut Interp,
    f: Func,
    name: &str,
    args: Vec<Operand>,
) -> Result<Operand, Exception> {
    let (lo, hi) = f.arity();
    if args.len() < lo {
        let to = if matches!(f, Func::Max | Func::Min) { "to" } else { "for" };
        return Err(Exception::error(format!(
            "not enough arguments {to} math function \"{name}\""
        )));
    }
    if args.len() > hi {
        return Err(Exception::error(format!("too many arguments for math function \"{name}\"")));
    }
    // Functions of any number say "number"; those of doubles say so.
    let kind = match f {
        Func::Abs | Func::Int | Func::Wide | Func::Entier | Func::Round | Func::Isqrt => "number",
        Func::Srand => "integer",
        _ => "floating-point number",
    };
    let num = |o: &Operand| -> Result<Num, Exception> {
        match o.num() {
            Some(Num::Double(d)) if d.is_nan() => Err(not_a_number()),
            Some(n) => Ok(n),
            None => Err(Exception::error(format!(
                "expected {kind} but got \"{}\"",
                o.str_value().as_str()
            ))),
        }
    };
    let dbl = |o: &Operand| -> Result<f64, Exception> { Ok(num(o)?.to_f64()) };
    let integer = |o: &Operand| -> Result<Num, Exception> {
        match num(o)? {
            Num::Double(d) => entier(d),
            n => Ok(n),
        }
    };
    let d1 = |g: fn(f64) -> f64| -> Result<Operand, Exception> { check_double(g(dbl(&args[0])?)) };
    match f {
        Func::Sin => d1(f64::sin),
        Func::Cos => d1(f64::cos),
        Func::Tan => d1(f64::tan),
        Func::Asin => d1(f64::asin),
        Func::Acos => d1(f64::acos),
        Func::Atan => d1(f64::atan),
        Func::Sinh => d1(f64::sinh),
        Func::Cosh => d1(f64::cosh),
        Func::Tanh => d1(f64::tanh),
        Func::Exp => d1(f64::exp),
        Func::Log => d1(f64::ln),
        Func::Log10 => d1(f64::log10),
        Func::Sqrt => d1(f64::sqrt),
        Func::Ceil => d1(f64::ceil),
        Func::Floor => d1(f64::floor),
        Func::Double => d1(|x| x),
        Func::Atan2 => check_double(dbl(&args[0])?.atan2(dbl(&args[1])?)),
        Func::Pow => check_double(dbl(&args[0])?.powf(dbl(&args[1])?)),
        Func::Hypot => check_double(dbl(&args[0])?.hypot(dbl(&args[1])?)),
        Func::Fmod => {
            let (x, y) = (dbl(&args[0])?, dbl(&args[1])?);
            check_double(x % y)
        }
        Func::Abs => Ok(match num(&args[0])? {
            Num::Int(i) => match i.checked_abs() {
                Some(a) => Operand::Int(a),
                None => from_big(BigInt::from(i).abs()),
            },
            Num::Double(d) => Operand::Dbl(d.abs()),
            Num::Big(b) => from_big(b.abs()),
        }),
        Func::Int | Func::Wide => {
            Ok(Operand::Int(integer(&args[0])?.wrap_i64().expect("an integer")))
        }
        Func::Entier => Ok(from_num(integer(&args[0])?)),
        Func::Round => Ok(match num(&args[0])? {
            Num::Double(d) => from_num(entier(d.round())?),
            n => from_num(n),
        }),
        Func::Isqrt => {
            let n = integer(&args[0])?;
            let negative = match &n {
                Num::Int(i) => *i < 0,
                _ => big(&n).is_negative(),
            };
            if negative {
                return Err(Exception::error("square root of negative argument"));
            }
            Ok(match n {
                Num::Int(i) => Operand::Int((i as u64).sqrt() as i64),
                n => from_big(big(&n).sqrt()),
            })
        }
        Func::Bool => Ok(Operand::Int(args[0].truth()? as i64)),
        Func::Max | Func::Min => {
            let mut best = num(&args[0])?;
            for a in &args[1..] {
                let n = num(a)?;
                let order = cmp_nums(&n, &best);
                let better = if f == Func::Max {
                    order.is_some_and(std::cmp::Ordering::is_gt)
                } else {
                    order.is_some_and(std::cmp::Ordering::is_lt)
                };
                if better {
                    best = n;
                }
            }
            Ok(from_num(best))
        }
        Func::Rand => Ok(Operand::Dbl(interp.next_rand())),
        Func::Srand => {
            let seed = integer(&args[0])?.wrap_i64().expect("an integer");
            interp.seed_rand(seed);
            Ok(Operand::Dbl(interp.next_rand()))
        }
    }
}

pub(crate) fn eval(interp: &mut Interp, e: &Expr) -> Result<Operand, Exception> {
    Ok(match e {
        Expr::Lit(o) => o.clone(),
        Expr::Word(w) => Operand::from_value(interp.eval_word(w)?),
        Expr::Unary(op, x) => unary(*op, eval(interp, x)?)?,
        Expr::Binary(op, a, b) => {
            let a = eval(interp, a)?;
            let b = eval(interp, b)?;
            binary(*op, a, b)?
        }
        Expr::And(a, b) => {
            let r = eval(interp, a)?.truth()? && eval(interp, b)?.truth()?;
            Operand::Int(r as i64)
        }
        Expr::Or(a, b) => {
            let r = eval(interp, a)?.truth()? || eval(interp, b)?.truth()?;
            Operand::Int(r as i64)
        }
        Expr::Ternary(c, a, b) => {
            if eval(interp, c)?.truth()? {
                eval(interp, a)?
            } else {
                eval(interp, b)?
            }
        }
        Expr::Call(f, args) => {
            let mut vals = Vec::with_capacity(args.len());
            for a in args {
                vals.push(eval(interp, a)?);
            }
            call(interp, *f, Func::NAMES[*f as usize], vals)?
        }
        Expr::Custom(name, args) => {
            let mut argv = Vec::with_capacity(args.len() + 1);
            argv.push(Value::from(format!("tcl::mathfunc::{name}")));
            for a in args {
                argv.push(eval(interp, a)?.into_value());
            }
            Operand::Str(interp.invoke(&argv)?)
        }
    })
}

#[cfg(test)]
mod tests;
