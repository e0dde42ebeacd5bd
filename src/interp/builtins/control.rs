//! Control flow and evaluation: if, while, for, foreach, switch, proc,
//! return, catch, error, eval, uplevel, source, exit, time, info, rename.

use std::rc::Rc;
use std::time::Instant;

use super::super::error::{Code, Exception, TclResult};
use super::super::eval::{Interp, Proc};
use super::super::parser;
use super::super::value::Value;
use super::{Entry, check_args, glob_match, pick_option};
use crate::interp::compile;

pub(super) const COMMANDS: &[Entry] = &[
    (
        "if",
        cmd_if,
        "expr1 ?then? body1 elseif expr2 ?then? body2 elseif ... ?else? ?bodyN?",
        "run a body if a condition holds",
    ),
    ("expr", cmd_expr, "arg ?arg ...?", "evaluate an expression"),
    ("while", cmd_while, "test command", "loop while a condition holds"),
    ("for", cmd_for, "start test next command", "C-style loop"),
    ("foreach", cmd_foreach, "varList list ?varList list ...? command", "loop over list elements"),
    (
        "lmap",
        cmd_lmap,
        "varList list ?varList list ...? command",
        "the list of a body's results over list elements",
    ),
    ("apply", cmd_apply, "lambdaExpr ?arg ...?", "call an anonymous procedure"),
    (
        "try",
        cmd_try,
        "body ?on code variableList script ...? ?trap pattern variableList script ...? ?finally script?",
        "run a body, handle its outcome by code or error code, and always a finally script",
    ),
    ("throw", cmd_throw, "type message", "raise an error with an error code"),
    (
        "interp",
        cmd_interp,
        "subcommand ?arg ...?",
        "aliases, the recursion limit, eval: of this interpreter (`{}`) only",
    ),
    (
        "subst",
        cmd_subst,
        "?-nobackslashes? ?-nocommands? ?-novariables? string",
        "a string with its backslashes, commands and variables substituted",
    ),
    ("break", cmd_break, "", "leave the innermost loop"),
    ("continue", cmd_continue, "", "skip to the next loop iteration"),
    (
        "switch",
        cmd_switch,
        "?-option ...? string ?pattern body ...? ?default body?",
        "choose a body by matching a string",
    ),
    ("proc", cmd_proc, "name args body", "define a procedure"),
    ("return", cmd_return, "?-option value ...? ?result?", "return from a procedure or script"),
    (
        "catch",
        cmd_catch,
        "script ?resultVarName? ?optionsVarName?",
        "run a script, trapping errors; returns the code",
    ),
    ("error", cmd_error, "message ?errorInfo? ?errorCode?", "raise an error"),
    ("eval", cmd_eval, "arg ?arg ...?", "concatenate the arguments and run them as a script"),
    ("uplevel", cmd_uplevel, "?level? command ?arg ...?", "run a script in a caller's frame"),
    ("source", cmd_source, "fileName", "run a script file"),
    ("exit", cmd_exit, "?returnCode?", "end the program"),
    ("time", cmd_time, "script ?count?", "time a script: microseconds per iteration"),
    (
        "info",
        cmd_info,
        "subcommand ?arg ...?",
        "exists, commands, procs, complete, args, body, default, level, vars, locals, globals, script",
    ),
    ("rename", cmd_rename, "oldName newName", "rename or delete a command"),
];

/// What a loop does with the outcome of its body.
enum Flow {
    Next,
    Stop,
}

fn loop_body(r: TclResult) -> Result<Flow, Exception> {
    match r {
        Ok(_) => Ok(Flow::Next),
        Err(e) => match e.code {
            Code::Break => Ok(Flow::Stop),
            Code::Continue => Ok(Flow::Next),
            _ => Err(e),
        },
    }
}

/// The shape of an `if` command, checked before any of it runs, as Tcl
/// (which compiles it whole) does: `if 1 {} elwood {}` is an error even
/// though its first branch would be taken.
pub(crate) fn check_if(argv: &[Value]) -> Result<(), Exception> {
    let mut i = 1;
    loop {
        if i >= argv.len() {
            return Err(Exception::error(format!(
                "wrong # args: no expression after \"{}\" argument",
                argv[i - 1].as_str()
            )));
        }
        i += 1;
        if i < argv.len() && argv[i].as_str() == "then" {
            i += 1;
        }
        if i >= argv.len() {
            return Err(Exception::error(format!(
                "wrong # args: no script following \"{}\" argument",
                argv[i - 1].as_str()
            )));
        }
        i += 1;
        match argv.get(i).map(Value::as_str) {
            None => return Ok(()),
            Some("elseif") => i += 1,
            Some(word) => {
                if word == "else" {
                    i += 1;
                    if i >= argv.len() {
                        return Err(Exception::error(
                            "wrong # args: no script following \"else\" argument",
                        ));
                    }
                }
                if i + 1 < argv.len() {
                    return Err(Exception::error(
                        "wrong # args: extra words after \"else\" clause in \"if\" command",
                    ));
                }
                return Ok(());
            }
        }
    }
}

fn cmd_if(interp: &mut Interp, argv: &[Value]) -> TclResult {
    // The shape is checked whole first, so the walk below cannot fail on it.
    check_if(argv)?;
    let mut i = 1;
    loop {
        let cond = interp.eval_cond(&argv[i])?;
        i += 1;
        if argv[i].as_str() == "then" {
            i += 1;
        }
        if cond {
            return interp.eval_inline(&argv[i]);
        }
        i += 1;
        match argv.get(i).map(Value::as_str) {
            None => return Ok(Value::empty()),
            Some("elseif") => i += 1,
            Some("else") => return interp.eval_inline(&argv[i + 1]),
            Some(_) => return interp.eval_inline(&argv[i]),
        }
    }
}

fn cmd_expr(interp: &mut Interp, argv: &[Value]) -> TclResult {
    check_args(argv, 2, usize::MAX, "arg ?arg ...?")?;
    if argv.len() == 2 {
        return interp.eval_expr(&argv[1]);
    }
    interp.eval_expr(&concat(&argv[1..])?)
}

fn cmd_while(interp: &mut Interp, argv: &[Value]) -> TclResult {
    check_args(argv, 3, 3, "test command")?;
    let unit = interp.inline_is_unit(&argv[2]);
    while interp.eval_cond(&argv[1])? {
        let r = interp.eval_inline(&argv[2]);
        if let Flow::Stop = loop_body(named_body(r, unit, "\"while\" body"))? {
            break;
        }
    }
    Ok(Value::empty())
}

