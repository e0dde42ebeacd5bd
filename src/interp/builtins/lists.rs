//! List commands: list, llength, lindex, lrange, lappend, linsert, lreplace,
//! lassign, lsort, lsearch, lreverse, lrepeat, lset, concat, join, split.

use std::cmp::Ordering;

use super::super::error::{Exception, TclResult};
use super::super::eval::{Interp, check_len, check_list_len};
use super::super::list::is_bare_element;
use super::super::value::Value;
use super::control::concat;
use super::{Entry, check_args, glob_match, parse_index, pick_option};

pub(super) const COMMANDS: &[Entry] = &[
    ("list", cmd_list, "?arg ...?", "make a list of the arguments"),
    ("llength", cmd_llength, "list", "number of elements"),
    ("lindex", cmd_lindex, "list ?index ...?", "an element (nested indices allowed)"),
    ("lrange", cmd_lrange, "list first last", "a slice of a list"),
    ("lappend", cmd_lappend, "varName ?value ...?", "append elements to a list variable"),
    ("linsert", cmd_linsert, "list index ?element ...?", "insert elements"),
    ("lreplace", cmd_lreplace, "list first last ?element ...?", "replace a range of elements"),
    ("lassign", cmd_lassign, "list ?varName ...?", "assign elements to variables"),
    ("lsort", cmd_lsort, "?-option value ...? list", "sort a list"),
    ("lsearch", cmd_lsearch, "?-option ...? list pattern", "find elements"),
    ("lreverse", cmd_lreverse, "list", "reverse a list"),
    ("lrepeat", cmd_lrepeat, "count ?value ...?", "repeat elements"),
    ("lset", cmd_lset, "listVar ?index? ?index ...? value", "change an element of a list variable"),
    ("concat", cmd_concat, "?arg ...?", "join lists into one"),
    ("join", cmd_join, "list ?joinString?", "join elements into a string"),
    ("split", cmd_split, "string ?splitChars?", "split a string into a list"),
];

fn cmd_list(_: &mut Interp, argv: &[Value]) -> TclResult {
    Ok(Value::from_list(argv[1..].to_vec()))
}

fn cmd_llength(_: &mut Interp, argv: &[Value]) -> TclResult {
    check_args(argv, 2, 2, "list")?;
    Ok(Value::from_int(argv[1].as_list()?.len() as i64))
}

fn index_into(list: &Value, idx: &Value) -> TclResult {
    let items = list.as_list()?;
    let i = parse_index(idx, items.len())?;
    Ok(if i < 0 || i as usize >= items.len() { Value::empty() } else { items[i as usize].clone() })
}

fn cmd_lindex(_: &mut Interp, argv: &[Value]) -> TclResult {
    check_args(argv, 2, usize::MAX, "list ?index ...?")?;
    if argv.len() == 3 && (argv[2].cached_int().is_some() || is_bare_element(argv[2].as_str())) {
        // One index, an integer or a word that is a list of just itself
        // (not read as a list: the integer it parses to stays).
        return index_into(&argv[1], &argv[2]);
    }
    let indices: Vec<Value> = if argv.len() == 3 {
        // A single index argument may itself be a list of indices.
        match argv[2].as_list() {
            Ok(l) if l.len() != 1 => l.to_vec(),
            _ => vec![argv[2].clone()],
        }
    } else {
        argv[2..].to_vec()
    };
    let mut cur = argv[1].clone();
    for idx in &indices {
        cur = index_into(&cur, idx)?;
    }
    Ok(cur)
}

/// Clamps a `first last` pair to a list of `len` elements.
fn range(first: &Value, last: &Value, len: usize) -> Result<Option<(usize, usize)>, Exception> {
    let f = parse_index(first, len)?.max(0);
    let l = parse_index(last, len)?.min(len as i64 - 1);
    Ok(if f > l { None } else { Some((f as usize, l as usize)) })
}

