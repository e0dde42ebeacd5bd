//! `dict`: every Tcl 8.6 subcommand. A dictionary is a list of keys and
//! values; each operation reads it into an insertion-ordered map (a
//! repeated key keeps its first place and its last value, as Tcl's) and
//! writes the canonical list back.

use indexmap::IndexMap;

use super::{check_args, glob_match};
use crate::interp::error::{Code, Exception, TclResult};
use crate::interp::eval::Interp;
use crate::interp::number::{self, Num};
use crate::interp::value::Value;

pub(super) const COMMANDS: &[super::Entry] =
    &[("dict", cmd_dict, "subcommand ?arg ...?", "dictionaries: create, get, set, for, with...")];

const SUBCOMMANDS: &[&str] = &[
    "append", "create", "exists", "filter", "for", "get", "incr", "info", "keys", "lappend", "map",
    "merge", "remove", "replace", "set", "size", "unset", "update", "values", "with",
];

type Dict = IndexMap<String, Value>;

/// A value read as a dictionary.
fn dict_of(v: &Value) -> Result<Dict, Exception> {
    let items = v.as_list().map_err(|e| {
        // The list parser's complaint, in a dictionary's words.
        let msg = e.message().replace("list element", "dict element").replace("in list", "in dict");
        let kind = if msg.contains("quote") && msg.starts_with("unmatched") {
            "QUOTE"
        } else if msg.starts_with("unmatched") {
            "BRACE"
        } else {
            "JUNK"
        };
        Exception::error(msg).with_error_code(&format!("TCL VALUE DICTIONARY {kind}"))
    })?;
    if !items.len().is_multiple_of(2) {
        return Err(Exception::error("missing value to go with key")
            .with_error_code("TCL VALUE DICTIONARY"));
    }
    let mut d = Dict::with_capacity(items.len() / 2);
    for kv in items.chunks(2) {
        d.insert(kv[0].as_str().to_string(), kv[1].clone());
    }
    Ok(d)
}

fn value_of(d: &Dict) -> Value {
    let mut items = Vec::with_capacity(d.len() * 2);
    for (k, v) in d {
        items.push(Value::from(k.as_str()));
        items.push(v.clone());
    }
    Value::from_list(items)
}

fn not_known(key: &str) -> Exception {
    Exception::error(format!("key \"{key}\" not known in dictionary")).with_error_code(&format!(
        "TCL LOOKUP DICT {}",
        Value::from_list(vec![Value::from(key)]).as_str()
    ))
}

/// The value at a path of keys.
fn get_path(v: &Value, keys: &[Value]) -> TclResult {
    let mut cur = v.clone();
    for k in keys {
        let d = dict_of(&cur)?;
        cur = d.get(k.as_str()).cloned().ok_or_else(|| not_known(k.as_str()))?;
    }
    Ok(cur)
}

/// `v` with the value at the path of keys set (missing levels made).
fn set_path(v: &Value, keys: &[Value], new: Value) -> TclResult {
    let mut d = dict_of(v)?;
    let k = keys[0].as_str();
    let inner = if keys.len() == 1 {
        new
    } else {
        let below = d.get(k).cloned().unwrap_or_default();
        set_path(&below, &keys[1..], new)?
    };
    d.insert(k.to_string(), inner);
    Ok(value_of(&d))
}

/// `v` with the last key of the path removed; every key before it must
/// exist.
fn unset_path(v: &Value, keys: &[Value]) -> TclResult {
    let mut d = dict_of(v)?;
    let k = keys[0].as_str();
    if keys.len() == 1 {
        d.shift_remove(k);
    } else {
        let below = d.get(k).cloned().ok_or_else(|| not_known(k))?;
        d.insert(k.to_string(), unset_path(&below, &keys[1..])?);
    }
    Ok(value_of(&d))
}

/// The variable's value, or an empty dictionary when it does not exist.
fn var_or_empty(interp: &mut Interp, name: &str) -> TclResult {
    if interp.var_exists(name) {
        // Read to be written: an array is refused as `set` refuses it.
        interp.get_var(name).map_err(|e| {
            if e.message().ends_with("variable is array") {
                Exception::error(format!("can't set \"{name}\": variable is array"))
            } else {
                e
            }
        })
    } else {
        Ok(Value::empty())
    }
}