/// A loop body's outcome; run as a unit of its own, its error names it.
fn named_body(r: TclResult, unit: bool, what: &str) -> TclResult {
    if unit { r.map_err(|e| with_body_line(e, what)) } else { r }
}

fn cmd_for(interp: &mut Interp, argv: &[Value]) -> TclResult {
    check_args(argv, 5, 5, "start test next command")?;
    let unit = interp.inline_is_unit(&argv[4]);
    interp.eval_inline(&argv[1])?;
    while interp.eval_cond(&argv[2])? {
        let r = interp.eval_inline(&argv[4]);
        if let Flow::Stop = loop_body(named_body(r, unit, "\"for\" body"))? {
            break;
        }
        // `break` in the next clause ends the loop, as in Tcl.
        match interp.eval_inline(&argv[3]) {
            Err(e) if e.code == Code::Break => break,
            r => r?,
        };
    }
    Ok(Value::empty())
}

fn cmd_foreach(interp: &mut Interp, argv: &[Value]) -> TclResult {
    each(interp, argv, None)
}

fn cmd_lmap(interp: &mut Interp, argv: &[Value]) -> TclResult {
    let mut out = Vec::new();
    each(interp, argv, Some(&mut out))?;
    Ok(Value::from_list(out))
}

/// `foreach`, or `lmap` when `collect` takes the body's results (those
/// that end normally: `continue` skips one, `break` ends the loop).
fn each(interp: &mut Interp, argv: &[Value], mut collect: Option<&mut Vec<Value>>) -> TclResult {
    if argv.len() < 4 || !argv.len().is_multiple_of(2) {
        return Err(Exception::wrong_args(&format!(
            "{} varList list ?varList list ...? command",
            argv[0].as_str()
        )));
    }
    let mut groups = Vec::new();
    let mut n_iter = 0;
    for pair in argv[1..argv.len() - 1].chunks(2) {
        let vars = pair[0].as_list()?;
        if vars.is_empty() {
            return Err(Exception::error("foreach varlist is empty"));
        }
        let values = pair[1].as_list()?;
        n_iter = n_iter.max(values.len().div_ceil(vars.len()));
        groups.push((vars, values));
    }
    let body = &argv[argv.len() - 1];
    for i in 0..n_iter {
        for (vars, values) in &groups {
            for (j, var) in vars.iter().enumerate() {
                let v = values.get(i * vars.len() + j).cloned().unwrap_or_else(Value::empty);
                interp.set_var(var.as_str(), v)?;
            }
        }
        let what = if collect.is_some() { "\"lmap\" body" } else { "\"foreach\" body" };
        let r = interp.eval_body(body, what);
        if let (Some(out), Ok(v)) = (collect.as_deref_mut(), &r) {
            out.push(v.clone());
        }
        if let Flow::Stop = loop_body(r)? {
            break;
        }
    }
    Ok(Value::empty())
}

/// `apply {args body ?namespace?} ?arg ...?`: the lambda's parameters are
/// parsed as `proc`'s, and it runs in a frame of its own.
fn cmd_apply(interp: &mut Interp, argv: &[Value]) -> TclResult {
    check_args(argv, 2, usize::MAX, "lambdaExpr ?arg ...?")?;
    let lambda = &argv[1];
    let parts = lambda.as_list()?;
    if !(2..=3).contains(&parts.len()) {
        return Err(Exception::error(format!(
            "can't interpret \"{}\" as a lambda expression",
            lambda.as_str()
        )));
    }
    let (params, variadic) = parse_params(&parts[0]).map_err(|mut e| {
        e.trace = format!(
            "{}\n    (parsing lambda expression \"{}\")",
            e.value.as_str(),
            lambda.as_str()
        );
        e.traced = true;
        e
    })?;
    let p = Proc {
        name: String::new(),
        params,
        variadic,
        body: parts[1].clone(),
        arg_spec: parts[0].clone(),
        lambda: Some(lambda.clone()),
        ns: match parts.get(2) {
            Some(n) => Rc::from(n.as_str().trim_start_matches(':')),
            None => Rc::from(""),
        },
        compiled: Default::default(),
        in_file: false,
    };
    interp.call_lambda(p, argv)
}

fn cmd_subst(interp: &mut Interp, argv: &[Value]) -> TclResult {
    let usage = "?-nobackslashes? ?-nocommands? ?-novariables? string";
    check_args(argv, 2, 5, usage)?;
    let (mut backslashes, mut commands, mut variables) = (true, true, true);
    for o in &argv[1..argv.len() - 1] {
        match pick_option(o.as_str(), &["-nobackslashes", "-nocommands", "-novariables"], "option")?
        {
            "-nobackslashes" => backslashes = false,
            "-nocommands" => commands = false,
            _ => variables = false,
        }
    }
    let text = &argv[argv.len() - 1];
    // A braced string keeps its lines (for `info frame` in its commands).
    let (file, line, cont) = match &*text.rep() {
        crate::interp::value::Rep::Origin(o) => (o.file.clone(), o.line, o.cont.clone()),
        _ => (None, 1, None),
    };
    let mut p = parser::Parser::new(Rc::from(text.as_str()), file, line).with_cont(cont);
    let parts =
        p.subst_parts(backslashes, commands, variables).map_err(|e| Exception::error(e.msg))?;
    interp.subst(&parts)
}

/// Parameters: each name with its default.
type Params = Vec<(Rc<str>, Option<Value>)>;

/// A `proc`'s or lambda's parameter list, and whether the last is `args`.
fn parse_params(spec: &Value) -> Result<(Params, bool), Exception> {
    let spec = spec.as_list()?;
    let mut params = Vec::new();
    for p in spec.iter() {
        let fields = p.as_list()?;
        match fields.len() {
            0 => return Err(Exception::error("argument with no name")),
            1 | 2 => {
                let name = fields[0].as_str();
                if name.contains("::") {
                    return Err(Exception::error(format!(
                        "formal parameter \"{name}\" is not a simple name"
                    )));
                }
                if name.ends_with(')') && name.contains('(') {
                    return Err(Exception::error(format!(
                        "formal parameter \"{name}\" is an array element"
                    )));
                }
                params.push((Rc::from(name), fields.get(1).cloned()));
            }
            _ => {
                return Err(Exception::error(format!(
                    "too many fields in argument specifier \"{}\"",
                    p.as_str()
                )));
            }
        }
    }
    let variadic = params
        .last()
        .is_some_and(|(n, d): &(Rc<str>, Option<Value>)| &**n == "args" && d.is_none());
    Ok((params, variadic))
}

fn cmd_break(_: &mut Interp, argv: &[Value]) -> TclResult {
    check_args(argv, 1, 1, "")?;
    Err(Exception::flow(Code::Break, Value::empty()))
}