fn cmd_lrange(_: &mut Interp, argv: &[Value]) -> TclResult {
    check_args(argv, 4, 4, "list first last")?;
    let items = argv[1].as_list()?;
    Ok(match range(&argv[2], &argv[3], items.len())? {
        Some((f, l)) => Value::from_list(items[f..=l].to_vec()),
        None => Value::empty(),
    })
}

fn cmd_lappend(interp: &mut Interp, argv: &[Value]) -> TclResult {
    check_args(argv, 2, usize::MAX, "varName ?value ...?")?;
    // Tcl reads the variable (its read traces fire) except where `lappend`
    // compiles to a proc's local-variable instruction.
    if !interp.var_traces.is_empty() && (interp.direct || interp.level() == 0) {
        interp.fire_read_traces_of(argv[1].as_str())?;
    }
    interp
        .update_var(argv[1].as_str(), Some(Value::empty()), &mut |v| append_elements(v, &argv[2..]))
}

/// `lappend`'s change to the variable's value.
pub(crate) fn append_elements(v: &mut Value, extra: &[Value]) -> Result<(), Exception> {
    check_list_len(v.list_len()? + extra.len() + 2)?;
    v.list_append(extra)
}

/// `lappend`'s change for one element, moved in.
pub(crate) fn append_element(v: &mut Value, x: Value) -> Result<(), Exception> {
    check_list_len(v.list_len()? + 3)?;
    v.list_push(x)
}

fn cmd_linsert(_: &mut Interp, argv: &[Value]) -> TclResult {
    check_args(argv, 3, usize::MAX, "list index ?element ...?")?;
    let mut items = argv[1].as_list()?.to_vec();
    let len = items.len();
    let mut at = parse_index(&argv[2], len)?;
    if argv[2].as_str().trim().starts_with("end") {
        at = at.saturating_add(1);
    }
    let at = at.clamp(0, len as i64) as usize;
    check_list_len(len + argv.len())?;
    items.splice(at..at, argv[3..].iter().cloned());
    Ok(Value::from_list(items))
}

fn cmd_lreplace(interp: &mut Interp, argv: &[Value]) -> TclResult {
    check_args(argv, 4, usize::MAX, "list first last ?element ...?")?;
    let len = argv[1].list_len()?;
    let first = parse_index(&argv[2], len)?.clamp(0, len as i64) as usize;
    let last = parse_index(&argv[3], len)?;
    let end = if last < first as i64 { first } else { (last as usize + 1).min(len) };
    check_list_len(len + argv.len())?;
    // An unshared list argument is changed in place, as in Tcl (nothing
    // can fail from here on, and no trace looks at the arguments).
    let mut items = match interp.cmd_traces.is_empty().then(|| argv[1].take_unshared_list()) {
        Some(Some(items)) => items,
        _ => argv[1].as_list()?.to_vec(),
    };
    items.splice(first..end, argv[4..].iter().cloned());
    Ok(Value::from_list(items))
}

fn cmd_lassign(interp: &mut Interp, argv: &[Value]) -> TclResult {
    check_args(argv, 2, usize::MAX, "list ?varName ...?")?;
    let items = argv[1].as_list()?;
    for (i, name) in argv[2..].iter().enumerate() {
        interp.set_var(name.as_str(), items.get(i).cloned().unwrap_or_else(Value::empty))?;
    }
    let rest = items.get(argv.len() - 2..).map(|r| r.to_vec()).unwrap_or_default();
    Ok(Value::from_list(rest))
}

