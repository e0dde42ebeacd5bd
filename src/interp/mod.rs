//! A Tcl 8.6-compatible interpreter. It knows nothing of graphics: the
//! shell registers the scene commands into it and supplies I/O (`Host`).
//!
//! Reading order: `parser` (script -> commands -> words), `value` (the
//! dual-ported value), `eval` (evaluation, frames, procs; `stream` for whole files), `expr`,
//! `builtins`, then the leaves `number`, `list`, `format`, `error`.

mod builtins;
mod cmdframe;
mod compile;
mod error;
mod eval;
mod expr;
mod format;
mod list;
mod number;
mod parser;
mod stream;
mod value;

pub use builtins::subcommands;
pub use builtins::{making_a_stack, waited_children};
pub use error::{Code, Exception, Loc, TclResult};
pub use eval::{Access, FsPolicy, Host, INTERRUPT_CODE, Interp, MAX_LIST_LEN, MAX_VALUE_LEN};
pub use number::{Num, format_double, parse_double};
pub use parser::is_complete;
pub use value::Value;

/// Checks a command's argument count, producing Tcl's
/// `wrong # args: should be "name usage"`.
pub fn check_args(argv: &[Value], min: usize, max: usize, usage: &str) -> Result<(), Exception> {
    builtins::check_args(argv, min, max, usage)
}
