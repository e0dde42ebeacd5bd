//! Variables: set, unset, append, incr, global, upvar, array.

use super::super::error::{Exception, TclResult};
use super::super::eval::{Interp, Var, check_len};
use super::super::number::{self, Num};
use super::super::value::Value;
use super::{Entry, check_args, glob_match, pick_option};

pub(super) const COMMANDS: &[Entry] = &[
    ("set", cmd_set, "varName ?newValue?", "read or write a variable"),
    ("unset", cmd_unset, "?-nocomplain? ?--? ?varName ...?", "delete variables"),
    ("append", cmd_append, "varName ?value ...?", "append strings to a variable"),
    ("incr", cmd_incr, "varName ?increment?", "add to an integer variable"),
    ("global", cmd_global, "?varName ...?", "use global variables in a procedure"),
    (
        "variable",
        cmd_variable,
        "?name value...? name ?value?",
        "a namespace variable (here the global one), linked into a procedure",
    ),
    (
        "upvar",
        cmd_upvar,
        "?level? otherVar localVar ?otherVar localVar ...?",
        "alias a caller's variable",
    ),
    ("array", cmd_array, "subcommand ?arg ...?", "set, get, names, exists, size, unset"),
];

fn cmd_set(interp: &mut Interp, argv: &[Value]) -> TclResult {
    check_args(argv, 2, 3, "varName ?newValue?")?;
    if argv.len() == 3 {
        interp.set_var(argv[1].as_str(), argv[2].clone())
    } else {
        interp.get_var(argv[1].as_str())
    }
}

fn cmd_unset(interp: &mut Interp, argv: &[Value]) -> TclResult {
    let mut i = 1;
    let mut complain = true;
    while i < argv.len() {
        match argv[i].as_str() {
            "-nocomplain" => complain = false,
            "--" => {
                i += 1;
                break;
            }
            _ => break,
        }
        i += 1;
    }
    for name in &argv[i..] {
        if let Err(e) = interp.unset_var(name.as_str())
            && complain
        {
            return Err(e);
        }
    }
    Ok(Value::empty())
}

fn cmd_append(interp: &mut Interp, argv: &[Value]) -> TclResult {
    check_args(argv, 2, usize::MAX, "varName ?value ...?")?;
    if argv.len() == 2 {
        return interp.get_var(argv[1].as_str());
    }
    interp
        .update_var(argv[1].as_str(), Some(Value::empty()), &mut |v| append_strings(v, &argv[2..]))
}

/// `append`'s change to the variable's value.
pub(crate) fn append_strings(v: &mut Value, extra: &[Value]) -> Result<(), Exception> {
    let n: usize = extra.iter().map(|a| a.as_str().len()).sum();
    check_len(v.as_str().len() + n)?;
    for a in extra {
        v.str_append(a.as_str());
    }
    Ok(())
}

fn cmd_incr(interp: &mut Interp, argv: &[Value]) -> TclResult {
    check_args(argv, 2, 3, "varName ?increment?")?;
    let by = if argv.len() == 3 { argv[2].as_integer()? } else { Num::Int(1) };
    interp.incr_var(argv[1].as_str(), by)
}

impl Interp {
    /// `incr name by`.
    pub(crate) fn incr_var(&mut self, name: &str, by: Num) -> TclResult {
        if !self.var_traces.is_empty() {
            self.fire_read_traces_of(name)?;
        }
        self.update_var(name, Some(Value::from_int(0)), &mut |v| {
            // The 64-bit path first; bignums when it overflows.
            if let (Some(x), Num::Int(y)) = (v.cached_int(), &by)
                && let Some(sum) = x.checked_add(*y)
            {
                *v = Value::from_int(sum);
                return Ok(());
            }
            *v = Value::from_num(number::int_add(&v.as_integer()?, &by));
            Ok(())
        })
    }
}

fn cmd_global(interp: &mut Interp, argv: &[Value]) -> TclResult {
    if interp.level() == 0 {
        return Ok(Value::empty());
    }
    for name in &argv[1..] {
        let n = name.as_str();
        let local = n.rsplit("::").next().unwrap_or(n);
        interp.link_var(0, n, local)?;
    }
    Ok(Value::empty())
}

