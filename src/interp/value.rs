//! `Value`: Tcl's dual-ported value. Every value has a string form (Tcl's
//! "everything is a string"), produced lazily, plus a cached internal form
//! (integer, double, list, parsed script, parsed expression) so that a loop
//! body is parsed once and a list is not re-split on every `lindex`.
//!
//! `Value` is `Rc`-based and deliberately not `Send`: it never leaves the
//! interpreter's thread. Scene commands convert to plain numbers at the edge.

use std::cell::{OnceCell, RefCell};
use std::rc::Rc;

use compact_str::CompactString;

use super::error::Exception;
use super::expr::Expr;
use super::list;
use super::number::{self, Num};
use super::parser::Script;

#[derive(Clone)]
pub struct Value(Rc<Inner>);

struct Inner {
    /// Short strings (most words: numbers, names) live inline: one
    /// allocation per value instead of two.
    string: OnceCell<CompactString>,
    rep: RefCell<Rep>,
}

/// The cached internal representation. Replacing it ("shimmering") is always
/// allowed once the string form exists, because the string is the truth.
#[derive(Clone)]
pub(crate) enum Rep {
    None,
    Int(i64),
    Double(f64),
    List(Rc<Vec<Value>>),
    Script(Rc<Script>),
    Expr(Rc<Expr>),
    /// A braced word straight from the parser: where it came from, so a proc
    /// or loop body defined in a file reports that file's line numbers.
    Origin(Option<Rc<str>>, u32),
}

thread_local! {
    static EMPTY: Value = Value::from_string(String::new());
}

impl Value {
    pub fn empty() -> Value {
        EMPTY.with(|v| v.clone())
    }

    pub fn from_string(s: String) -> Value {
        Value(Rc::new(Inner {
            string: OnceCell::from(CompactString::from(s)),
            rep: RefCell::new(Rep::None),
        }))
    }

    pub fn from_int(i: i64) -> Value {
        Value(Rc::new(Inner { string: OnceCell::new(), rep: RefCell::new(Rep::Int(i)) }))
    }

    pub fn from_f64(d: f64) -> Value {
        Value(Rc::new(Inner { string: OnceCell::new(), rep: RefCell::new(Rep::Double(d)) }))
    }

    pub fn from_bool(b: bool) -> Value {
        Value::from_int(b as i64)
    }

    pub fn from_num(n: Num) -> Value {
        match n {
            Num::Int(i) => Value::from_int(i),
            Num::Double(d) => Value::from_f64(d),
        }
    }

    pub fn from_list(items: Vec<Value>) -> Value {
        Value(Rc::new(Inner {
            string: OnceCell::new(),
            rep: RefCell::new(Rep::List(Rc::new(items))),
        }))
    }

    pub(crate) fn with_origin(s: String, file: Option<Rc<str>>, line: u32) -> Value {
        Value(Rc::new(Inner {
            string: OnceCell::from(CompactString::from(s)),
            rep: RefCell::new(Rep::Origin(file, line)),
        }))
    }

    /// The string form, generated from the internal form on first use.
    pub fn as_str(&self) -> &str {
        self.0.string.get_or_init(|| match &*self.0.rep.borrow() {
            Rep::Int(i) => CompactString::from(itoa::Buffer::new().format(*i)),
            Rep::Double(d) => CompactString::from(number::format_double(*d)),
            Rep::List(items) => CompactString::from(list::format_list(items)),
            _ => CompactString::default(),
        })
    }

    pub fn is_empty(&self) -> bool {
        match &*self.0.rep.borrow() {
            Rep::Int(_) | Rep::Double(_) => return false,
            Rep::List(l) if self.0.string.get().is_none() => return l.is_empty(),
            _ => {}
        }
        self.as_str().is_empty()
    }

