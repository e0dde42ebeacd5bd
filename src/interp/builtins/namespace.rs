//! `namespace`: namespaces for commands and variables. A namespace's
//! commands are table entries under their qualified names (`a::b::cmd`),
//! its variables live in the global frame as `a::b::var`; names resolve in
//! the current namespace first, then the global one (`Interp::resolve_command`,
//! `var_place`). `namespace eval` runs its script at the global level with
//! the namespace current, as procedures defined in a namespace run in it.

use std::rc::Rc;

use super::{check_args, glob_match};
use crate::interp::error::{Exception, TclResult};
use crate::interp::eval::Interp;
use crate::interp::value::Value;

pub(super) const COMMANDS: &[super::Entry] =
    &[("namespace", cmd_namespace, "subcommand ?arg ...?", "namespaces of commands and variables")];

const SUBCOMMANDS: &[&str] = &[
    "children",
    "code",
    "current",
    "delete",
    "ensemble",
    "eval",
    "exists",
    "export",
    "forget",
    "import",
    "inscope",
    "origin",
    "parent",
    "path",
    "qualifiers",
    "tail",
    "unknown",
    "upvar",
    "which",
];

/// `name` as an absolute namespace path without the leading `::` ("" is
/// the global namespace), resolved against the current one.
fn absolute(interp: &Interp, name: &str) -> String {
    let name = name.trim_end_matches(':');
    match name.strip_prefix("::") {
        Some(abs) => abs.trim_start_matches(':').to_string(),
        None if interp.ns.is_empty() => name.to_string(),
        None if name.is_empty() => interp.ns.to_string(),
        None => format!("{}::{name}", interp.ns),
    }
}

fn shown(ns: &str) -> String {
    format!("::{ns}")
}

fn exists(interp: &Interp, ns: &str) -> bool {
    ns.is_empty() || interp.namespaces.contains(ns)
}

/// Makes a namespace and its parents exist.
fn create(interp: &mut Interp, ns: &str) {
    let mut path = String::new();
    for part in ns.split("::").filter(|p| !p.is_empty()) {
        if !path.is_empty() {
            path.push_str("::");
        }
        path.push_str(part);
        interp.namespaces.insert(path.clone());
    }
}

/// Tcl's wording: a relative name is not found in the current namespace.
fn not_found(interp: &Interp, name: &str) -> Exception {
    let msg = if name.starts_with("::") {
        format!("namespace \"{name}\" not found")
    } else {
        format!("namespace \"{name}\" not found in \"::{}\"", interp.ns)
    };
    Exception::error(msg).with_error_code(&format!("TCL LOOKUP NAMESPACE {name}"))
}

/// Runs `f` with namespace `ns` current, in the global frame.
fn within(interp: &mut Interp, ns: &str, f: impl FnOnce(&mut Interp) -> TclResult) -> TclResult {
    let saved = std::mem::replace(&mut interp.frames[0].ns, Rc::from(ns));
    let r = interp.in_frame(0, f);
    interp.frames[0].ns = saved;
    r
}