fn cmd_continue(_: &mut Interp, argv: &[Value]) -> TclResult {
    check_args(argv, 1, 1, "")?;
    Err(Exception::flow(Code::Continue, Value::empty()))
}

fn cmd_switch(interp: &mut Interp, argv: &[Value]) -> TclResult {
    let usage = "switch ?-option ...? string ?pattern body ...? ?default body?";
    let mut i = 1;
    let mut mode: Option<&str> = None;
    let mut nocase = false;
    let (mut matchvar, mut indexvar) = (None, None);
    while i < argv.len() && argv[i].as_str().starts_with('-') {
        let opt = argv[i].as_str();
        i += 1;
        let name = pick_option(
            opt,
            &["--", "-exact", "-glob", "-indexvar", "-matchvar", "-nocase", "-regexp"],
            "option",
        )
        .map_err(|_| {
            Exception::error(format!(
                "bad option \"{opt}\": must be -exact, -glob, -indexvar, -matchvar, -nocase, -regexp, or --"
            ))
        })?;
        match name {
            "--" => break,
            "-exact" | "-glob" | "-regexp" => {
                if let Some(m) = mode {
                    return Err(Exception::error(format!(
                        "bad option \"{opt}\": {m} option already found"
                    )));
                }
                mode = Some(name);
            }
            "-nocase" => nocase = true,
            "-matchvar" | "-indexvar" => {
                let Some(v) = argv.get(i) else {
                    return Err(Exception::error(format!(
                        "missing variable name argument to {name} option"
                    )));
                };
                if name == "-matchvar" {
                    matchvar = Some(v.clone());
                } else {
                    indexvar = Some(v.clone());
                }
                i += 1;
            }
            _ => unreachable!("listed above"),
        }
    }
    let mode = mode.unwrap_or("-exact");
    if (matchvar.is_some() || indexvar.is_some()) && mode != "-regexp" {
        let which = if indexvar.is_some() { "-indexvar" } else { "-matchvar" };
        return Err(Exception::error(format!("{which} option requires -regexp option")));
    }
    if i >= argv.len() {
        return Err(Exception::wrong_args(usage));
    }
    let subject = argv[i].as_str().to_string();
    i += 1;
    let pairs: Vec<Value> = match argv.len() - i {
        0 => return Err(Exception::wrong_args(usage)),
        1 => argv[i].as_list()?.to_vec(),
        _ => argv[i..].to_vec(),
    };
    if !pairs.len().is_multiple_of(2) {
        return Err(Exception::error("extra switch pattern with no body"));
    }
    let fold = |s: &str| if nocase { s.to_lowercase() } else { s.to_string() };
    for (k, pair) in pairs.chunks(2).enumerate() {
        let pat = pair[0].as_str();
        let is_last = k == pairs.len() / 2 - 1;
        let hit = if is_last && pat == "default" {
            true
        } else {
            match mode {
                "-glob" => glob_match(pat, &subject, nocase),
                "-regexp" => {
                    let flags = super::regexp::Flags { nocase, ..Default::default() };
                    let re = super::regexp::compile(pat, flags)?;
                    match re.captures(&subject).map_err(|e| Exception::error(e.to_string()))? {
                        Some(caps) => {
                            let span = |g: usize| caps.get(g).map(|m| (m.start(), m.end()));
                            if let Some(v) = &matchvar {
                                let words = (0..caps.len())
                                    .map(|g| {
                                        Value::from(span(g).map_or("", |(a, b)| &subject[a..b]))
                                    })
                                    .collect();
                                interp.set_var(v.as_str(), Value::from_list(words))?;
                            }
                            if let Some(v) = &indexvar {
                                let at = |b: usize| subject[..b].chars().count() as i64;
                                let words = (0..caps.len())
                                    .map(|g| match span(g) {
                                        Some((a, b)) => Value::from_list(vec![
                                            Value::from_int(at(a)),
                                            Value::from_int(at(b) - 1),
                                        ]),
                                        None => Value::from("-1 -1"),
                                    })
                                    .collect();
                                interp.set_var(v.as_str(), Value::from_list(words))?;
                            }
                            true
                        }
                        None => false,
                    }
                }
                _ => fold(pat) == fold(&subject),
            }
        };
        if hit {
            // Fall through bodies that are "-".
            for body in pairs[k * 2..].chunks(2).map(|p| &p[1]) {
                if body.as_str() != "-" {
                    let arm = format!("\"{}\" arm", pairs[k * 2].as_str());
                    return interp.eval_arm(body, &arm);
                }
            }
            return Err(Exception::error(format!(
                "no body specified for pattern \"{}\"",
                pairs[pairs.len() - 2].as_str()
            )));
        }
    }
    Ok(Value::empty())
}

fn cmd_proc(interp: &mut Interp, argv: &[Value]) -> TclResult {
    check_args(argv, 4, 4, "name args body")?;
    let (params, variadic) = parse_params(&argv[2])?;
    let name = interp.new_command_key(argv[1].as_str())?;
    // It runs in the namespace its name is in.
    let ns: Rc<str> = Rc::from(name.rsplit_once("::").map_or("", |(n, _)| n));
    let in_file = interp.body_in_file(&argv[3]);
    interp.define_proc(Proc {
        name,
        params,
        variadic,
        body: argv[3].clone(),
        arg_spec: argv[2].clone(),
        lambda: None,
        ns,
        compiled: Default::default(),
        in_file,
    });
    Ok(Value::empty())
}

fn parse_code(v: &Value) -> Result<Option<Code>, Exception> {
    Ok(match v.as_str() {
        "ok" => None,
        "error" => Some(Code::Error),
        "return" => Some(Code::Return),
        "break" => Some(Code::Break),
        "continue" => Some(Code::Continue),
        s => match crate::interp::number::parse_int(s) {
            Some(n) => Code::from_int(n),
            None => {
                return Err(Exception::error(format!(
                    "bad completion code \"{s}\": must be ok, error, return, break, continue, or an integer"
                )));
            }
        },
    })
}

