//! `package` (require, provide, present, ifneeded, names, versions,
//! vcompare, vsatisfies, forget, unknown) and the version arithmetic Tcl's
//! `package` does. `Tcl` itself is provided at 8.6.13. A package not yet
//! known is looked for as Tcl's `tclPkgUnknown` does it: each directory of
//! `$auto_path` (and their subdirectories) may hold a `pkgIndex.tcl`, which
//! is sourced with `dir` set and says `package ifneeded`.

use std::cmp::Ordering;

use super::{check_args, pick_option};
use crate::interp::error::{Exception, TclResult};
use crate::interp::eval::Interp;
use crate::interp::value::Value;

pub(super) const COMMANDS: &[super::Entry] = &[
    (
        "package",
        cmd_package,
        "subcommand ?arg ...?",
        "load and describe packages (require, provide, vsatisfies...)",
    ),
    (
        "auto_load",
        cmd_auto_load,
        "cmd ?namespace?",
        "whether a command is defined (rayshell has no auto_index to load from)",
    ),
];

/// `auto_load`: Tcl loads a command named in `auto_index`; rayshell ships
/// no script library, so it answers whether the command exists already.
fn cmd_auto_load(interp: &mut Interp, argv: &[Value]) -> TclResult {
    super::check_args(argv, 2, 3, "cmd ?namespace?")?;
    Ok(Value::from_bool(interp.has_command(argv[1].as_str())))
}

const SUBCOMMANDS: &[&str] = &[
    "forget",
    "ifneeded",
    "names",
    "prefer",
    "present",
    "provide",
    "require",
    "unknown",
    "vcompare",
    "versions",
    "vsatisfies",
];

/// The version Tcl's `package require Tcl` gives.
pub const TCL_PATCHLEVEL: &str = "8.6.13";
pub const TCL_VERSION: &str = "8.6";

/// What the interpreter knows of packages.
#[derive(Default)]
pub struct Packages {
    /// Provided: name → version.
    provided: Vec<(String, String)>,
    /// `package ifneeded`: (name, version, script).
    ifneeded: Vec<(String, String, Value)>,
    /// Whether `$auto_path` has been searched for pkgIndex.tcl files.
    scanned: bool,
}

/// A version's numbers, or why it is not one ("1.2", "8.6b1" → a, b count
/// as -2, -1 before the next number, as Tcl orders them).
fn parse(v: &str) -> Option<Vec<i64>> {
    let mut out = Vec::new();
    let mut num = String::new();
    let mut last_sep = true;
    for c in v.chars() {
        match c {
            '0'..='9' => {
                num.push(c);
                last_sep = false;
            }
            '.' | 'a' | 'b' => {
                if last_sep {
                    return None;
                }
                out.push(num.parse().ok()?);
                num.clear();
                match c {
                    'a' => out.push(-2),
                    'b' => out.push(-1),
                    _ => {}
                }
                last_sep = true;
            }
            _ => return None,
        }
    }
    if last_sep {
        return None;
    }
    out.push(num.parse().ok()?);
    Some(out)
}

fn checked(v: &Value) -> Result<Vec<i64>, Exception> {
    parse(v.as_str()).ok_or_else(|| {
        Exception::error(format!("expected version number but got \"{}\"", v.as_str()))
    })
}

fn compare(a: &[i64], b: &[i64]) -> Ordering {
    let n = a.len().max(b.len());
    for i in 0..n {
        let (x, y) = (a.get(i).copied().unwrap_or(0), b.get(i).copied().unwrap_or(0));
        match x.cmp(&y) {
            Ordering::Equal => {}
            o => return o,
        }
    }
    Ordering::Equal
}

/// Whether version `v` satisfies requirement `req`: "min", "min-", or
/// "min-max" (Tcl 8.5's rules: "min" alone means the same major version).
fn satisfies(v: &[i64], req: &str) -> Result<bool, Exception> {
    let bad = || Exception::error(format!("expected versionMin-versionMax but got \"{req}\""));
    if let Some((lo, hi)) = req.split_once('-') {
        let lo = parse(lo).ok_or_else(bad)?;
        if compare(v, &lo) == Ordering::Less {
            return Ok(false);
        }
        if hi.is_empty() {
            return Ok(true);
        }
        let hi = parse(hi).ok_or_else(bad)?;
        // min-max: max excluded, unless min == max.
        return Ok(compare(v, &hi) == Ordering::Less
            || compare(&lo, &hi) == Ordering::Equal && compare(v, &hi) == Ordering::Equal);
    }
    let min = parse(req)
        .ok_or_else(|| Exception::error(format!("expected version number but got \"{req}\"")))?;
    Ok(v.first() == min.first() && compare(v, &min) != Ordering::Less)
}