/// Tcl's `-dictionary` order: case-insensitive, digit runs as numbers.
fn dictionary_cmp(a: &str, b: &str) -> Ordering {
    let (a, b): (Vec<char>, Vec<char>) = (a.chars().collect(), b.chars().collect());
    let (mut i, mut j) = (0, 0);
    let mut case_tiebreak = Ordering::Equal;
    while i < a.len() && j < b.len() {
        if a[i].is_ascii_digit() && b[j].is_ascii_digit() {
            let si = i;
            while i < a.len() && a[i].is_ascii_digit() {
                i += 1;
            }
            let sj = j;
            while j < b.len() && b[j].is_ascii_digit() {
                j += 1;
            }
            let na: String = a[si..i].iter().collect::<String>().trim_start_matches('0').into();
            let nb: String = b[sj..j].iter().collect::<String>().trim_start_matches('0').into();
            let o = na.len().cmp(&nb.len()).then_with(|| na.cmp(&nb));
            if o != Ordering::Equal {
                return o;
            }
            continue;
        }
        let (ca, cb) = (a[i], b[j]);
        let (la, lb) =
            (ca.to_lowercase().next().unwrap_or(ca), cb.to_lowercase().next().unwrap_or(cb));
        if la != lb {
            return la.cmp(&lb);
        }
        if case_tiebreak == Ordering::Equal && ca != cb {
            case_tiebreak = if ca.is_uppercase() { Ordering::Less } else { Ordering::Greater };
        }
        i += 1;
        j += 1;
    }
    (a.len() - i).cmp(&(b.len() - j)).then(case_tiebreak)
}

/// Follows a nested `-index` path (`lsort`, `lsearch`) down from `v`;
/// `step` sees each index taken.
fn walk_index(mut v: Value, path: &[Value], mut step: impl FnMut(i64)) -> Result<Value, Exception> {
    for idx in path {
        let l = v.as_list()?;
        let k = parse_index(idx, l.len())?;
        if k < 0 || k as usize >= l.len() {
            return Err(Exception::error(format!(
                "element {} missing from sublist \"{}\"",
                idx.as_str(),
                v.as_str()
            )));
        }
        step(k);
        v = l[k as usize].clone();
    }
    Ok(v)
}

