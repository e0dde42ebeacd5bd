//! `Exception`: every non-normal outcome of evaluation. Errors, and the
//! control flow of `return`, `break`, `continue` and `exit`, all travel on
//! the `Err` side of `Result<Value, Exception>` (molt's `ResultCode` idea).
//! An error carries Tcl's `errorInfo` trace and the innermost file and line.

use std::rc::Rc;

use super::value::Value;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Code {
    Error,
    Return,
    Break,
    Continue,
    /// `exit N`: not catchable, unwinds to the host.
    Exit(i32),
    /// Any other completion code (`return -code 5`), for scripts' own
    /// control structures.
    Other(i32),
}

impl Code {
    /// The integer `catch` returns for this code.
    pub fn as_int(self) -> i64 {
        match self {
            Code::Error => 1,
            Code::Return => 2,
            Code::Break => 3,
            Code::Continue => 4,
            Code::Exit(_) => 1,
            Code::Other(n) => n as i64,
        }
    }

    /// The code of an integer (`catch`'s numbering).
    pub fn from_int(n: i64) -> Option<Code> {
        Some(match n {
            0 => return None,
            1 => Code::Error,
            2 => Code::Return,
            3 => Code::Break,
            4 => Code::Continue,
            n => Code::Other(i32::try_from(n).unwrap_or(if n < 0 { i32::MIN } else { i32::MAX })),
        })
    }
}

/// A source position: a file (if the script came from one) and a line.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Loc {
    pub file: Option<Rc<str>>,
    pub line: u32,
}

/// An exception: one pointer, so a `Result<Value, Exception>` travels in
/// registers and only a raised exception costs an allocation.
#[derive(Clone, Debug)]
pub struct Exception(Box<ExceptionData>);

impl std::ops::Deref for Exception {
    type Target = ExceptionData;
    #[inline]
    fn deref(&self) -> &ExceptionData {
        &self.0
    }
}

impl std::ops::DerefMut for Exception {
    #[inline]
    fn deref_mut(&mut self) -> &mut ExceptionData {
        &mut self.0
    }
}

#[derive(Clone, Debug)]
pub struct ExceptionData {
    pub code: Code,
    pub value: Value,
    /// For `return -code c -level n`: the code to become when `level` hits 0.
    pub(crate) return_code: Option<Code>,
    pub(crate) level: u32,
    /// Tcl's `errorInfo` text so far.
    pub(crate) trace: String,
    /// True once the command that raised the error is in `trace`.
    pub(crate) traced: bool,
    /// Tcl's ERR_ALREADY_LOGGED: the evaluation unit now running (a
    /// proc body, a script given to `eval`, ...) has put its command in
    /// `trace`, so the commands around it in the same unit add nothing.
    pub(crate) logged: bool,
    /// The line of the unit's innermost failing command (in the text the
    /// unit was parsed from), for the unit's `line N`.
    pub(crate) abs_line: u32,
    pub(crate) error_code: Option<Value>,
    /// The innermost location with a file, for `file:line:` messages.
    pub loc: Option<Loc>,
    /// Line (1-based, within the script that was running) of the command
    /// that failed, for `(procedure "f" line N)`.
    pub(crate) script_line: u32,
    /// What few exceptions have (boxed, so control flow stays small).
    pub(crate) ext: Option<Box<ExceptionExt>>,
}

#[derive(Clone, Debug, Default)]
pub(crate) struct ExceptionExt {
    /// Tcl's `-errorstack` (TIP 348): `INNER` and the failing command,
    /// then a `CALL` with each proc call's words (or `UP n` for an
    /// `uplevel`) as the error leaves it; `None` until it is started.
    pub(crate) errorstack: Option<Vec<Value>>,
    /// The options given to `return`, `error` or `throw` (key, value, ...;
    /// not `-code` or `-level`), in order: `catch` lists them first, as
    /// Tcl's return options dictionary keeps them.
    pub(crate) return_opts: Vec<Value>,
}

impl Exception {
    pub fn error(msg: impl Into<String>) -> Exception {
        let msg: String = msg.into();
        Exception(Box::new(ExceptionData {
            code: Code::Error,
            trace: msg.clone(),
            value: Value::from_string(msg),
            return_code: None,
            level: 0,
            traced: false,
            logged: false,
            abs_line: 0,
            error_code: None,
            loc: None,
            script_line: 0,
            ext: None,
        }))
    }

    pub fn flow(code: Code, value: Value) -> Exception {
        Exception(Box::new(ExceptionData {
            code,
            value,
            return_code: None,
            level: 0,
            trace: String::new(),
            traced: false,
            logged: false,
            abs_line: 0,
            error_code: None,
            loc: None,
            script_line: 0,
            ext: None,
        }))
    }

    /// The exception's parts, to move out of.
    pub(crate) fn into_data(self) -> ExceptionData {
        *self.0
    }

    pub(crate) fn errorstack(&self) -> Option<&Vec<Value>> {
        self.ext.as_ref()?.errorstack.as_ref()
    }

    pub(crate) fn return_opts(&self) -> &[Value] {
        self.ext.as_ref().map_or(&[], |x| &x.return_opts)
    }

    pub(crate) fn ext_mut(&mut self) -> &mut ExceptionExt {
        self.ext.get_or_insert_with(Default::default)
    }

    /// `wrong # args: should be "usage"`.
    pub fn wrong_args(usage: &str) -> Exception {
        Exception::error(format!("wrong # args: should be \"{usage}\""))
            .with_error_code("TCL WRONGARGS")
    }

    pub fn message(&self) -> &str {
        self.value.as_str()
    }

    /// The full `errorInfo` text.
    pub fn error_info(&self) -> &str {
        &self.trace
    }

    /// Sets `errorCode` (a list such as `RAYSHELL IO`).
    pub fn with_error_code(mut self, code: &str) -> Exception {
        self.error_code = Some(Value::from(code));
        self
    }

    pub fn error_code(&self) -> Value {
        self.error_code.clone().unwrap_or_else(|| Value::from("NONE"))
    }

    /// `file:line: message`, or just the message when no file is known.
    pub fn located_message(&self) -> String {
        match &self.loc {
            Some(Loc { file: Some(f), line }) => format!("{f}:{line}: {}", self.message()),
            Some(Loc { file: None, line }) => format!("line {line}: {}", self.message()),
            None => self.message().to_string(),
        }
    }
}

pub type TclResult = Result<Value, Exception>;

impl From<crate::mem::OverBudget> for Exception {
    fn from(e: crate::mem::OverBudget) -> Exception {
        Exception::error(e.to_string()).with_error_code("RAYSHELL MEMORY")
    }
}
