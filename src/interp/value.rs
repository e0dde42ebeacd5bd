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

impl Drop for Inner {
    /// Frees the lists nested in a list with a work list instead of
    /// recursion: a list nested a million deep would overflow the stack.
    #[inline]
    fn drop(&mut self) {
        if let Rep::List(l) = self.rep.get_mut() {
            drop_list(l);
        }
    }
}

#[inline(never)]
fn drop_list(l: &mut Rc<Vec<Value>>) {
    let Some(items) = Rc::get_mut(l) else { return };
    if !items.iter().any(Value::owns_nested_list) {
        return;
    }
    let mut work = std::mem::take(items);
    while let Some(v) = work.pop() {
        if let Ok(mut inner) = Rc::try_unwrap(v.0)
            && let Rep::List(l) = inner.rep.get_mut()
            && let Some(items) = Rc::get_mut(l)
        {
            // `inner` goes with an empty list; its elements wait here.
            work.append(items);
        }
    }
}

impl Value {
    /// Whether dropping this value would drop a non-empty list.
    fn owns_nested_list(&self) -> bool {
        Rc::strong_count(&self.0) == 1
            && matches!(&*self.0.rep.borrow(), Rep::List(l) if Rc::strong_count(l) == 1 && !l.is_empty())
    }
}

/// The cached internal representation. Replacing it ("shimmering") is always
/// allowed once the string form exists, because the string is the truth.
#[derive(Clone)]
pub(crate) enum Rep {
    None,
    Int(i64),
    Double(f64),
    Big(Rc<num_bigint::BigInt>),
    List(Rc<Vec<Value>>),
    Script(Rc<Script>),
    Expr(Rc<Expr>),
    /// A braced word straight from the parser: where it came from, so a proc
    /// or loop body defined in a file reports that file's line numbers.
    Origin(Box<Origin>),
    /// The string is all ASCII: character `i` is byte `i`.
    Ascii,
    /// The string's characters, for indexing a non-ASCII string.
    Chars(Rc<Vec<char>>),
}

/// Where a braced word came from (boxed: `Rep` stays two words, so a
/// value is 64 bytes with its counts).
#[derive(Clone)]
pub(crate) struct Origin {
    pub(crate) file: Option<Rc<str>>,
    pub(crate) line: u32,
    pub(crate) cont: Option<Rc<super::parser::Cont>>,
}

const _: () = assert!(std::mem::size_of::<Inner>() <= 48);