fn cmd_lsort(interp: &mut Interp, argv: &[Value]) -> TclResult {
    check_args(argv, 2, usize::MAX, "?-option value ...? list")?;
    let mut mode = "-ascii";
    let mut decreasing = false;
    let mut unique = false;
    let mut nocase = false;
    let mut index: Vec<Value> = Vec::new();
    let mut command: Option<Value> = None;
    let mut stride: Option<i64> = None;
    let mut indices = false;
    let mut i = 1;
    while i < argv.len() - 1 {
        let opt = pick_option(
            argv[i].as_str(),
            &[
                "-ascii",
                "-command",
                "-decreasing",
                "-dictionary",
                "-increasing",
                "-index",
                "-indices",
                "-integer",
                "-nocase",
                "-real",
                "-stride",
                "-unique",
            ],
            "option",
        )?;
        match opt {
            "-ascii" | "-dictionary" | "-integer" | "-real" => mode = opt,
            "-increasing" => decreasing = false,
            "-decreasing" => decreasing = true,
            "-unique" => unique = true,
            "-nocase" => nocase = true,
            "-indices" => indices = true,
            "-index" | "-command" | "-stride" => {
                i += 1;
                if i >= argv.len() - 1 {
                    return Err(Exception::error(format!(
                        "\"{opt}\" option must be followed by {}",
                        match opt {
                            "-index" => "list index",
                            "-stride" => "stride length",
                            _ => "comparison command",
                        }
                    )));
                }
                match opt {
                    "-index" => {
                        index = argv[i].as_list()?.to_vec();
                        for idx in &index {
                            // A negative literal index can select nothing.
                            parse_index(idx, 0)?;
                            if idx.as_int().is_ok_and(|k| k < 0) {
                                return Err(Exception::error(format!(
                                    "index \"{}\" cannot select an element from any list",
                                    idx.as_str()
                                )));
                            }
                        }
                    }
                    "-stride" => {
                        let n = argv[i].as_int()?;
                        if n < 2 {
                            return Err(Exception::error("stride length must be at least 2"));
                        }
                        stride = Some(n);
                    }
                    _ => command = Some(argv[i].clone()),
                }
            }
            _ => {}
        }
        i += 1;
    }
    let items = argv[argv.len() - 1].as_list()?;
    let group = stride.map_or(1, |n| usize::try_from(n).unwrap_or(usize::MAX));
    if !items.len().is_multiple_of(group) {
        return Err(Exception::error("list size must be a multiple of the stride length"));
    }
    // The key's path: with a stride, the first index picks within a group.
    let mut path: &[Value] = &index;
    let mut lead = 0usize;
    if stride.is_some()
        && let Some((first, rest)) = index.split_first()
    {
        let k = parse_index(first, group)?;
        if k < 0 || k as usize >= group {
            return Err(Exception::error(
                "when used with \"-stride\", the leading \"-index\" value must be within the group",
            ));
        }
        lead = k as usize;
        path = rest;
    }
    // (key, first position of the group)
    let mut keyed: Vec<(Value, usize)> = Vec::with_capacity(items.len() / group);
    for start in (0..items.len()).step_by(group) {
        let key = walk_index(items[start + lead].clone(), path, |_| {})?;
        if mode == "-integer" {
            key.as_int()?;
        } else if mode == "-real" {
            key.as_f64()?;
        }
        keyed.push((key, start));
    }
    let err: std::cell::RefCell<Option<Exception>> = std::cell::RefCell::new(None);
    let mut cmp = |a: &Value, b: &Value| -> Ordering {
        if err.borrow().is_some() {
            return Ordering::Equal;
        }
        let o = match mode {
            "-integer" => a.as_int().unwrap_or(0).cmp(&b.as_int().unwrap_or(0)),
            "-real" => a
                .as_f64()
                .unwrap_or(0.0)
                .partial_cmp(&b.as_f64().unwrap_or(0.0))
                .unwrap_or(Ordering::Equal),
            "-dictionary" => dictionary_cmp(a.as_str(), b.as_str()),
            _ if command.is_some() => {
                let cmd = command.as_ref().expect("checked");
                let mut words = cmd.as_list().map(|l| l.to_vec()).unwrap_or_default();
                words.push(a.clone());
                words.push(b.clone());
                match interp.invoke(&words).and_then(|r| r.as_int()) {
                    Ok(n) => n.cmp(&0),
                    Err(e) => {
                        *err.borrow_mut() = Some(e);
                        Ordering::Equal
                    }
                }
            }
            _ if nocase => a.as_str().to_lowercase().cmp(&b.as_str().to_lowercase()),
            _ => a.as_str().cmp(b.as_str()),
        };
        if decreasing { o.reverse() } else { o }
    };
    // Our own merge sort (Tcl's algorithm): std's sort may panic when a
    // `-command` comparison is not a consistent order; Tcl returns some order.
    merge_sort(&mut keyed, |a, b| cmp(&a.0, &b.0));
    if let Some(e) = err.borrow_mut().take() {
        return Err(e);
    }
    if unique {
        let mut out: Vec<(Value, usize)> = Vec::with_capacity(keyed.len());
        for kv in keyed {
            // Keep the last of a run of equal keys, as Tcl does.
            if let Some(prev) = out.last()
                && cmp(&prev.0, &kv.0) == Ordering::Equal
            {
                out.pop();
            }
            out.push(kv);
        }
        keyed = out;
    }
    let mut out = Vec::with_capacity(keyed.len() * group);
    for (_, start) in keyed {
        for k in start..start + group {
            out.push(if indices { Value::from_int(k as i64) } else { items[k].clone() });
        }
    }
    Ok(Value::from_list(out))
}