/// `variable`: with only the global namespace, a global variable, linked
/// into the procedure that declares it, and set when a value is given.
fn cmd_variable(interp: &mut Interp, argv: &[Value]) -> TclResult {
    for pair in argv[1..].chunks(2) {
        let n = pair[0].as_str();
        let local = n.rsplit("::").next().unwrap_or(n);
        // The variable of the current namespace (never a global of the
        // same name, which `set` would find from a namespace).
        let full = match n.strip_prefix("::") {
            Some(_) => n.to_string(),
            None if interp.ns.is_empty() => format!("::{n}"),
            None => format!("::{}::{n}", interp.ns),
        };
        if interp.level() > 0 {
            interp.link_var(0, &full, local)?;
        }
        if let Some(v) = pair.get(1) {
            interp.set_var(if interp.level() > 0 { local } else { &full }, v.clone())?;
        }
    }
    Ok(Value::empty())
}

fn cmd_upvar(interp: &mut Interp, argv: &[Value]) -> TclResult {
    let usage = "?level? otherVar localVar ?otherVar localVar ...?";
    check_args(argv, 3, usize::MAX, usage)?;
    let (frame, taken) = super::control::frame_arg(interp, argv[1].as_str())?;
    let rest = &argv[1 + taken as usize..];
    if !rest.len().is_multiple_of(2) || rest.is_empty() {
        return Err(Exception::wrong_args(&format!("upvar {usage}")));
    }
    for pair in rest.chunks(2) {
        let (other, local) = (pair[0].as_str(), pair[1].as_str());
        if frame == 0 && interp.cur == 0 && !interp.ns.is_empty() {
            // In `namespace eval`: both names are the namespace's.
            let (base, elem) = super::super::eval::split_var_name(other);
            let mut full = format!("::{}", interp.qualify_var(base));
            if let Some(e) = elem {
                full = format!("{full}({e})");
            }
            let local = if local.contains("::") {
                local.trim_start_matches(':').to_string()
            } else {
                format!("{}::{local}", interp.ns)
            };
            interp.link_var(0, &full, &local)?;
            continue;
        }
        interp.link_var(frame, other, local)?;
    }
    Ok(Value::empty())
}

pub(crate) const ARRAY_SUBCOMMANDS: &[&str] = &["exists", "get", "names", "set", "size", "unset"];