fn cmd_return(_: &mut Interp, argv: &[Value]) -> TclResult {
    let mut code = None;
    let mut level = 1u32;
    let mut error_code = None;
    let mut error_info = None;
    let mut error_stack = None;
    // The options, `-options` dictionaries spread out in place.
    let mut opts: Vec<Value> = Vec::new();
    let mut i = 1;
    while i + 1 < argv.len() {
        if argv[i].as_str() == "-options" {
            let d = argv[i + 1].as_list()?;
            if !d.len().is_multiple_of(2) {
                return Err(Exception::error(format!(
                    "bad -options value: expected dictionary but got \"{}\"",
                    argv[i + 1].as_str()
                )));
            }
            opts.extend(d.iter().cloned());
        } else {
            opts.extend([argv[i].clone(), argv[i + 1].clone()]);
        }
        i += 2;
    }
    for kv in opts.chunks(2) {
        let v = &kv[1];
        match kv[0].as_str() {
            "-code" => code = parse_code(v)?,
            "-level" => {
                let l = v.as_int()?;
                level = u32::try_from(l).map_err(|_| {
                    Exception::error(format!(
                        "bad -level value: expected non-negative integer but got \"{}\"",
                        v.as_str()
                    ))
                })?;
            }
            "-errorcode" => error_code = Some(v.clone()),
            "-errorinfo" => error_info = Some(v.as_str().to_string()),
            "-errorstack" => error_stack = Some(v.as_list()?.to_vec()),
            _ => {}
        }
    }
    let value = if i < argv.len() { argv[i].clone() } else { Value::empty() };
    // The options a catch lists first, in order.
    let mut given = Vec::new();
    for kv in opts.chunks(2) {
        if !matches!(kv[0].as_str(), "-code" | "-level") {
            put_opt(&mut given, kv[0].as_str(), kv[1].clone());
        }
    }
    let with_info = |mut e: Exception| {
        if let Some(info) = &error_info {
            e.trace = info.clone();
            e.traced = true;
            e.logged = true;
        }
        e.ext_mut().errorstack = error_stack.clone();
        e.ext_mut().return_opts = given.clone();
        e
    };
    if level == 0 {
        return match code {
            None => Ok(value),
            Some(Code::Error) => {
                let mut e = Exception::error(value.as_str().to_string());
                e.error_code = error_code;
                Err(with_info(e))
            }
            Some(c) => {
                let mut e = Exception::flow(c, value);
                e.ext_mut().return_opts = given;
                Err(e)
            }
        };
    }
    let mut e = Exception::flow(Code::Return, value);
    e.ext_mut().return_opts = given;
    e.return_code = code;
    e.level = level;
    e.error_code = error_code;
    e.ext_mut().errorstack = error_stack;
    if let Some(info) = error_info {
        e.trace = info;
        e.traced = true;
    }
    Err(e)
}

fn cmd_catch(interp: &mut Interp, argv: &[Value]) -> TclResult {
    check_args(argv, 2, 4, "script ?resultVarName? ?optionVarName?")?;
    // Tcl compiles `catch` inline only without variables, or in a proc
    // with plain local names; otherwise its script is a unit of its own.
    let compiled = argv.len() == 2
        || (interp.in_proc_body() && argv[2..].iter().all(|v| compile::is_local_name(v.as_str())));
    let r = if compiled { interp.eval_inline(&argv[1]) } else { interp.eval(&argv[1]) };
    if let Err(e) = &r
        && let Code::Exit(_) = e.code
    {
        return r;
    }
    let (code, value, opts) = outcome(interp, &r)?;
    if argv.len() > 2 {
        interp.set_var(argv[2].as_str(), value)?;
    }
    if argv.len() > 3 {
        interp.set_var(argv[3].as_str(), opts)?;
    }
    Ok(Value::from_int(code))
}

/// What `catch` and `try` see of a script's outcome: its code, its value
/// and its options dictionary (`-code`, `-level`, and for errors
/// `-errorcode`, `-errorinfo`, `-errorline`); an error also sets
/// `::errorInfo` and `::errorCode`.
fn outcome(interp: &mut Interp, r: &TclResult) -> Result<(i64, Value, Value), Exception> {
    let e = match r {
        Ok(v) => {
            let opts = vec![
                Value::from("-code"),
                Value::from_int(0),
                Value::from("-level"),
                Value::from_int(0),
            ];
            return Ok((0, v.clone(), Value::from_list(opts)));
        }
        Err(e) => e,
    };
    // The options given first, then what every outcome has, as Tcl
    // builds its return options dictionary (TclGetReturnOptions).
    let mut opts = e.return_opts().to_vec();
    if e.code == Code::Return {
        // `return -code c -level n`: the code it will become, and the levels
        // still to go.
        let c = e.return_code.map_or(0, Code::as_int);
        put_opt(&mut opts, "-code", Value::from_int(c));
        put_opt(&mut opts, "-level", Value::from_int(e.level as i64));
        if e.return_code == Some(Code::Error) || e.error_code.is_some() {
            put_opt(&mut opts, "-errorcode", e.error_code());
        }
        return Ok((2, e.value.clone(), Value::from_list(opts)));
    }
    put_opt(&mut opts, "-code", Value::from_int(e.code.as_int()));
    put_opt(&mut opts, "-level", Value::from_int(0));
    if e.code == Code::Error {
        // An error whose errorInfo was given was never logged, so, as in
        // Tcl, the stack of the error before it stands.
        let stack = match e.errorstack() {
            Some(s) => Value::from_list(s.clone()),
            None => interp.errorstack.clone(),
        };
        interp.errorstack = stack.clone();
        put_opt(&mut opts, "-errorstack", stack);
        // As in Tcl, a failing trace on these cannot stop the `catch`.
        let _ = interp.set_var("::errorCode", e.error_code());
        let _ = interp.set_var("::errorInfo", Value::from(e.error_info()));
        put_opt(&mut opts, "-errorcode", e.error_code());
        put_opt(&mut opts, "-errorinfo", Value::from(e.error_info()));
        put_opt(&mut opts, "-errorline", Value::from_int(e.script_line as i64));
    }
    Ok((e.code.as_int(), e.value.clone(), Value::from_list(opts)))
}

/// Sets `key` in an options list (key, value, ...): in place when it is
/// there, at the end otherwise.
fn put_opt(opts: &mut Vec<Value>, key: &str, v: Value) {
    match opts.chunks(2).position(|kv| kv[0].as_str() == key) {
        Some(i) if 2 * i + 1 < opts.len() => opts[2 * i + 1] = v,
        _ => opts.extend([Value::from(key), v]),
    }
}