fn cmd_dict(interp: &mut Interp, argv: &[Value]) -> TclResult {
    check_args(argv, 2, usize::MAX, "subcommand ?arg ...?")?;
    let sub = super::pick_subcommand(argv[1].as_str(), SUBCOMMANDS)?;

    let a = &argv[2..];
    let usage = |u: &str| Exception::wrong_args(&format!("dict {sub} {u}"));
    match sub {
        "create" => {
            if !a.len().is_multiple_of(2) {
                return Err(usage("?key value ...?"));
            }
            let mut d = Dict::new();
            for kv in a.chunks(2) {
                d.insert(kv[0].as_str().to_string(), kv[1].clone());
            }
            Ok(value_of(&d))
        }
        "get" => {
            if a.is_empty() {
                return Err(usage("dictionary ?key ...?"));
            }
            if a.len() == 1 {
                // Checked, and canonical.
                return Ok(value_of(&dict_of(&a[0])?));
            }
            get_path(&a[0], &a[1..])
        }
        "exists" => {
            if a.len() < 2 {
                return Err(usage("dictionary key ?key ...?"));
            }
            Ok(Value::from_bool(get_path(&a[0], &a[1..]).is_ok()))
        }
        "size" => {
            if a.len() != 1 {
                return Err(usage("dictionary"));
            }
            Ok(Value::from_int(dict_of(&a[0])?.len() as i64))
        }
        "keys" | "values" => {
            if a.is_empty() || a.len() > 2 {
                return Err(usage("dictionary ?pattern?"));
            }
            let d = dict_of(&a[0])?;
            let pat = a.get(1).map(|p| p.as_str());
            let items = d
                .iter()
                .filter(|(k, v)| {
                    let s = if sub == "keys" { k.as_str() } else { v.as_str() };
                    pat.is_none_or(|p| glob_match(p, s, false))
                })
                .map(|(k, v)| if sub == "keys" { Value::from(k.as_str()) } else { v.clone() })
                .collect();
            Ok(Value::from_list(items))
        }
        "info" => {
            if a.len() != 1 {
                return Err(usage("dictionary"));
            }
            let n = dict_of(&a[0])?.len();
            Ok(Value::from_string(format!("{n} entries in table, {} buckets", n.max(4))))
        }
        "merge" => {
            let mut d = Dict::new();
            for v in a {
                for (k, x) in dict_of(v)? {
                    d.insert(k, x);
                }
            }
            Ok(value_of(&d))
        }
        "remove" => {
            if a.is_empty() {
                return Err(usage("dictionary ?key ...?"));
            }
            let mut d = dict_of(&a[0])?;
            for k in &a[1..] {
                d.shift_remove(k.as_str());
            }
            Ok(value_of(&d))
        }
        "replace" => {
            if a.is_empty() || a.len().is_multiple_of(2) {
                return Err(usage("dictionary ?key value ...?"));
            }
            let mut d = dict_of(&a[0])?;
            for kv in a[1..].chunks(2) {
                d.insert(kv[0].as_str().to_string(), kv[1].clone());
            }
            Ok(value_of(&d))
        }
        "set" => {
            if a.len() < 3 {
                return Err(usage("dictVarName key ?key ...? value"));
            }
            let name = a[0].as_str();
            let cur = var_or_empty(interp, name)?;
            let new = set_path(&cur, &a[1..a.len() - 1], a[a.len() - 1].clone())?;
            interp.set_var(name, new)
        }
        "unset" => {
            if a.len() < 2 {
                return Err(usage("dictVarName key ?key ...?"));
            }
            let name = a[0].as_str();
            let cur = var_or_empty(interp, name)?;
            let new = unset_path(&cur, &a[1..])?;
            interp.set_var(name, new)
        }
        "incr" => {
            if !(2..=3).contains(&a.len()) {
                return Err(usage("dictVarName key ?increment?"));
            }
            let name = a[0].as_str();
            let mut d = dict_of(&var_or_empty(interp, name)?)?;
            let by = match a.get(2) {
                Some(v) => v.as_integer()?,
                None => Num::Int(1),
            };
            let k = a[1].as_str();
            let old = match d.get(k) {
                Some(v) => v.as_integer()?,
                None => Num::Int(0),
            };
            d.insert(k.to_string(), Value::from_num(number::int_add(&old, &by)));
            interp.set_var(name, value_of(&d))
        }
        "append" | "lappend" => {
            if a.len() < 2 {
                return Err(usage("dictVarName key ?value ...?"));
            }
            let name = a[0].as_str();
            let mut d = dict_of(&var_or_empty(interp, name)?)?;
            let k = a[1].as_str();
            let old = d.get(k).cloned().unwrap_or_default();
            let new = if sub == "append" {
                let mut s = old.as_str().to_string();
                a[2..].iter().for_each(|v| s.push_str(v.as_str()));
                Value::from_string(s)
            } else {
                let mut items = old.as_list()?.to_vec();
                items.extend(a[2..].iter().cloned());
                Value::from_list(items)
            };
            d.insert(k.to_string(), new);
            interp.set_var(name, value_of(&d))
        }
        "for" | "map" => {
            if a.len() != 3 {
                return Err(usage("{keyVarName valueVarName} dictionary script"));
            }
            let vars = a[0].as_list()?;
            if vars.len() != 2 {
                return Err(Exception::error("must have exactly two variable names"));
            }
            let d = dict_of(&a[1])?;
            let mut out = Dict::new();
            for (k, v) in &d {
                interp.set_var(vars[0].as_str(), Value::from(k.as_str()))?;
                interp.set_var(vars[1].as_str(), v.clone())?;
                match interp.eval_body(&a[2], &format!("\"dict {sub}\" body")) {
                    Ok(r) => {
                        if sub == "map" {
                            out.insert(k.clone(), r);
                        }
                    }
                    Err(e) if e.code == Code::Continue => {}
                    Err(e) if e.code == Code::Break => break,
                    Err(e) => return Err(e),
                }
            }
            Ok(if sub == "map" { value_of(&out) } else { Value::empty() })
        }
        "filter" => filter(interp, a),
        "with" => {
            if a.len() < 2 {
                return Err(usage("dictVarName ?key ...? script"));
            }
            let name = a[0].as_str();
            let path = &a[1..a.len() - 1];
            let whole = interp.get_var(name)?;
            let inner = dict_of(&get_path(&whole, path)?)?;
            for (k, v) in &inner {
                interp.set_var(k, v.clone())?;
            }
            let r = interp.eval(&a[a.len() - 1]);
            // The keys' variables go back in (those still set), even after
            // an error.
            let whole = var_or_empty(interp, name)?;
            let mut back = dict_of(&get_path(&whole, path)?)?;
            for k in inner.keys() {
                if interp.var_exists(k) {
                    back.insert(k.clone(), interp.get_var(k)?);
                } else {
                    back.shift_remove(k);
                }
            }
            let new = if path.is_empty() {
                value_of(&back)
            } else {
                set_path(&whole, path, value_of(&back))?
            };
            interp.set_var(name, new)?;
            r
        }
        "update" => {
            if a.len() < 4 || !a.len().is_multiple_of(2) {
                return Err(usage("dictVarName key varName ?key varName ...? script"));
            }
            let name = a[0].as_str();
            let d = dict_of(&interp.get_var(name)?)?;
            let pairs = &a[1..a.len() - 1];
            for kv in pairs.chunks(2) {
                match d.get(kv[0].as_str()) {
                    Some(v) => {
                        interp.set_var(kv[1].as_str(), v.clone())?;
                    }
                    None => {
                        let _ = interp.unset_var(kv[1].as_str());
                    }
                }
            }
            let r = interp.eval(&a[a.len() - 1]);
            if !interp.var_exists(name) {
                return r;
            }
            let mut d = dict_of(&interp.get_var(name)?)?;
            for kv in pairs.chunks(2) {
                if interp.var_exists(kv[1].as_str()) {
                    d.insert(kv[0].as_str().to_string(), interp.get_var(kv[1].as_str())?);
                } else {
                    d.shift_remove(kv[0].as_str());
                }
            }
            interp.set_var(name, value_of(&d))?;
            r
        }
        _ => unreachable!("every subcommand is handled"),
    }
}