fn cmd_package(interp: &mut Interp, argv: &[Value]) -> TclResult {
    check_args(argv, 2, usize::MAX, "option ?arg ...?")?;
    let sub = pick_option(argv[1].as_str(), SUBCOMMANDS, "option")?;
    let args = &argv[2..];
    let usage = |u: &str| Exception::wrong_args(&format!("package {sub} {u}"));
    match sub {
        "provide" => {
            let Some(name) = args.first() else { return Err(usage("package ?version?")) };
            if args.len() > 2 {
                return Err(usage("package ?version?"));
            }
            match args.get(1) {
                None => Ok(provided(interp, name.as_str()).map(Value::from).unwrap_or_default()),
                Some(v) => {
                    checked(v)?;
                    let p = &mut interp.packages;
                    p.provided.retain(|(n, _)| n != name.as_str());
                    p.provided.push((name.as_str().to_string(), v.as_str().to_string()));
                    Ok(Value::empty())
                }
            }
        }
        "present" | "require" => {
            let exact = args.first().is_some_and(|a| a.as_str() == "-exact");
            let args = if exact { &args[1..] } else { args };
            let Some(name) = args.first() else {
                return Err(usage("?-exact? package ?requirement ...?"));
            };
            let name = name.as_str();
            let reqs: Vec<String> = if exact {
                args.get(1).map(|v| format!("{0}-{0}", v.as_str())).into_iter().collect()
            } else {
                args[1..].iter().map(|v| v.as_str().to_string()).collect()
            };
            let ok = |v: &str| -> Result<bool, Exception> {
                let v = parse(v).unwrap_or_default();
                if reqs.is_empty() {
                    return Ok(true);
                }
                for r in &reqs {
                    if satisfies(&v, r)? {
                        return Ok(true);
                    }
                }
                Ok(false)
            };
            let conflict = |have: &str| {
                Exception::error(format!(
                    "version conflict for package \"{name}\": have {have}, need {}",
                    reqs.join(" ")
                ))
            };
            if let Some(have) = provided(interp, name) {
                return if ok(&have)? {
                    Ok(Value::from(have.as_str()))
                } else {
                    Err(conflict(&have))
                };
            }
            if sub == "present" {
                return Err(Exception::error(format!("package {name} is not present")));
            }
            if !interp.packages.scanned {
                interp.packages.scanned = true;
                scan_auto_path(interp)?;
            }
            // The best script that satisfies the requirements.
            let mut best: Option<(Vec<i64>, Value)> = None;
            for (n, v, script) in &interp.packages.ifneeded {
                if n == name && ok(v)? {
                    let pv = parse(v).unwrap_or_default();
                    if best.as_ref().is_none_or(|(b, _)| compare(&pv, b) == Ordering::Greater) {
                        best = Some((pv, script.clone()));
                    }
                }
            }
            let Some((_, script)) = best else {
                return Err(Exception::error(format!(
                    "can't find package {name}{}",
                    if reqs.is_empty() { String::new() } else { format!(" {}", reqs.join(" ")) }
                )));
            };
            interp.eval_global(script.as_str())?;
            match provided(interp, name) {
                Some(have) => Ok(Value::from(have.as_str())),
                None => Err(Exception::error(format!(
                    "attempt to provide package {name} failed: no version of package {name} provided"
                ))),
            }
        }
        "ifneeded" => {
            if !(2..=3).contains(&args.len()) {
                return Err(usage("package version ?script?"));
            }
            checked(&args[1])?;
            let (n, v) = (args[0].as_str(), args[1].as_str());
            let list = &mut interp.packages.ifneeded;
            match args.get(2) {
                None => Ok(list
                    .iter()
                    .find(|(a, b, _)| a == n && b == v)
                    .map(|(_, _, s)| s.clone())
                    .unwrap_or_default()),
                Some(script) => {
                    list.retain(|(a, b, _)| !(a == n && b == v));
                    list.push((n.to_string(), v.to_string(), script.clone()));
                    Ok(Value::empty())
                }
            }
        }
        "names" => {
            let mut names: Vec<String> =
                interp.packages.provided.iter().map(|(n, _)| n.clone()).collect();
            for (n, _, _) in &interp.packages.ifneeded {
                if !names.contains(n) {
                    names.push(n.clone());
                }
            }
            Ok(Value::from_list(names.into_iter().map(Value::from_string).collect()))
        }
        "versions" => {
            let Some(name) = args.first() else { return Err(usage("package")) };
            let vs = interp
                .packages
                .ifneeded
                .iter()
                .filter(|(n, _, _)| n == name.as_str())
                .map(|(_, v, _)| Value::from(v.as_str()))
                .collect();
            Ok(Value::from_list(vs))
        }
        "forget" => {
            for name in args {
                let n = name.as_str();
                interp.packages.provided.retain(|(a, _)| a != n);
                interp.packages.ifneeded.retain(|(a, _, _)| a != n);
            }
            Ok(Value::empty())
        }
        "vcompare" => {
            if args.len() != 2 {
                return Err(usage("version1 version2"));
            }
            let (a, b) = (checked(&args[0])?, checked(&args[1])?);
            Ok(Value::from_int(match compare(&a, &b) {
                Ordering::Less => -1,
                Ordering::Equal => 0,
                Ordering::Greater => 1,
            }))
        }
        "vsatisfies" => {
            if args.len() < 2 {
                return Err(usage("version ?requirement ...?"));
            }
            let v = checked(&args[0])?;
            for r in &args[1..] {
                if satisfies(&v, r.as_str())? {
                    return Ok(Value::from_bool(true));
                }
            }
            Ok(Value::from_bool(false))
        }
        "prefer" => Ok(Value::from("stable")),
        "unknown" => Ok(Value::empty()),
        _ => unreachable!("pick_option only returns listed names"),
    }
}