/// `try body ?on code vars script? ?trap pattern vars script? ... ?finally script?`
fn cmd_try(interp: &mut Interp, argv: &[Value]) -> TclResult {
    if argv.len() < 2 {
        return Err(Exception::wrong_args("try body ?handler ...? ?finally script?"));
    }
    // The handlers: (on code | trap pattern, variables, script).
    enum Match {
        Code(i64),
        Trap(Vec<Value>),
    }
    let mut handlers = Vec::new();
    let mut finally = None;
    let mut i = 2;
    while i < argv.len() {
        match argv[i].as_str() {
            w @ ("on" | "trap") => {
                if i + 3 >= argv.len() {
                    return Err(Exception::error(format!(
                        "wrong # args to {w} clause: must be \"... {w} {} variableList script\"",
                        if w == "on" { "code" } else { "pattern" }
                    )));
                }
                let m = if w == "on" {
                    Match::Code(parse_code(&argv[i + 1])?.map_or(0, Code::as_int))
                } else {
                    Match::Trap(argv[i + 1].as_list()?.to_vec())
                };
                let vars = argv[i + 2].as_list()?;
                if vars.len() > 2 {
                    return Err(Exception::error(
                        "wrong # args to variableList: must be \"?resultVar? ?optionsVar?\"",
                    ));
                }
                handlers.push((m, vars.to_vec(), argv[i + 3].clone()));
                i += 4;
            }
            "finally" if i + 2 == argv.len() => {
                finally = Some(argv[i + 1].clone());
                i += 2;
            }
            "finally" => {
                return Err(Exception::error(
                    "wrong # args to finally clause: must be \"... finally script\"",
                ));
            }
            w => {
                return Err(Exception::error(format!(
                    "bad handler \"{w}\": must be finally, on, or trap"
                )));
            }
        }
    }
    if handlers.last().is_some_and(|h| h.2.as_str() == "-") {
        return Err(Exception::error("last non-finally clause must not have a body of \"-\""));
    }
    // Tcl compiles `try` only where its handlers' variables can be
    // locals (none, or plain names in a proc); otherwise it is invoked and
    // its scripts are units of their own.
    let in_proc = interp.in_proc_body();
    let trap = handlers.iter().any(|(m, _, _)| matches!(m, Match::Trap(_)));
    let compiled = handlers.iter().all(|(_, vars, _)| vars.is_empty())
        || (in_proc
            && handlers
                .iter()
                .all(|(_, vars, _)| vars.iter().all(|v| compile::is_local_name(v.as_str()))));
    let run = |interp: &mut Interp, script: &Value| {
        if compiled { interp.eval_inline(script) } else { interp.eval(script) }
    };
    // A script that errs names itself in errorInfo where Tcl's try does
    // (run as a unit of its own; a handled body outside procs or with a
    // `trap`; a handler outside procs), and the `try` then logs nothing
    // more.
    let name = |e: &mut Exception, yes: bool, what: &str| {
        if yes && e.code == Code::Error {
            let t = format!("\n    ({what} line {})", e.script_line);
            e.trace.push_str(&t);
            e.logged = true;
        }
    };
    let unit = !compiled || interp.inline_is_unit(&argv[1]);
    let mut r = run(interp, &argv[1]);
    if let Err(e) = &r
        && let Code::Exit(_) = e.code
    {
        return r;
    }
    let (code, error_code) = match &r {
        Ok(_) => (0, None),
        Err(e) if e.code == Code::Return => (2, None),
        Err(e) => (e.code.as_int(), (e.code == Code::Error).then(|| e.error_code())),
    };
    let found = handlers.iter().position(|(m, _, _)| match m {
        Match::Code(c) => *c == code,
        Match::Trap(pattern) => error_code.as_ref().is_some_and(|ec| {
            ec.as_list().is_ok_and(|ec| {
                pattern.len() <= ec.len()
                    && pattern.iter().zip(ec.iter()).all(|(a, b)| a.as_str() == b.as_str())
            })
        }),
    });
    if let Err(e) = &mut r {
        name(e, unit || (found.is_some() && (!in_proc || trap)), "\"try\" body");
    }
    let (_, value, opts) = outcome(interp, &r)?;
    let mut result = r;
    // The options of what a finally script interrupts.
    let mut result_opts = opts.clone();
    if let Some(k) = found {
        let (_, vars, _) = &handlers[k];
        // A body of "-" falls through to the next handler's.
        let script = handlers[k..]
            .iter()
            .map(|h| &h.2)
            .find(|s| s.as_str() != "-")
            .cloned()
            .unwrap_or_default();
        if let Some(v) = vars.first() {
            interp.set_var(v.as_str(), value)?;
        }
        if let Some(v) = vars.get(1) {
            interp.set_var(v.as_str(), opts.clone())?;
        }
        let unit = !compiled || !in_proc || interp.inline_is_unit(&script);
        let what = if matches!(handlers[k].0, Match::Code(_)) { "on" } else { "trap" };
        let what = format!("\"try ... {what}\" handler");
        result = run(interp, &script);
        if let Err(mut e) = result {
            name(&mut e, unit, &what);
            let (e, full) = during(interp, e, &opts);
            result_opts = full;
            result = Err(e);
        } else {
            result_opts = outcome(interp, &result)?.2;
        }
    }
    if let Some(f) = finally {
        let unit = !compiled || interp.inline_is_unit(&f);
        if let Err(mut e) = run(interp, &f) {
            name(&mut e, unit, "\"try ... finally\" body");
            return Err(during(interp, e, &result_opts).0);
        }
    }
    result
}

/// An error raised by a `try` handler or finally script carries the
/// options of the outcome it interrupted as `-during`; also the error's
/// options dictionary as Tcl then has it (-during last).
fn during(interp: &mut Interp, mut e: Exception, opts: &Value) -> (Exception, Value) {
    if e.code != Code::Error {
        return (e, Value::empty());
    }
    // Tcl sets the error's whole options dictionary, and -during, as its
    // return options (which keep no -code or -level).
    let Ok((_, _, full)) = outcome(interp, &Err(e.clone())) else { return (e, Value::empty()) };
    let mut full = full.as_list().map(|l| l.to_vec()).unwrap_or_default();
    put_opt(&mut full, "-during", opts.clone());
    let mut given: Vec<Value> = Vec::new();
    for kv in full.chunks(2) {
        if kv.len() == 2 && !matches!(kv[0].as_str(), "-code" | "-level") {
            given.extend([kv[0].clone(), kv[1].clone()]);
        }
    }
    e.ext_mut().return_opts = given;
    (e, Value::from_list(full))
}