/// `dict filter dictionary key|value ?pattern ...?` or `script {k v} script`.
fn filter(interp: &mut Interp, a: &[Value]) -> TclResult {
    if a.len() < 2 {
        return Err(Exception::wrong_args("dict filter dictionary filterType ?arg ...?"));
    }
    let d = dict_of(&a[0])?;
    let kind = super::pick_option(a[1].as_str(), &["key", "script", "value"], "filterType")?;
    let mut out = Dict::new();
    match kind {
        "key" | "value" => {
            for (k, v) in &d {
                let s = if kind == "key" { k.as_str() } else { v.as_str() };
                if a[2..].iter().any(|p| glob_match(p.as_str(), s, false)) {
                    out.insert(k.clone(), v.clone());
                }
            }
        }
        _ => {
            if a.len() != 4 {
                return Err(Exception::wrong_args(
                    "dict filter dictionary script {keyVarName valueVarName} filterScript",
                ));
            }
            let vars = a[2].as_list()?;
            if vars.len() != 2 {
                return Err(Exception::error("must have exactly two variable names"));
            }
            for (k, v) in &d {
                interp.set_var(vars[0].as_str(), Value::from(k.as_str()))?;
                interp.set_var(vars[1].as_str(), v.clone())?;
                match interp.eval(&a[3]) {
                    Ok(r) => {
                        if r.as_bool()? {
                            out.insert(k.clone(), v.clone());
                        }
                    }
                    Err(e) if e.code == Code::Continue => {}
                    Err(e) if e.code == Code::Break => break,
                    Err(e) => return Err(e),
                }
            }
        }
    }
    Ok(value_of(&out))
}