thread_local! {
    static EMPTY: Value = Value::from_string(String::new());
    /// The error of a string form that could not be made (see `as_str`).
    static PENDING: RefCell<Option<Exception>> = const { RefCell::new(None) };
    static HAS_PENDING: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

#[inline]
pub(crate) fn has_pending() -> bool {
    HAS_PENDING.with(|f| f.get())
}

/// The error left by a string form that could not be made, if any.
pub(crate) fn take_pending() -> Option<Exception> {
    HAS_PENDING.with(|f| f.set(false));
    PENDING.with(|p| p.borrow_mut().take())
}

impl Value {
    /// Heap bytes of one value of its own (a short string or a number):
    /// the handle, the shared box and the allocator's header.
    pub(crate) const BYTES: usize =
        std::mem::size_of::<Value>() + std::mem::size_of::<Inner>() + 2 * 8 + 16;

    pub fn empty() -> Value {
        EMPTY.with(|v| v.clone())
    }

    pub fn from_string(s: String) -> Value {
        Value(Rc::new(Inner {
            string: OnceCell::from(CompactString::from(s)),
            rep: RefCell::new(Rep::None),
        }))
    }

    /// A string built in place (short ones never touch the heap).
    pub(crate) fn from_compact(s: CompactString) -> Value {
        Value(Rc::new(Inner { string: OnceCell::from(s), rep: RefCell::new(Rep::None) }))
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
            Num::Big(b) => {
                Value(Rc::new(Inner { string: OnceCell::new(), rep: RefCell::new(Rep::Big(b)) }))
            }
        }
    }

    pub fn from_list(items: Vec<Value>) -> Value {
        Value(Rc::new(Inner {
            string: OnceCell::new(),
            rep: RefCell::new(Rep::List(Rc::new(items))),
        }))
    }

    pub(crate) fn with_origin(
        s: String,
        file: Option<Rc<str>>,
        line: u32,
        cont: Option<Rc<super::parser::Cont>>,
    ) -> Value {
        Value(Rc::new(Inner {
            string: OnceCell::from(CompactString::from(s)),
            rep: RefCell::new(Rep::Origin(Box::new(Origin { file, line, cont }))),
        }))
    }

    /// The string's characters by index: `None` when it is all ASCII
    /// (index the bytes), else the characters. Cached on a plain string,
    /// so `string index` in a loop does not rescan it.
    pub(crate) fn char_table(&self) -> Option<Rc<Vec<char>>> {
        match &*self.0.rep.borrow() {
            Rep::Ascii => return None,
            Rep::Chars(c) => return Some(c.clone()),
            _ => {}
        }
        let s = self.as_str();
        let table = (!s.is_ascii()).then(|| Rc::new(s.chars().collect::<Vec<char>>()));
        if matches!(*self.0.rep.borrow(), Rep::None) {
            *self.0.rep.borrow_mut() = match &table {
                None => Rep::Ascii,
                Some(c) => Rep::Chars(c.clone()),
            };
        }
        table
    }

    /// Whether both are the same value (not merely equal strings).
    #[inline]
    pub(crate) fn ptr_eq(&self, other: &Value) -> bool {
        Rc::ptr_eq(&self.0, &other.0)
    }

    /// The string form, generated from the internal form on first use.
    ///
    /// A list whose string would pass the value cap or the memory budget
    /// has none: this returns "" (not cached) and leaves the error pending,
    /// and the command that asked fails with it when it returns
    /// (`take_pending`).
    #[inline]
    pub fn as_str(&self) -> &str {
        match self.0.string.get() {
            Some(s) => s,
            None => self.make_str(),
        }
    }

    #[inline(never)]
    fn make_str(&self) -> &str {
        let s = match &*self.0.rep.borrow() {
            Rep::Int(i) => CompactString::from(itoa::Buffer::new().format(*i)),
            Rep::Double(d) => CompactString::from(number::format_double(*d)),
            Rep::Big(b) => CompactString::from(b.to_string()),
            Rep::List(items) => match list::format_list_checked(items) {
                Ok(s) => CompactString::from(s),
                Err(e) => {
                    PENDING.with(|p| *p.borrow_mut() = Some(e));
                    HAS_PENDING.with(|f| f.set(true));
                    return "";
                }
            },
            _ => CompactString::default(),
        };
        self.0.string.get_or_init(|| s)
    }

    /// Whether this is a list whose string form is not made yet.
    pub(crate) fn is_unformatted_list(&self) -> bool {
        self.0.string.get().is_none() && matches!(&*self.0.rep.borrow(), Rep::List(_))
    }

    pub fn is_empty(&self) -> bool {
        match &*self.0.rep.borrow() {
            Rep::Int(_) | Rep::Double(_) | Rep::Big(_) => return false,
            Rep::List(l) if self.0.string.get().is_none() => return l.is_empty(),
            _ => {}
        }
        self.as_str().is_empty()
    }

    pub(crate) fn rep(&self) -> std::cell::Ref<'_, Rep> {
        self.0.rep.borrow()
    }

    pub(crate) fn set_rep(&self, rep: Rep) {
        // The string must exist before the old representation is dropped
        // (it may not, for a list too long to print: keep the list then).
        self.as_str();
        if self.0.string.get().is_some() {
            *self.0.rep.borrow_mut() = rep;
        }
    }

    /// The value's integer, when it is already cached as one (no parsing):
    /// the fast path of `expr`'s operators.
    #[inline]
    pub(crate) fn cached_int(&self) -> Option<i64> {
        match &*self.0.rep.borrow() {
            Rep::Int(i) => Some(*i),
            _ => None,
        }
    }

    /// The value as a number, if its string is one (cached).
    pub fn as_num(&self) -> Option<Num> {
        match &*self.0.rep.borrow() {
            Rep::Int(i) => return Some(Num::Int(*i)),
            Rep::Double(d) => return Some(Num::Double(*d)),
            Rep::Big(b) => return Some(Num::Big(b.clone())),
            _ => {}
        }
        let n = number::parse_num(self.as_str())?;
        // Keep a list, script or expression cache; numbers are cheap to re-parse.
        if matches!(&*self.0.rep.borrow(), Rep::None | Rep::Origin(..) | Rep::Ascii | Rep::Chars(_))
        {
            self.set_rep(match &n {
                Num::Int(i) => Rep::Int(*i),
                Num::Double(d) => Rep::Double(*d),
                Num::Big(b) => Rep::Big(b.clone()),
            });
        }
        Some(n)
    }

    pub fn as_int(&self) -> Result<i64, Exception> {
        match self.as_num() {
            Some(Num::Int(i)) => Ok(i),
            Some(Num::Big(_)) => Err(Exception::error("integer value too large to represent")),
            _ => Err(number::int_error(self.as_str())),
        }
    }

    /// The value as an integer of any size.
    #[inline]
    pub fn as_integer(&self) -> Result<Num, Exception> {
        if let Some(i) = self.cached_int() {
            return Ok(Num::Int(i));
        }
        match self.as_num() {
            Some(n @ (Num::Int(_) | Num::Big(_))) => Ok(n),
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
            if matches!(n, Num::Double(d) if d.is_nan()) {
                return Err(Exception::error("floating point value is Not a Number"));
            }
            return Ok(n.truthy());
        }
        number::parse_bool(self.as_str()).ok_or_else(|| {
            Exception::error(format!("expected boolean value but got \"{}\"", self.as_str()))
        })
    }

    /// The number of elements of the value as a list.
    #[inline]
    pub fn list_len(&self) -> Result<usize, Exception> {
        if let Rep::List(l) = &*self.0.rep.borrow() {
            return Ok(l.len());
        }
        Ok(self.as_list()?.len())
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
        // An unshared list value: in place, with no reference taken.
        if let Some(inner) = Rc::get_mut(&mut self.0)
            && let Rep::List(l) = inner.rep.get_mut()
        {
            Rc::make_mut(l).extend_from_slice(extra);
            inner.string.take();
            return Ok(());
        }
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

    /// Makes this value the integer `i`, reusing its allocation when
    /// nothing else holds it (`incr` of an array element in a loop).
    #[inline]
    pub(crate) fn set_int(&mut self, i: i64) {
        if let Some(inner) = Rc::get_mut(&mut self.0) {
            inner.string = OnceCell::new();
            *inner.rep.get_mut() = Rep::Int(i);
            return;
        }
        *self = Value::from_int(i);
    }

    /// This value's elements to change in place (`lset`, `lreplace` of an
    /// unshared list): copied only when another value shares them. The
    /// string form goes; the list is the value now.
    pub(crate) fn list_items_mut(&mut self) -> Result<&mut Vec<Value>, Exception> {
        let unique_list = Rc::get_mut(&mut self.0)
            .is_some_and(|inner| matches!(inner.rep.get_mut(), Rep::List(_)));
        if !unique_list {
            let items = self.as_list()?;
            *self = Value(Rc::new(Inner {
                string: OnceCell::new(),
                rep: RefCell::new(Rep::List(items)),
            }));
        }
        let inner = Rc::get_mut(&mut self.0).expect("made unique above");
        inner.string.take();
        match inner.rep.get_mut() {
            Rep::List(l) => Ok(Rc::make_mut(l)),
            _ => unreachable!("a list, made above"),
        }
    }

    /// The elements of a pure list (no string form) that nothing else
    /// holds, taken out to change in place: what Tcl does with an
    /// unshared argument (`lreplace [K $l [set l {}]] ...`). The value is
    /// left empty, so only a command's own argument that nothing reads
    /// again (no execution trace, no error after this) may be taken from.
    pub(crate) fn take_unshared_list(&self) -> Option<Vec<Value>> {
        if Rc::strong_count(&self.0) != 1 || self.0.string.get().is_some() {
            return None;
        }
        let mut rep = self.0.rep.borrow_mut();
        match &*rep {
            Rep::List(l) if Rc::strong_count(l) == 1 => {}
            _ => return None,
        }
        match std::mem::replace(&mut *rep, Rep::None) {
            Rep::List(l) => Rc::try_unwrap(l).ok(),
            _ => unreachable!("matched above"),
        }
    }

    /// [`Value::list_append`] of one element, moved in.
    pub fn list_push(&mut self, x: Value) -> Result<(), Exception> {
        if let Some(inner) = Rc::get_mut(&mut self.0)
            && let Rep::List(l) = inner.rep.get_mut()
        {
            Rc::make_mut(l).push(x);
            inner.string.take();
            return Ok(());
        }
        self.list_append(std::slice::from_ref(&x))
    }

    /// The integer or double this value is when it has no string form
    /// yet (made by arithmetic: its string would be the canonical one), so
    /// `expr` may use it as a plain number.
    #[inline]
    pub(crate) fn pure_number(&self) -> Option<Num> {
        if self.0.string.get().is_some() {
            return None;
        }
        match &*self.0.rep.borrow() {
            Rep::Int(i) => Some(Num::Int(*i)),
            Rep::Double(d) => Some(Num::Double(*d)),
            _ => None,
        }
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