/// `interp` for the one interpreter there is (the path `{}`): `alias`,
/// `aliases`, `eval`, `exists`, `recursionlimit`.
fn cmd_interp(interp: &mut Interp, argv: &[Value]) -> TclResult {
    check_args(argv, 2, usize::MAX, "cmd ?arg ...?")?;
    let sub = pick_option(
        argv[1].as_str(),
        &["alias", "aliases", "eval", "exists", "recursionlimit"],
        "option",
    )?;
    let args = &argv[2..];
    let this = |v: &Value| -> Result<(), Exception> {
        let p = v.as_list()?;
        if p.is_empty() {
            Ok(())
        } else {
            Err(Exception::error(format!("could not find interpreter \"{}\"", v.as_str())))
        }
    };
    match sub {
        "exists" => {
            check_args(argv, 2, 3, "exists ?path?")?;
            Ok(Value::from_bool(
                args.first().is_none_or(|p| p.as_list().is_ok_and(|l| l.is_empty())),
            ))
        }
        "recursionlimit" => {
            check_args(argv, 3, 4, "recursionlimit path ?maxRecursion?")?;
            this(&args[0])?;
            if let Some(n) = args.get(1) {
                let n = n.as_int()?;
                if n <= 0 {
                    return Err(Exception::error("recursion limit must be > 0"));
                }
                interp.max_depth = (n as usize).min(super::super::eval::DEFAULT_MAX_DEPTH * 10);
            }
            Ok(Value::from_int(interp.max_depth as i64))
        }
        "eval" => {
            check_args(argv, 4, usize::MAX, "eval path arg ?arg ...?")?;
            this(&args[0])?;
            let script = concat(&args[1..])?;
            let src = script.as_str().to_string();
            interp.eval_global(&src)
        }
        "aliases" => {
            check_args(argv, 2, 3, "aliases ?path?")?;
            if let Some(p) = args.first() {
                this(p)?;
            }
            let names: Vec<Value> =
                interp.aliases.keys().map(|k| Value::from(k.as_str())).collect();
            Ok(Value::from_list(names))
        }
        _ => {
            // alias srcPath srcCmd ?targetPath targetCmd ?arg ...??
            if args.len() < 2 {
                return Err(Exception::wrong_args(
                    "interp alias slavePath slaveCmd ?masterPath masterCmd? ?arg ...?",
                ));
            }
            this(&args[0])?;
            let name = args[1].as_str().trim_start_matches("::").to_string();
            match args.len() {
                2 => {
                    Ok(interp.aliases.get(&name).cloned().map(Value::from_list).unwrap_or_default())
                }
                3 if args[2].as_str().is_empty() => {
                    interp.aliases.remove(&name);
                    let _ = interp.rename_command(&name, "");
                    Ok(Value::empty())
                }
                3 => Err(Exception::wrong_args(
                    "interp alias slavePath slaveCmd ?masterPath masterCmd? ?arg ...?",
                )),
                _ => {
                    this(&args[2])?;
                    let target: Vec<Value> = args[3..].to_vec();
                    interp.aliases.insert(name.clone(), target.clone());
                    interp.register_host(&name, "?arg ...?", "an alias", move |i, argv| {
                        let mut words = target.clone();
                        words.extend_from_slice(&argv[1..]);
                        i.invoke(&words)
                    });
                    Ok(Value::from(name.as_str()))
                }
            }
        }
    }
}

/// `throw type message`: an error with `type` as its error code.
fn cmd_throw(_: &mut Interp, argv: &[Value]) -> TclResult {
    check_args(argv, 3, 3, "type message")?;
    if argv[1].as_list()?.is_empty() {
        return Err(Exception::error("type must be non-empty list"));
    }
    let mut e = Exception::error(argv[2].as_str().to_string());
    e.error_code = Some(argv[1].clone());
    e.ext_mut().return_opts = vec![Value::from("-errorcode"), argv[1].clone()];
    Err(e)
}

fn cmd_error(_: &mut Interp, argv: &[Value]) -> TclResult {
    check_args(argv, 2, 4, "message ?errorInfo? ?errorCode?")?;
    let mut e = Exception::error(argv[1].as_str().to_string());
    if argv.len() > 2 && !argv[2].as_str().is_empty() {
        e.trace = argv[2].as_str().to_string();
        e.traced = true;
        e.logged = true;
    }
    if argv.len() > 2 {
        e.ext_mut().return_opts.extend([Value::from("-errorinfo"), argv[2].clone()]);
    }
    if argv.len() > 3 {
        e.error_code = Some(argv[3].clone());
        e.ext_mut().return_opts.extend([Value::from("-errorcode"), argv[3].clone()]);
    }
    Err(e)
}

/// The frame `uplevel` or `upvar` names with its first word, and whether
/// that word was a level (Tcl's TclObjGetFrame): an integer of at least 0,
/// or `#` and one; another word starting with `#` or a digit is a bad
/// level; any other is no level (one up).
pub(crate) fn frame_arg(interp: &Interp, word: &str) -> Result<(usize, bool), Exception> {
    let int = crate::interp::number::parse_int;
    if int(word).is_some_and(|n| n >= 0) || word.starts_with('#') {
        return Ok((interp.resolve_level(word)?, true));
    }
    if word.starts_with(|c: char| c.is_ascii_digit()) {
        return Err(Exception::error(format!("bad level \"{word}\""))
            .with_error_code(&format!("TCL LOOKUP LEVEL {word}")));
    }
    Ok((interp.resolve_level("1")?, false))
}

/// `concat` semantics: trim each argument and join with spaces.
pub(crate) fn concat(args: &[Value]) -> TclResult {
    if args.len() == 1 {
        return Ok(args[0].clone());
    }
    let ws: &[char] = &[' ', '\t', '\n', '\r', '\x0b', '\x0c'];
    let parts: Vec<&str> =
        args.iter().map(|a| a.as_str().trim_matches(ws)).filter(|s| !s.is_empty()).collect();
    super::super::eval::check_len(parts.iter().map(|p| p.len() + 1).sum())?;
    Ok(Value::from_string(parts.join(" ")))
}

fn cmd_eval(interp: &mut Interp, argv: &[Value]) -> TclResult {
    check_args(argv, 2, usize::MAX, "arg ?arg ...?")?;
    let script = if argv.len() == 2 { argv[1].clone() } else { concat(&argv[1..])? };
    interp.eval(&script).map_err(|e| with_body_line(e, "\"eval\" body"))
}

/// An error leaving a script a command ran adds where it was in it, as
/// `("eval" body line 2)`.
pub(crate) fn with_body_line(mut e: Exception, what: &str) -> Exception {
    if e.code == Code::Error {
        let t = format!("\n    ({what} line {})", e.script_line);
        e.trace.push_str(&t);
    }
    e
}

