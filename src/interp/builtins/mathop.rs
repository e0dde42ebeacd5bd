//! The `tcl::mathop` commands (`+ - * / % ** == < ... eq in ! ~`), which
//! are `expr`'s operators as commands taking any number of operands, and
//! the `tcl::mathfunc` commands, its functions. Both use `expr`'s own
//! arithmetic, so `[tcl::mathop::+ 1 2]` is `[expr {1 + 2}]` exactly.

use super::check_args;
use crate::interp::error::{Exception, TclResult};
use crate::interp::eval::Interp;
use crate::interp::expr::{self, BinOp, Func, Operand, UnOp};
use crate::interp::value::Value;

/// The operator commands, by name.
const OPS: &[(&str, Op)] = &[
    ("+", Op::Fold(BinOp::Add, 0)),
    ("*", Op::Fold(BinOp::Mul, 1)),
    ("&", Op::Fold(BinOp::BitAnd, -1)),
    ("|", Op::Fold(BinOp::BitOr, 0)),
    ("^", Op::Fold(BinOp::BitXor, 0)),
    ("-", Op::Minus(BinOp::Sub)),
    ("/", Op::Minus(BinOp::Div)),
    ("**", Op::Power),
    ("%", Op::Two(BinOp::Mod, "integer integer")),
    ("<<", Op::Two(BinOp::Shl, "integer shift")),
    (">>", Op::Two(BinOp::Shr, "integer shift")),
    ("!=", Op::Two(BinOp::Ne, "value value")),
    ("ne", Op::Two(BinOp::StrNe, "value value")),
    ("in", Op::Two(BinOp::In, "value list")),
    ("ni", Op::Two(BinOp::Ni, "value list")),
    ("==", Op::Chain(BinOp::Eq)),
    ("eq", Op::Chain(BinOp::StrEq)),
    ("<", Op::Chain(BinOp::Lt)),
    ("<=", Op::Chain(BinOp::Le)),
    (">", Op::Chain(BinOp::Gt)),
    (">=", Op::Chain(BinOp::Ge)),
    ("!", Op::Unary(UnOp::Not, "boolean")),
    ("~", Op::Unary(UnOp::BitNot, "integer")),
];

#[derive(Clone, Copy)]
enum Op {
    /// Left fold from an identity: `+ * & | ^`.
    Fold(BinOp, i64),
    /// One operand is negated or inverted, more fold left: `- /`.
    Minus(BinOp),
    /// Right fold from 1.
    Power,
    /// Exactly two operands, with their usage words.
    Two(BinOp, &'static str),
    /// Every neighbouring pair holds: `== eq < <= > >=`.
    Chain(BinOp),
    Unary(UnOp, &'static str),
}

pub(crate) fn register(interp: &mut Interp) {
    for (name, _) in OPS {
        interp.register_hidden(&format!("tcl::mathop::{name}"), cmd_mathop);
    }
    for name in Func::NAMES {
        interp.register_hidden(&format!("tcl::mathfunc::{name}"), cmd_mathfunc);
    }
    for ns in ["tcl", "tcl::mathop", "tcl::mathfunc"] {
        interp.namespaces.insert(ns.to_string());
    }
    // What they export, as in Tcl (`namespace import ::tcl::mathop::*`).
    interp.exports.insert("tcl::mathop".into(), vec!["*".into()]);
    interp
        .exports
        .insert("tcl::mathfunc".into(), Func::NAMES.iter().map(|n| n.to_string()).collect());
}

/// The last `::` part of the name a command was called by.
fn tail(v: &Value) -> &str {
    let s = v.as_str();
    s.rsplit("::").next().unwrap_or(s)
}

fn operand(v: &Value) -> Operand {
    Operand::from_value(v.clone())
}

/// `+ x` alone still checks that x is a number, as Tcl does.
fn checked(op: BinOp, v: &Value) -> Result<Operand, Exception> {
    expr::binary(op, operand(v), Operand::Int(0)).map(|_| operand(v))
}

fn cmd_mathop(_: &mut Interp, argv: &[Value]) -> TclResult {
    let name = tail(&argv[0]);
    let Some(&(_, op)) = OPS.iter().find(|(n, _)| *n == name) else {
        return Err(Exception::error(format!("invalid command name \"{}\"", argv[0].as_str())));
    };
    let args = &argv[1..];
    let r = match op {
        Op::Fold(b, identity) => {
            let mut acc = Operand::Int(identity);
            if let [only] = args {
                acc = checked(b, only)?;
            } else {
                for (k, a) in args.iter().enumerate() {
                    acc = if k == 0 { operand(a) } else { expr::binary(b, acc, operand(a))? };
                }
            }
            acc
        }
        Op::Minus(b) => {
            check_args(argv, 2, usize::MAX, "value ?value ...?")?;
            if let [only] = args {
                let first = Operand::Int(if b == BinOp::Sub { 0 } else { 1 });
                expr::binary(b, first, operand(only))?
            } else {
                let mut acc = operand(&args[0]);
                for a in &args[1..] {
                    acc = expr::binary(b, acc, operand(a))?;
                }
                acc
            }
        }
        Op::Power => match args.split_last() {
            None => Operand::Int(1),
            Some((last, [])) => checked(BinOp::Pow, last)?,
            Some((last, rest)) => {
                let mut acc = operand(last);
                for a in rest.iter().rev() {
                    acc = expr::binary(BinOp::Pow, operand(a), acc)?;
                }
                acc
            }
        },
        Op::Two(b, usage) => {
            check_args(argv, 3, 3, usage)?;
            expr::binary(b, operand(&args[0]), operand(&args[1]))?
        }
        Op::Chain(b) => {
            for pair in args.windows(2) {
                if !expr::binary(b, operand(&pair[0]), operand(&pair[1]))?.truth()? {
                    return Ok(Value::from_int(0));
                }
            }
            Operand::Int(1)
        }
        Op::Unary(u, usage) => {
            check_args(argv, 2, 2, usage)?;
            expr::unary(u, operand(&args[0]))?
        }
    };
    Ok(r.into_value())
}

fn cmd_mathfunc(interp: &mut Interp, argv: &[Value]) -> TclResult {
    let name = tail(&argv[0]);
    let Some(f) = Func::from_name(name) else {
        return Err(Exception::error(format!("invalid command name \"{}\"", argv[0].as_str())));
    };
    let args = argv[1..].iter().map(operand).collect();
    Ok(expr::call(interp, f, name, args)?.into_value())
}