    pub(crate) fn rep(&self) -> std::cell::Ref<'_, Rep> {
        self.0.rep.borrow()
    }

    pub(crate) fn set_rep(&self, rep: Rep) {
        // The string must exist before the old representation is dropped.
        self.as_str();
        *self.0.rep.borrow_mut() = rep;
    }

    /// The value as a number, if its string is one (cached).
    pub fn as_num(&self) -> Option<Num> {
        match &*self.0.rep.borrow() {
            Rep::Int(i) => return Some(Num::Int(*i)),
            Rep::Double(d) => return Some(Num::Double(*d)),
            _ => {}
        }
        let n = number::parse_num(self.as_str())?;
        // Keep a list, script or expression cache; numbers are cheap to re-parse.
        if matches!(&*self.0.rep.borrow(), Rep::None | Rep::Origin(..)) {
            self.set_rep(match n {
                Num::Int(i) => Rep::Int(i),
                Num::Double(d) => Rep::Double(d),
            });
        }
        Some(n)
    }

    pub fn as_int(&self) -> Result<i64, Exception> {
        match self.as_num() {
            Some(Num::Int(i)) => Ok(i),
            _ => Err(number::int_error(self.as_str())),
        }
    }

    pub fn as_f64(&self) -> Result<f64, Exception> {
        match self.as_num() {
            Some(n) => Ok(n.to_f64()),
            None => Err(Exception::error(format!(
                "expected floating-point number but got \"{}\"",
                self.as_str()
            ))),
        }
    }

    pub fn as_bool(&self) -> Result<bool, Exception> {
        if let Some(n) = self.as_num() {
            return Ok(n.truthy());
        }
        number::parse_bool(self.as_str()).ok_or_else(|| {
            Exception::error(format!("expected boolean value but got \"{}\"", self.as_str()))
        })
    }

    /// The value as a list (cached).
    pub fn as_list(&self) -> Result<Rc<Vec<Value>>, Exception> {
        if let Rep::List(l) = &*self.0.rep.borrow() {
            return Ok(l.clone());
        }
        let items = Rc::new(list::parse_list(self.as_str())?);
        self.set_rep(Rep::List(items.clone()));
        Ok(items)
    }

    /// Appends list elements in place when this value is not shared, so
    /// `lappend` in a loop is linear, not quadratic.
    pub fn list_append(&mut self, extra: &[Value]) -> Result<(), Exception> {
        let items = self.as_list()?;
        if let Some(inner) = Rc::get_mut(&mut self.0) {
            drop(items);
            if let Rep::List(l) = inner.rep.get_mut() {
                Rc::make_mut(l).extend_from_slice(extra);
                inner.string.take();
                return Ok(());
            }
            unreachable!("as_list just cached a list");
        }
        let mut v = (*items).clone();
        v.extend_from_slice(extra);
        *self = Value::from_list(v);
        Ok(())
    }

    /// Appends to the string in place when this value is not shared.
    pub fn str_append(&mut self, extra: &str) {
        self.as_str();
        if let Some(inner) = Rc::get_mut(&mut self.0)
            && let Some(s) = inner.string.get_mut()
        {
            s.push_str(extra);
            *inner.rep.get_mut() = Rep::None;
            return;
        }
        let mut s = String::with_capacity(self.as_str().len() + extra.len());
        s.push_str(self.as_str());
        s.push_str(extra);
        *self = Value::from_string(s);
    }

    /// Reuses this value's allocation for a new plain string when nothing
    /// else holds it (the fast path for long generated scripts).
    pub(crate) fn recycle(&mut self, s: &str) -> bool {
        match Rc::get_mut(&mut self.0) {
            Some(inner) => {
                match inner.string.get_mut() {
                    Some(st) => {
                        st.clear();
                        st.push_str(s);
                    }
                    None => inner.string = OnceCell::from(CompactString::new(s)),
                }
                *inner.rep.get_mut() = Rep::None;
                true
            }
            None => false,
        }
    }
}

impl Default for Value {
    fn default() -> Value {
        Value::empty()
    }
}

impl From<&str> for Value {
    fn from(s: &str) -> Value {
        Value(Rc::new(Inner {
            string: OnceCell::from(CompactString::new(s)),
            rep: RefCell::new(Rep::None),
        }))
    }
}

impl From<String> for Value {
    fn from(s: String) -> Value {
        Value::from_string(s)
    }
}

impl std::fmt::Debug for Value {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{:?}", self.as_str())
    }
}

impl std::fmt::Display for Value {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}