fn cmd_uplevel(interp: &mut Interp, argv: &[Value]) -> TclResult {
    check_args(argv, 2, usize::MAX, "?level? command ?arg ...?")?;
    let first = argv[1].as_str();
    let (frame, taken) = frame_arg(interp, first)?;
    let rest = &argv[1 + taken as usize..];
    if rest.is_empty() {
        return Err(Exception::wrong_args("uplevel ?level? command ?arg ...?"));
    }
    let script = if rest.len() == 1 { rest[0].clone() } else { concat(rest)? };
    interp
        .in_frame(frame, |i| i.eval_registered(&script))
        .map_err(|e| with_body_line(e, "\"uplevel\" body"))
}

fn cmd_source(interp: &mut Interp, argv: &[Value]) -> TclResult {
    check_args(argv, 2, 2, "fileName")?;
    let path = argv[1].as_str();
    interp.check_access(path, crate::interp::Access::Read)?;
    let src = interp.host.read_file(path).map_err(|e| {
        let why = match e.kind() {
            std::io::ErrorKind::NotFound => "no such file or directory".to_string(),
            std::io::ErrorKind::PermissionDenied => "permission denied".to_string(),
            _ => e.to_string().to_lowercase(),
        };
        Exception::error(format!("couldn't read file \"{path}\": {why}"))
    })?;
    // Read as Tcl reads a script file: any end of line is `\n`.
    let mut bytes = src.into_bytes();
    super::super::stream::translate_eol(&mut bytes, 0, &mut false);
    let src = String::from_utf8(bytes).expect("only ASCII bytes changed");
    interp.source_script(&src, path)
}

fn cmd_exit(interp: &mut Interp, argv: &[Value]) -> TclResult {
    check_args(argv, 1, 2, "?returnCode?")?;
    let code = if argv.len() == 2 { argv[1].as_int()? } else { 0 };
    // Tcl takes a C int here (unsigned values up to 2^32 - 1 too).
    if !(i32::MIN as i64..=u32::MAX as i64).contains(&code) {
        return Err(Exception::error("integer value too large to represent"));
    }
    interp.flush();
    Err(Exception::flow(Code::Exit(code as u32 as i32), Value::empty()))
}

fn cmd_time(interp: &mut Interp, argv: &[Value]) -> TclResult {
    check_args(argv, 2, 3, "script ?count?")?;
    let count = if argv.len() == 3 { argv[2].as_int()? } else { 1 };
    let start = Instant::now();
    for _ in 0..count.max(0) {
        interp.eval(&argv[1])?;
    }
    let per = if count > 0 { start.elapsed().as_secs_f64() * 1e6 / count as f64 } else { 0.0 };
    let shown = if per == per.trunc() {
        format!("{per}")
    } else {
        format!("{per:.6}").trim_end_matches('0').to_string()
    };
    Ok(Value::from_string(format!("{shown} microseconds per iteration")))
}

/// `info commands` and `info procs`: without `::` in the pattern, the
/// current namespace's commands and the global ones, by their simple
/// names; with a qualified pattern, that namespace's, fully qualified.
fn command_list(interp: &Interp, keys: Vec<String>, pattern: Option<&str>) -> Value {
    let ns_of = |k: &str| k.rfind("::").map_or("", |i| &k[..i]).to_string();
    let tail = |k: &str| k.rsplit("::").next().unwrap_or(k).to_string();
    let Some((ns, pat)) = pattern.and_then(|p| p.rsplit_once("::")) else {
        let here = interp.ns.to_string();
        let mut seen = std::collections::HashSet::new();
        let names = keys
            .iter()
            .filter(|k| ns_of(k) == here || !k.contains("::"))
            .map(|k| tail(k))
            .filter(|n| seen.insert(n.clone()))
            .collect();
        return filter(names, pattern.map(Value::from).as_ref());
    };
    let ns = match ns.strip_prefix("::") {
        Some(abs) => abs.to_string(),
        None if interp.ns.is_empty() => ns.to_string(),
        None => format!("{}::{ns}", interp.ns),
    };
    let names = keys
        .iter()
        .filter(|k| ns_of(k) == ns && glob_match(pat, &tail(k), false))
        .map(|k| format!("::{k}"))
        .collect();
    filter(names, None)
}

/// The globals tclsh 8.6 starts with, which size its table.
const TCLSH_GLOBALS: &[&str] = &[
    "tcl_rcFileName",
    "tcl_version",
    "argv0",
    "argv",
    "tcl_interactive",
    "auto_path",
    "auto_index",
    "env",
    "tcl_pkgPath",
    "tcl_patchLevel",
    "argc",
    "tcl_library",
    "tcl_platform",
];

fn filter(names: Vec<String>, pattern: Option<&Value>) -> Value {
    let items = names
        .into_iter()
        .filter(|n| pattern.is_none_or(|p| glob_match(p.as_str(), n, false)))
        .map(Value::from_string)
        .collect();
    Value::from_list(items)
}

pub(crate) const INFO_SUBCOMMANDS: &[&str] = &[
    "args",
    "body",
    "class",
    "cmdcount",
    "commands",
    "complete",
    "coroutine",
    "default",
    "errorstack",
    "exists",
    "frame",
    "functions",
    "globals",
    "hostname",
    "level",
    "library",
    "loaded",
    "locals",
    "nameofexecutable",
    "object",
    "patchlevel",
    "procs",
    "script",
    "sharedlibextension",
    "tclversion",
    "vars",
];