fn cmd_lsearch(_: &mut Interp, argv: &[Value]) -> TclResult {
    check_args(argv, 3, usize::MAX, "?-option value ...? list pattern")?;
    let mut mode = "-glob";
    let mut kind = "-ascii";
    let (mut all, mut inline, mut not, mut nocase) = (false, false, false, false);
    let (mut sorted, mut bisect, mut decreasing, mut subindices) = (false, false, false, false);
    let mut start: Option<Value> = None;
    let mut index: Option<Vec<Value>> = None;
    let mut i = 1;
    while i < argv.len() - 2 {
        let opt = pick_option(
            argv[i].as_str(),
            &[
                "-all",
                "-ascii",
                "-bisect",
                "-decreasing",
                "-dictionary",
                "-exact",
                "-glob",
                "-increasing",
                "-index",
                "-inline",
                "-integer",
                "-nocase",
                "-not",
                "-real",
                "-regexp",
                "-sorted",
                "-start",
                "-subindices",
            ],
            "option",
        )?;
        match opt {
            "-all" => all = true,
            "-inline" => inline = true,
            "-not" => not = true,
            "-nocase" => nocase = true,
            "-exact" | "-glob" | "-regexp" => mode = opt,
            "-ascii" | "-dictionary" | "-integer" | "-real" => kind = opt,
            "-sorted" => sorted = true,
            "-bisect" => {
                bisect = true;
                sorted = true;
            }
            "-decreasing" => decreasing = true,
            "-increasing" => decreasing = false,
            "-subindices" => subindices = true,
            "-start" | "-index" => {
                i += 1;
                if i >= argv.len() - 2 {
                    return Err(Exception::error(if opt == "-start" {
                        "missing starting index"
                    } else {
                        "\"-index\" option must be followed by list index"
                    }));
                }
                if opt == "-start" {
                    start = Some(argv[i].clone());
                } else {
                    let idx = argv[i].as_list()?.to_vec();
                    // An index no list has an element at is refused now.
                    const HUGE: usize = 1 << 40;
                    for k in &idx {
                        let n = parse_index(k, HUGE)?;
                        if n < 0 || n >= HUGE as i64 {
                            return Err(Exception::error(format!(
                                "index \"{}\" cannot select an element from any list",
                                k.as_str()
                            )));
                        }
                    }
                    index = Some(idx);
                }
            }
            _ => {}
        }
        i += 1;
    }
    if subindices && index.is_none() {
        return Err(Exception::error("-subindices cannot be used without -index option"));
    }
    if bisect && (all || not) {
        return Err(Exception::error("-bisect is not compatible with -all or -not"));
    }
    // -sorted searches for an exact match (the comparison modes matter
    // only then, and with -exact).
    if sorted && mode == "-glob" {
        mode = "-exact";
    }
    let items = argv[argv.len() - 2].as_list()?;
    let pattern = &argv[argv.len() - 1];
    let first = match &start {
        Some(s) => parse_index(s, items.len())?.max(0) as usize,
        None => 0,
    };
    let re = if mode == "-regexp" {
        let flags = super::regexp::Flags { nocase, ..Default::default() };
        Some(super::regexp::compile(pattern.as_str(), flags)?)
    } else {
        None
    };
    // The part of an element compared (-index), and the path to it.
    let key_path = |it: &Value| -> Result<(Value, Vec<Value>), Exception> {
        match &index {
            None => Ok((it.clone(), Vec::new())),
            Some(idx) => {
                let mut path = Vec::new();
                let cur = walk_index(it.clone(), idx, |n| path.push(Value::from_int(n)))?;
                Ok((cur, path))
            }
        }
    };
    let key = |it: &Value| key_path(it).map(|(v, _)| v);
    let order = |a: &Value| -> Result<Ordering, Exception> {
        let o = match kind {
            "-integer" => a.as_int()?.cmp(&pattern.as_int()?),
            "-real" => a.as_f64()?.partial_cmp(&pattern.as_f64()?).unwrap_or(Ordering::Equal),
            "-dictionary" => dictionary_cmp(a.as_str(), pattern.as_str()),
            _ if nocase => a.as_str().to_lowercase().cmp(&pattern.as_str().to_lowercase()),
            _ => a.as_str().cmp(pattern.as_str()),
        };
        Ok(if decreasing { o.reverse() } else { o })
    };
    if bisect {
        // The last element at or before the pattern in the list's order.
        let mut found = -1i64;
        for (k, it) in items.iter().enumerate().skip(first) {
            if order(&key(it)?)? == Ordering::Greater {
                break;
            }
            found = k as i64;
        }
        return Ok(if inline {
            if found < 0 { Value::empty() } else { items[found as usize].clone() }
        } else {
            Value::from_int(found)
        });
    }
    let mut hits = Vec::new();
    for (k, it) in items.iter().enumerate().skip(first) {
        let (v, path) = key_path(it)?;
        let m = match mode {
            "-exact" => match kind {
                "-integer" | "-real" => order(&v)? == Ordering::Equal,
                _ if nocase => v.as_str().to_lowercase() == pattern.as_str().to_lowercase(),
                _ => v.as_str() == pattern.as_str(),
            },
            "-regexp" => re
                .as_ref()
                .expect("compiled above")
                .is_match(v.as_str())
                .map_err(|e| Exception::error(e.to_string()))?,
            _ => glob_match(pattern.as_str(), v.as_str(), nocase),
        };
        if m != not {
            hits.push(match (inline, subindices) {
                (true, _) => it.clone(),
                (false, true) => {
                    let mut full = vec![Value::from_int(k as i64)];
                    full.extend(path);
                    Value::from_list(full)
                }
                (false, false) => Value::from_int(k as i64),
            });
            if !all {
                break;
            }
        }
    }
    Ok(if all {
        Value::from_list(hits)
    } else {
        hits.pop().unwrap_or_else(|| if inline { Value::empty() } else { Value::from_int(-1) })
    })
}