fn cmd_namespace(interp: &mut Interp, argv: &[Value]) -> TclResult {
    check_args(argv, 2, usize::MAX, "subcommand ?arg ...?")?;
    let sub = super::pick_subcommand(argv[1].as_str(), SUBCOMMANDS)?;

    let a = &argv[2..];
    let usage = |u: &str| Exception::wrong_args(&format!("namespace {sub} {u}"));
    match sub {
        "current" => {
            if !a.is_empty() {
                return Err(Exception::wrong_args("namespace current"));
            }
            Ok(Value::from_string(shown(&interp.ns)))
        }
        "eval" => {
            if a.len() < 2 {
                return Err(usage("name arg ?arg...?"));
            }
            let ns = absolute(interp, a[0].as_str());
            create(interp, &ns);
            let script = if a.len() == 2 { a[1].clone() } else { super::control::concat(&a[1..])? };
            within(interp, &ns, |i| i.eval(&script)).map_err(|mut e| {
                if e.code == crate::interp::error::Code::Error {
                    let t = format!(
                        "\n    (in namespace eval \"{}\" script line {})",
                        shown(&ns),
                        e.script_line
                    );
                    e.trace.push_str(&t);
                }
                e
            })
        }
        "inscope" => {
            if a.len() < 2 {
                return Err(usage("name arg ?arg...?"));
            }
            let ns = absolute(interp, a[0].as_str());
            if !exists(interp, &ns) {
                return Err(not_found(interp, a[0].as_str()));
            }
            // The extra words join the script as `concat` joins them (the
            // script stays a script: `cmd $x ;#` keeps its `;#`).
            let text = if a.len() == 2 {
                a[1].clone()
            } else {
                let rest = Value::from_list(a[2..].to_vec());
                Value::from_string(format!("{} {}", a[1].as_str().trim(), rest.as_str()))
            };
            within(interp, &ns, |i| i.eval(&text))
        }
        "code" => {
            if a.len() != 1 {
                return Err(usage("arg"));
            }
            if a[0].as_str().starts_with("::namespace inscope ") {
                return Ok(a[0].clone());
            }
            Ok(Value::from_list(vec![
                Value::from("::namespace"),
                Value::from("inscope"),
                Value::from_string(shown(&interp.ns)),
                a[0].clone(),
            ]))
        }
        "exists" => {
            if a.len() != 1 {
                return Err(usage("name"));
            }
            let ns = absolute(interp, a[0].as_str());
            Ok(Value::from_bool(exists(interp, &ns)))
        }
        "children" => {
            if a.len() > 2 {
                return Err(usage("?name? ?pattern?"));
            }
            let parent = match a.first() {
                Some(n) => absolute(interp, n.as_str()),
                None => interp.ns.to_string(),
            };
            if !exists(interp, &parent) {
                return Err(not_found(interp, a[0].as_str()));
            }
            let prefix = if parent.is_empty() { String::new() } else { format!("{parent}::") };
            // A pattern is relative to the parent.
            let pattern = a.get(1).map(|p| {
                let p = p.as_str();
                if p.starts_with("::") { p.to_string() } else { format!("::{prefix}{p}") }
            });
            let kids: Vec<Value> = interp
                .namespaces
                .iter()
                .filter(|n| n.strip_prefix(&prefix).is_some_and(|rest| !rest.contains("::")))
                .map(|n| shown(n))
                .filter(|n| pattern.as_ref().is_none_or(|p| glob_match(p, n, false)))
                .map(Value::from_string)
                .collect();
            Ok(Value::from_list(kids))
        }
        "parent" => {
            if a.len() > 1 {
                return Err(usage("?name?"));
            }
            let ns = match a.first() {
                Some(n) => absolute(interp, n.as_str()),
                None => interp.ns.to_string(),
            };
            if !exists(interp, &ns) {
                return Err(not_found(interp, a[0].as_str()));
            }
            if ns.is_empty() {
                return Ok(Value::empty());
            }
            Ok(Value::from_string(shown(ns.rsplit_once("::").map_or("", |(p, _)| p))))
        }
        "qualifiers" | "tail" => {
            if a.len() != 1 {
                return Err(usage("string"));
            }
            let s = a[0].as_str();
            let (q, t) = match s.rfind("::") {
                Some(i) => {
                    let q = s[..i].trim_end_matches(':');
                    (q, &s[i + 2..])
                }
                None => ("", s),
            };
            Ok(Value::from(if sub == "tail" { t.trim_start_matches(':') } else { q }))
        }
        "delete" => {
            for n in a {
                let ns = absolute(interp, n.as_str());
                if !exists(interp, &ns) {
                    return Err(Exception::error(format!(
                        "unknown namespace \"{}\" in namespace delete command",
                        n.as_str()
                    )));
                }
                let prefix = format!("{ns}::");
                interp.namespaces.retain(|x| *x != ns && !x.starts_with(&prefix));
                interp.forget_prefix(&prefix);
            }
            Ok(Value::empty())
        }
        "which" => {
            let (kind, name) = match a {
                [n] => ("-command", n),
                [k, n] if k.as_str() == "-command" || k.as_str() == "-variable" => (k.as_str(), n),
                _ => return Err(usage("?-command? ?-variable? name")),
            };
            if kind == "-variable" {
                let n = name.as_str();
                return Ok(if interp.var_exists(n) {
                    Value::from_string(shown(&interp.qualify_var(n)))
                } else {
                    Value::empty()
                });
            }
            Ok(match interp.command_key(name.as_str()) {
                Some(k) => Value::from_string(shown(&k)),
                None => Value::empty(),
            })
        }
        "origin" => {
            if a.len() != 1 {
                return Err(usage("name"));
            }
            match interp.command_key(a[0].as_str()) {
                Some(k) => Ok(Value::from_string(shown(&k))),
                None => {
                    Err(Exception::error(format!("invalid command name \"{}\"", a[0].as_str())))
                }
            }
        }
        "import" => {
            let force = a.first().is_some_and(|f| f.as_str() == "-force");
            for pattern in &a[force as usize..] {
                let p = pattern.as_str();
                let (from, tail) = match p.rfind("::") {
                    Some(i) => (absolute(interp, &p[..i]), &p[i + 2..]),
                    None => return Ok(Value::empty()),
                };
                if !exists(interp, &from) {
                    return Err(not_found(interp, &p[..p.rfind("::").unwrap_or(0)]));
                }
                let prefix = if from.is_empty() { String::new() } else { format!("{from}::") };
                // Only what the namespace exports.
                let exported = interp.exports.get(&from).cloned().unwrap_or_default();
                for name in interp.command_names() {
                    if let Some(t) = name.strip_prefix(&prefix)
                        && !t.contains("::")
                        && glob_match(tail, t, false)
                        && exported.iter().any(|e| glob_match(e, t, false))
                    {
                        let target = interp.qualify_command(t);
                        if target == name {
                            continue;
                        }
                        if !force
                            && interp.has_exact_command(&target)
                            && !interp.same_command(&name, &target)
                        {
                            return Err(Exception::error(format!(
                                "can't import command \"{t}\": already exists"
                            )));
                        }
                        interp.copy_command(&name, &target);
                    }
                }
            }
            Ok(Value::empty())
        }
        "ensemble" => ensemble(interp, a),
        "upvar" => {
            if a.is_empty() || a.len() % 2 != 1 {
                return Err(usage("ns ?otherVar myVar ...?"));
            }
            let ns = absolute(interp, a[0].as_str());
            if !exists(interp, &ns) {
                return Err(not_found(interp, a[0].as_str()));
            }
            for pair in a[1..].chunks(2) {
                let other = if ns.is_empty() {
                    format!("::{}", pair[0].as_str())
                } else {
                    format!("::{ns}::{}", pair[0].as_str())
                };
                interp.link_var(0, &other, pair[1].as_str())?;
            }
            Ok(Value::empty())
        }
        "export" => {
            let clear = a.first().is_some_and(|f| f.as_str() == "-clear");
            let ns = interp.ns.to_string();
            let list = interp.exports.entry(ns).or_default();
            if clear {
                list.clear();
            }
            if a.is_empty() {
                return Ok(Value::from_list(
                    list.iter().map(|p| Value::from(p.as_str())).collect(),
                ));
            }
            list.extend(a[clear as usize..].iter().map(|p| p.as_str().to_string()));
            Ok(Value::empty())
        }
        // Forgetting imports and search paths are accepted and not used.
        "path" => {
            // `namespace path ?list?`: where commands not found in the
            // current namespace are looked for, before the global one.
            if a.len() > 1 {
                return Err(usage("?pathList?"));
            }
            let here = interp.ns.to_string();
            let Some(list) = a.first() else {
                let path = interp.ns_paths.get(&here).cloned().unwrap_or_default();
                return Ok(Value::from_list(
                    path.iter().map(|p| Value::from_string(shown(p))).collect(),
                ));
            };
            let mut path = Vec::new();
            for item in list.as_list()?.iter() {
                let ns = absolute(interp, item.as_str());
                if !exists(interp, &ns) {
                    return Err(not_found(interp, item.as_str()));
                }
                path.push(ns);
            }
            interp.cmd_epoch += 1;
            interp.inline_epoch += 1;
            if path.is_empty() {
                interp.ns_paths.remove(&here);
            } else {
                interp.ns_paths.insert(here, path);
            }
            Ok(Value::empty())
        }
        "forget" | "unknown" => Ok(Value::empty()),
        _ => unreachable!("every subcommand is handled"),
    }
}