fn cmd_info(interp: &mut Interp, argv: &[Value]) -> TclResult {
    check_args(argv, 2, usize::MAX, "subcommand ?arg ...?")?;
    let sub = super::pick_subcommand(argv[1].as_str(), INFO_SUBCOMMANDS)?;
    let proc_of = |interp: &Interp, name: &Value| {
        interp
            .get_proc(name.as_str())
            .ok_or_else(|| Exception::error(format!("\"{}\" isn't a procedure", name.as_str())))
    };
    let args = &argv[2..];
    let usage = |u: &str| {
        Exception::wrong_args(&format!("info {sub}{}{u}", if u.is_empty() { "" } else { " " }))
    };
    match sub {
        "exists" => {
            if args.len() != 1 {
                return Err(usage("varName"));
            }
            Ok(Value::from_bool(interp.var_exists(args[0].as_str())))
        }
        "commands" | "procs" => {
            if args.len() > 1 {
                return Err(usage("?pattern?"));
            }
            let names =
                if sub == "commands" { interp.command_names() } else { interp.proc_names() };
            Ok(command_list(interp, names, args.first().map(Value::as_str)))
        }
        "complete" => {
            if args.len() != 1 {
                return Err(usage("command"));
            }
            Ok(Value::from_bool(parser::is_complete(args[0].as_str())))
        }
        "args" => {
            if args.len() != 1 {
                return Err(usage("procname"));
            }
            let p = proc_of(interp, &args[0])?;
            Ok(Value::from_list(p.params.iter().map(|(n, _)| Value::from(&**n)).collect()))
        }
        "body" => {
            if args.len() != 1 {
                return Err(usage("procname"));
            }
            Ok(proc_of(interp, &args[0])?.body.clone())
        }
        "default" => {
            if args.len() != 3 {
                return Err(usage("procname arg varname"));
            }
            let p = proc_of(interp, &args[0])?;
            let _ = &p.arg_spec;
            let Some((_, d)) = p.params.iter().find(|(n, _)| &**n == args[1].as_str()) else {
                return Err(Exception::error(format!(
                    "procedure \"{}\" doesn't have an argument \"{}\"",
                    args[0].as_str(),
                    args[1].as_str()
                )));
            };
            match d {
                Some(d) => {
                    interp.set_var(args[2].as_str(), d.clone())?;
                    Ok(Value::from_int(1))
                }
                None => {
                    interp.set_var(args[2].as_str(), Value::empty())?;
                    Ok(Value::from_int(0))
                }
            }
        }
        "level" => match args.len() {
            0 => Ok(Value::from_int(interp.level() as i64)),
            1 => {
                let n = args[0].as_int()?;
                let spec = if n > 0 { format!("#{n}") } else { n.unsigned_abs().to_string() };
                let f = interp
                    .resolve_level(&spec)
                    .map_err(|_| Exception::error(format!("bad level \"{}\"", args[0].as_str())))?;
                Ok(Value::from_list(interp.frames[f].objv.clone()))
            }
            _ => Err(usage("?number?")),
        },
        "vars" | "locals" | "globals" => {
            if args.len() > 1 {
                return Err(usage("?pattern?"));
            }
            let frame = if sub == "globals" { 0 } else { interp.cur };
            if sub == "locals" && interp.level() == 0 {
                return Ok(Value::empty());
            }
            let links = interp.frames[frame].links();
            let defined = interp.frames[frame].defined_names().map(|k| &**k);
            if frame != 0 {
                // A proc's variables in the order they were made.
                let names =
                    defined.filter(|k| sub != "locals" || !links.iter().any(|l| &**l == *k));
                return Ok(filter(names.map(str::to_string).collect(), args.first()));
            }
            // A namespace's table: `info vars ns::*` names them in full.
            let pattern = args.first().map(Value::as_str);
            if let Some((ns, pat)) = pattern.and_then(|p| p.rsplit_once("::")) {
                let ns = ns.trim_start_matches(':');
                let names: Vec<&str> = defined
                    .filter(|k| k.rsplit_once("::").map_or("", |(n, _)| n) == ns)
                    .filter(|k| glob_match(pat, k.rsplit("::").next().unwrap_or(k), false))
                    .collect();
                let ordered = super::tcl_hash_order(
                    names.into_iter().map(|k| (k.rsplit("::").next().unwrap_or(k), k)),
                );
                return Ok(filter(ordered.into_iter().map(|k| format!("::{k}")).collect(), None));
            }
            // The global table in Tcl's hash order, as tclsh fills it: its
            // startup variables first (their number sets the table size).
            let ours: Vec<&str> = defined.filter(|k| !k.contains("::")).collect();
            let startup = TCLSH_GLOBALS.iter().copied().filter(|k| !ours.contains(k));
            let order = super::tcl_hash_order(
                startup.map(|k| (k, None)).chain(ours.iter().map(|k| (*k, Some(*k)))),
            );
            let names = order.into_iter().flatten().map(str::to_string).collect();
            Ok(filter(names, args.first()))
        }
        "script" => Ok(interp.script_file.as_deref().map(Value::from).unwrap_or_else(Value::empty)),
        "functions" => {
            if args.len() > 1 {
                return Err(usage("?pattern?"));
            }
            let names = interp
                .command_names()
                .into_iter()
                .filter_map(|k| k.strip_prefix("tcl::mathfunc::").map(str::to_string))
                .collect();
            Ok(filter(names, args.first()))
        }
        "library" => {
            if !args.is_empty() {
                return Err(usage(""));
            }
            interp
                .get_var("::tcl_library")
                .map_err(|_| Exception::error("no library has been specified for Tcl"))
        }
        "loaded" => {
            if args.len() > 2 {
                return Err(usage("?interp? ?packageName?"));
            }
            Ok(Value::empty())
        }
        "cmdcount" | "sharedlibextension" | "hostname" | "coroutine" => {
            if !args.is_empty() {
                return Err(usage(""));
            }
            Ok(match sub {
                "cmdcount" => Value::from_int(interp.commands_run() as i64),
                "sharedlibextension" => Value::from(std::env::consts::DLL_SUFFIX),
                "hostname" => Value::from(
                    std::fs::read_to_string("/proc/sys/kernel/hostname").unwrap_or_default().trim(),
                ),
                _ => super::coro::info_coroutine(interp),
            })
        }
        "frame" => match args.len() {
            0 => Ok(Value::from_int(interp.frame_count() as i64)),
            1 => interp.frame_info(&args[0]),
            _ => Err(usage("?number?")),
        },
        "errorstack" => match args.len() {
            0 => Ok(interp.errorstack.clone()),
            1 => Err(Exception::error(format!(
                "could not find interpreter \"{}\"",
                args[0].as_str()
            ))),
            _ => Err(usage("?interp?")),
        },
        "class" | "object" => {
            Err(Exception::error(format!("info {sub} is not supported by rayshell")))
        }
        "patchlevel" | "tclversion" | "nameofexecutable" => {
            if !args.is_empty() {
                return Err(usage(""));
            }
            Ok(Value::from(match sub {
                "patchlevel" => super::TCL_PATCHLEVEL,
                "tclversion" => super::TCL_VERSION,
                _ => interp.executable.as_str(),
            }))
        }
        _ => unreachable!("pick_option only returns listed names"),
    }
}

fn cmd_rename(interp: &mut Interp, argv: &[Value]) -> TclResult {
    check_args(argv, 3, 3, "oldName newName")?;
    let (old, new) = (argv[1].as_str(), argv[2].as_str());
    // Names resolve as commands do: qualified, or here then globally.
    let Some(key) = interp.command_key(old) else {
        return Err(Exception::error(format!("can't rename \"{old}\": command doesn't exist")));
    };
    let new_key = if new.is_empty() { String::new() } else { interp.qualify_command(new) };
    if !new_key.is_empty() && interp.has_exact_command(&new_key) {
        return Err(Exception::error(format!("can't rename to \"{new}\": command already exists")));
    }
    interp.rename_command(&key, &new_key)?;
    Ok(Value::empty())
}