fn cmd_lreverse(_: &mut Interp, argv: &[Value]) -> TclResult {
    check_args(argv, 2, 2, "list")?;
    let mut items = argv[1].as_list()?.to_vec();
    items.reverse();
    Ok(Value::from_list(items))
}

fn cmd_lrepeat(_: &mut Interp, argv: &[Value]) -> TclResult {
    check_args(argv, 2, usize::MAX, "count ?value ...?")?;
    let n = argv[1].as_int()?;
    // Tcl's count is a C int.
    if n > i32::MAX as i64 {
        return Err(Exception::error("integer value too large to represent"));
    }
    if n < 0 {
        return Err(Exception::error(format!("bad count \"{n}\": must be integer >= 0")));
    }
    if argv.len() == 2 {
        return Ok(Value::from_list(Vec::new()));
    }
    let total = (n as usize).saturating_mul(argv.len() - 2);
    check_list_len(total)?;
    let mut out = Vec::with_capacity(total);
    for _ in 0..n {
        out.extend_from_slice(&argv[2..]);
    }
    Ok(Value::from_list(out))
}

fn set_nested(list: &Value, indices: &[Value], v: Value) -> TclResult {
    let Some((first, rest)) = indices.split_first() else { return Ok(v) };
    let mut items = list.as_list()?.to_vec();
    let i = parse_index(first, items.len())?;
    if i < 0 || i as usize > items.len() || (i as usize == items.len() && !rest.is_empty()) {
        return Err(Exception::error("list index out of range"));
    }
    let i = i as usize;
    if i == items.len() {
        items.push(v);
    } else {
        items[i] = set_nested(&items[i], rest, v)?;
    }
    Ok(Value::from_list(items))
}

/// `set_nested` on the variable's own value, in place where nothing else
/// shares it (so `lset` in a loop is O(1) a call, not a copy of the list).
fn set_nested_in_place(list: &mut Value, indices: &[Value], v: Value) -> Result<(), Exception> {
    let Some((first, rest)) = indices.split_first() else {
        *list = v;
        return Ok(());
    };
    let n = list.list_len()?;
    let i = parse_index(first, n)?;
    if i < 0 || i as usize > n || (i as usize == n && !rest.is_empty()) {
        return Err(Exception::error("list index out of range"));
    }
    let items = list.list_items_mut()?;
    let i = i as usize;
    if i == n {
        items.push(v);
        return Ok(());
    }
    set_nested_in_place(&mut items[i], rest, v)
}