fn provided(interp: &Interp, name: &str) -> Option<String> {
    if name == "Tcl" {
        return Some(TCL_PATCHLEVEL.to_string());
    }
    interp.packages.provided.iter().find(|(n, _)| n == name).map(|(_, v)| v.clone())
}

/// Sources each `pkgIndex.tcl` in the directories of `$auto_path` and
/// their immediate subdirectories, as tclPkgUnknown does, with `dir` set.
fn scan_auto_path(interp: &mut Interp) -> Result<(), Exception> {
    let script = r#"
        if {[info exists ::auto_path]} {
            foreach __d $::auto_path {
                foreach __i [list [file join $__d pkgIndex.tcl] {*}[glob -nocomplain -- [file join $__d * pkgIndex.tcl]]] {
                    if {[file readable $__i]} {
                        set dir [file dirname $__i]
                        catch {source $__i}
                    }
                }
            }
            unset -nocomplain __d __i dir
        }
    "#;
    // Without `glob` (a host without files), only the directories.
    let fallback = script.replace("{*}[glob -nocomplain -- [file join $__d * pkgIndex.tcl]]", "");
    let have_glob = interp.command_names().iter().any(|n| n == "glob");
    interp.eval_global(if have_glob { script } else { &fallback })?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn versions_order_and_satisfy_as_tcl_says() {
        let v = |s: &str| parse(s).unwrap();
        assert_eq!(compare(&v("8.6.13"), &v("8.6")), Ordering::Greater);
        assert_eq!(compare(&v("8.6"), &v("8.6.0")), Ordering::Equal);
        assert_eq!(compare(&v("8.6a1"), &v("8.6")), Ordering::Less);
        assert_eq!(compare(&v("8.6b1"), &v("8.6a2")), Ordering::Greater);
        assert!(parse("8..6").is_none() && parse("x").is_none() && parse("8.").is_none());
        assert!(satisfies(&v("8.6.13"), "8.5").unwrap());
        assert!(!satisfies(&v("9.0"), "8.5").unwrap());
        assert!(satisfies(&v("9.0"), "8.5-").unwrap());
        assert!(!satisfies(&v("9.0"), "8.5-9.0").unwrap());
        assert!(satisfies(&v("8.6"), "8.6-8.6").unwrap());
    }
}