/// `namespace ensemble create ?-command name? ?-map dict? ?-subcommands
/// list?`: a command (by default the namespace's own name) whose first
/// argument names a command of the namespace, or of the map.
fn ensemble(interp: &mut Interp, a: &[Value]) -> TclResult {
    let Some(sub) = a.first() else {
        return Err(Exception::wrong_args("namespace ensemble subcommand ?arg ...?"));
    };
    match sub.as_str() {
        "create" => {}
        "exists" => {
            let n = a.get(1).map(|v| v.as_str()).unwrap_or("");
            return Ok(Value::from_bool(interp.is_ensemble(n)));
        }
        s => {
            return Err(Exception::error(format!(
                "bad subcommand \"{s}\": must be configure, create, or exists"
            )));
        }
    }
    let ns = interp.ns.to_string();
    let mut name = if ns.is_empty() { String::new() } else { ns.clone() };
    let mut map: Vec<(String, Vec<Value>)> = Vec::new();
    let mut only: Option<Vec<String>> = None;
    for pair in a[1..].chunks(2) {
        let v = pair.get(1).ok_or_else(|| Exception::error("missing value"))?;
        match pair[0].as_str() {
            "-command" => name = interp.qualify_command(v.as_str()),
            "-map" => {
                let items = v.as_list()?;
                for kv in items.chunks(2) {
                    if let [k, target] = kv {
                        map.push((k.as_str().to_string(), target.as_list()?.to_vec()));
                    }
                }
            }
            "-subcommands" => {
                only = Some(v.as_list()?.iter().map(|s| s.as_str().to_string()).collect())
            }
            "-parameters" | "-prefixes" | "-unknown" => {}
            o => {
                return Err(Exception::error(format!(
                    "bad option \"{o}\": must be -command, -map, -parameters, -prefixes, -subcommands, or -unknown"
                )));
            }
        }
    }
    let shown_name = shown(&name);
    interp.mark_ensemble(&name);
    interp.register_host(&name, "subcommand ?arg ...?", "an ensemble", move |i, argv| {
        // The subcommands: the map's, or the namespace's commands.
        let mut subs: Vec<String> = match &only {
            Some(o) => o.clone(),
            None if !map.is_empty() => map.iter().map(|(k, _)| k.clone()).collect(),
            None => {
                // The namespace's exported commands.
                let prefix = if ns.is_empty() { String::new() } else { format!("{ns}::") };
                let patterns = i.exports.get(&ns).cloned().unwrap_or_default();
                i.command_names()
                    .into_iter()
                    .filter_map(|c| c.strip_prefix(&prefix).map(str::to_string))
                    .filter(|c| !c.contains("::"))
                    .filter(|c| patterns.iter().any(|p| glob_match(p, c, false)))
                    .collect()
            }
        };
        subs.sort();
        let Some(given) = argv.get(1) else {
            return Err(Exception::wrong_args(&format!(
                "{} subcommand ?arg ...?",
                argv[0].as_str()
            )));
        };
        let g = given.as_str();
        let picked = subs.iter().find(|s| *s == g).or_else(|| {
            let m: Vec<&String> = subs.iter().filter(|s| s.starts_with(g)).collect();
            (m.len() == 1 && !g.is_empty()).then(|| m[0])
        });
        let Some(picked) = picked else {
            if subs.is_empty() {
                return Err(Exception::error(format!(
                    "unknown subcommand \"{g}\": namespace {} does not export any commands",
                    shown(&ns)
                )));
            }
            let n = subs.len();
            let list = match n {
                0 => String::new(),
                1 => subs[0].clone(),
                _ => format!("{}, or {}", subs[..n - 1].join(", "), subs[n - 1]),
            };
            return Err(Exception::error(format!(
                "unknown or ambiguous subcommand \"{g}\": must be {list}"
            )));
        };
        let mut words = match map.iter().find(|(k, _)| k == picked) {
            Some((_, target)) => target.clone(),
            None if ns.is_empty() => vec![Value::from(format!("::{picked}").as_str())],
            None => vec![Value::from(format!("::{ns}::{picked}").as_str())],
        };
        words.extend_from_slice(&argv[2..]);
        i.invoke(&words)
    });
    Ok(Value::from_string(shown_name))
}