fn cmd_lset(interp: &mut Interp, argv: &[Value]) -> TclResult {
    check_args(argv, 3, usize::MAX, "listVar ?index? ?index ...? value")?;
    let name = argv[1].as_str();
    // Read first, as Tcl does (its errors and read traces).
    let cur = interp.get_var(name)?;
    let value = argv[argv.len() - 1].clone();
    let indices: Vec<Value> = if argv.len() == 4 && argv[2].cached_int().is_some() {
        // One integer index (not read as a list: its integer stays).
        vec![argv[2].clone()]
    } else if argv.len() == 4 {
        argv[2].as_list()?.to_vec()
    } else {
        argv[2..argv.len() - 1].to_vec()
    };
    // Nested indices, which could fail half-way down: on a copy.
    if indices.len() > 1 {
        let new = set_nested(&cur, &indices, value)?;
        return interp.set_var(name, new);
    }
    // One index: checked before anything changes, then in place (the
    // handle read above let go, so an unshared list is not copied).
    drop(cur);
    let mut value = Some(value);
    interp.update_var(name, None, &mut |list| {
        set_nested_in_place(list, &indices, value.take().unwrap_or_default())
    })
}

fn cmd_concat(_: &mut Interp, argv: &[Value]) -> TclResult {
    if argv.len() == 1 {
        return Ok(Value::empty());
    }
    let v = concat(&argv[1..])?;
    Ok(if argv.len() == 2 {
        Value::from(v.as_str().trim_matches(|c: char| c.is_ascii_whitespace()))
    } else {
        v
    })
}

fn cmd_join(_: &mut Interp, argv: &[Value]) -> TclResult {
    check_args(argv, 2, 3, "list ?joinString?")?;
    let sep = if argv.len() == 3 { argv[2].as_str() } else { " " };
    let items = argv[1].as_list()?;
    let parts: Vec<&str> = items.iter().map(|v| v.as_str()).collect();
    let total: usize = parts.iter().map(|p| p.len() + sep.len()).sum();
    check_len(total)?;
    Ok(Value::from_string(parts.join(sep)))
}

fn cmd_split(_: &mut Interp, argv: &[Value]) -> TclResult {
    check_args(argv, 2, 3, "string ?splitChars?")?;
    let s = argv[1].as_str();
    let seps: Vec<char> = if argv.len() == 3 {
        argv[2].as_str().chars().collect()
    } else {
        vec![' ', '\t', '\n', '\r']
    };
    if s.is_empty() {
        return Ok(Value::empty());
    }
    let count = if seps.is_empty() {
        s.chars().count()
    } else {
        s.chars().filter(|c| seps.contains(c)).count() + 1
    };
    check_list_len(count)?;
    crate::mem::reserve_n(count, Value::BYTES)?;
    let items: Vec<Value> = if seps.is_empty() {
        s.chars().map(|c| Value::from_string(c.to_string())).collect()
    } else {
        s.split(|c| seps.contains(&c)).map(Value::from).collect()
    };
    Ok(Value::from_list(items))
}

/// A stable merge sort that only asks `cmp` and never panics, whatever it
/// answers (an inconsistent order gives some order, as in Tcl).
fn merge_sort<T: Clone>(v: &mut [T], mut cmp: impl FnMut(&T, &T) -> Ordering) {
    let n = v.len();
    if n < 2 {
        return;
    }
    let mut buf: Vec<T> = v.to_vec();
    let mut width = 1;
    // Runs of `width` are sorted in `v`; merge pairs of them into `buf`,
    // then copy back.
    while width < n {
        let mut start = 0;
        while start < n {
            let mid = (start + width).min(n);
            let end = (start + 2 * width).min(n);
            let (mut i, mut j, mut k) = (start, mid, start);
            while i < mid && j < end {
                // Take from the right only when strictly smaller: stable.
                if cmp(&v[j], &v[i]) == Ordering::Less {
                    buf[k] = v[j].clone();
                    j += 1;
                } else {
                    buf[k] = v[i].clone();
                    i += 1;
                }
                k += 1;
            }
            while i < mid {
                buf[k] = v[i].clone();
                i += 1;
                k += 1;
            }
            while j < end {
                buf[k] = v[j].clone();
                j += 1;
                k += 1;
            }
            start = end;
        }
        v.clone_from_slice(&buf);
        width *= 2;
    }
}