fn cmd_array(interp: &mut Interp, argv: &[Value]) -> TclResult {
    check_args(argv, 3, usize::MAX, "subcommand ?arg ...?")?;
    let sub = pick_option(argv[1].as_str(), ARRAY_SUBCOMMANDS, "option")?;
    let name = argv[2].as_str();
    let args = &argv[3..];
    let cell = interp.find_var(name);
    if !interp.var_traces.is_empty()
        && let Some(c) = &cell
        && !matches!(*c.borrow(), Var::Scalar(_))
    {
        interp.traced_access(c, name, None, super::trace::ARRAY)?;
    }
    let is_array = cell.as_ref().is_some_and(|c| matches!(*c.borrow(), Var::Array(_)));
    // Elements in Tcl's hash order, those the pattern takes.
    let matching = |pattern: &dyn Fn(&str) -> bool| -> Vec<(String, Value)> {
        match &cell {
            Some(c) => match &*c.borrow() {
                Var::Array(a) => super::tcl_hash_order(
                    a.iter().map(|(k, v)| (k.as_str(), (k.clone(), v.clone()))),
                )
                .into_iter()
                .filter(|(k, _)| pattern(k))
                .collect(),
                _ => Vec::new(),
            },
            None => Vec::new(),
        }
    };
    let all = |_: &str| true;
    let usage = |u: &str| Exception::wrong_args(&format!("array {sub} arrayName{u}"));
    match sub {
        "exists" => {
            if !args.is_empty() {
                return Err(usage(""));
            }
            Ok(Value::from_bool(is_array))
        }
        "size" => {
            if !args.is_empty() {
                return Err(usage(""));
            }
            Ok(Value::from_int(matching(&all).len() as i64))
        }
        "names" | "get" => {
            // `array names a ?mode? ?pattern?`, mode -exact, -glob or -regexp.
            let (mode, pattern) = match args {
                [] => ("-glob", None),
                [p] => ("-glob", Some(p)),
                [m, p] if sub == "names" => {
                    let m = pick_option(m.as_str(), &["-exact", "-glob", "-regexp"], "mode")?;
                    (m, Some(p))
                }
                _ if sub == "names" => return Err(usage(" ?mode? ?pattern?")),
                _ => return Err(usage(" ?pattern?")),
            };
            let re = match (mode, pattern) {
                ("-regexp", Some(p)) => {
                    Some(super::regexp::compile(p.as_str(), super::regexp::Flags::default())?)
                }
                _ => None,
            };
            let test = |k: &str| match (mode, pattern) {
                (_, None) => true,
                ("-exact", Some(p)) => k == p.as_str(),
                ("-regexp", Some(_)) => re.as_ref().is_some_and(|r| r.is_match(k).unwrap_or(false)),
                (_, Some(p)) => glob_match(p.as_str(), k, false),
            };
            let items = matching(&test);
            let out = if sub == "names" {
                items.into_iter().map(|(k, _)| Value::from_string(k)).collect()
            } else {
                items.into_iter().flat_map(|(k, v)| [Value::from_string(k), v]).collect()
            };
            Ok(Value::from_list(out))
        }
        "set" => {
            if args.len() != 1 {
                return Err(usage(" list"));
            }
            let items = args[0].as_list()?;
            if items.len() % 2 != 0 {
                return Err(Exception::error("list must have an even number of elements"));
            }
            if crate::interp::eval::split_var_name(name).1.is_some() {
                // An element cannot hold an array.
                return Err(Exception::error(format!(
                    "can't set \"{name}\": variable isn't array"
                )));
            }
            let cell = interp.var_cell(name);
            if !interp.var_traces.is_empty() && !matches!(*cell.borrow(), Var::Scalar(_)) {
                // Element by element, so write traces see each.
                if !matches!(*cell.borrow(), Var::Array(_)) {
                    *cell.borrow_mut() = Var::Array(Default::default());
                }
                for kv in items.chunks(2) {
                    interp.set_var(&format!("{name}({})", kv[0].as_str()), kv[1].clone())?;
                }
                return Ok(Value::empty());
            }
            let mut var = cell.borrow_mut();
            if let Var::Scalar(_) = &*var {
                return Err(Exception::error(format!(
                    "can't set \"{name}\": variable isn't array"
                )));
            }
            if !matches!(&*var, Var::Array(_)) {
                *var = Var::Array(Default::default());
            }
            if let Var::Array(a) = &mut *var {
                for kv in items.chunks(2) {
                    a.insert(kv[0].as_str().to_string(), kv[1].clone());
                }
            }
            Ok(Value::empty())
        }
        "unset" => {
            if args.len() > 1 {
                return Err(usage(" ?pattern?"));
            }
            match args.first() {
                None => {
                    if is_array {
                        interp.unset_var(name)?;
                    }
                }
                Some(p) if !interp.var_traces.is_empty() => {
                    let keys: Vec<String> = match cell.as_ref().map(|c| c.borrow()) {
                        Some(v) => match &*v {
                            Var::Array(a) => a
                                .keys()
                                .filter(|k| glob_match(p.as_str(), k, false))
                                .cloned()
                                .collect(),
                            _ => Vec::new(),
                        },
                        None => Vec::new(),
                    };
                    for k in keys {
                        let _ = interp.unset_var(&format!("{name}({k})"));
                    }
                }
                Some(p) => {
                    if let Some(c) = &cell
                        && let Var::Array(a) = &mut *c.borrow_mut()
                    {
                        a.retain(|k, _| !glob_match(p.as_str(), k, false));
                    }
                }
            }
            Ok(Value::empty())
        }
        _ => unreachable!("pick_option only returns listed names"),
    }
}
