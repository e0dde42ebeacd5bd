//! The memory budget's size (`crate::mem` does the counting): `--max-memory`,
//! or by default a share of the machine's memory and of the address-space
//! limit (`ulimit -v`, `prlimit --as`) when one is set.

/// The share of physical memory the budget takes by default.
const RAM_SHARE: f64 = 0.75;
/// Address space that is not heap: the interpreter's stack, thread stacks,
/// the allocators' reserves (small under a limit: `fit_address_space`),
/// the program itself.
const NOT_HEAP: u64 = super::INTERP_STACK_BYTES as u64 + (384 << 20);

/// Parses a size: bytes, or a number with K, M, G or T (powers of 1024,
/// optionally followed by "B" or "iB"), or a percentage of physical memory.
pub fn parse_size(s: &str) -> Result<u64, String> {
    let bad = || format!("expected a size such as 512M, 2G or 50% but got \"{s}\"");
    let t = s.trim();
    if let Some(p) = t.strip_suffix('%') {
        let p: f64 = p.trim().parse().map_err(|_| bad())?;
        if !(p > 0.0 && p <= 100.0) {
            return Err(bad());
        }
        let ram = physical_memory().ok_or("cannot read the machine's memory size")?;
        return Ok((ram as f64 * p / 100.0) as u64);
    }
    let lower = t.to_ascii_lowercase();
    let body = lower.strip_suffix("ib").or_else(|| lower.strip_suffix('b')).unwrap_or(&lower);
    let (num, unit) = match body.char_indices().last() {
        Some((i, c)) if c.is_ascii_alphabetic() => (&body[..i], c),
        _ => (body, ' '),
    };
    let shift = match unit {
        ' ' => 0,
        'k' => 10,
        'm' => 20,
        'g' => 30,
        't' => 40,
        _ => return Err(bad()),
    };
    let x: f64 = num.trim().parse().map_err(|_| bad())?;
    let bytes = x * (1u64 << shift) as f64;
    if !(bytes.is_finite() && bytes >= (1 << 20) as f64) {
        return Err(format!("--max-memory {s}: at least 1M, please"));
    }
    Ok(bytes.min(u64::MAX as f64) as u64)
}

/// The default budget: `RAM_SHARE` of physical memory, and at most half of
/// what an address-space limit leaves for the heap.
pub fn default_budget() -> Option<u64> {
    let ram = physical_memory().map(|b| (b as f64 * RAM_SHARE) as u64);
    let space = address_space_limit().map(|b| b.saturating_sub(NOT_HEAP) / 2);
    match (ram, space) {
        (Some(a), Some(b)) => Some(a.min(b)),
        (a, b) => a.or(b),
    }
}

/// The least heap a run needs: below it, even starting is not worth it.
const MIN_HEAP: u64 = 64 << 20;

/// Under an address-space limit (`ulimit -v`), address space reserved and
/// never used counts as much as memory: mimalloc reserves 1 GiB arenas,
/// and glibc's malloc 64 MiB per thread (for the C code that calls it).
/// Both read their settings from the environment as the process starts,
/// before `main`, so the process runs itself again with small reserves
/// (the same pid, arguments and streams). Returns only when no such step
/// is needed, or it failed.
pub fn fit_address_space() {
    const VAR: &str = "MIMALLOC_ARENA_RESERVE";
    if address_space_limit().is_none() || std::env::var_os(VAR).is_some() {
        return;
    }
    let Ok(exe) = std::env::current_exe() else { return };
    use std::os::unix::process::CommandExt;
    let args: Vec<_> = std::env::args_os().skip(1).collect();
    // On success this never returns; on failure, go on as we are.
    let _ = std::process::Command::new(exe)
        .args(args)
        .env(VAR, "16MiB")
        .env("MALLOC_ARENA_MAX", "1")
        .exec();
}

/// Sets the budget from `--max-memory` or the default; an address-space
/// limit too small to run in at all is an error (a usage error: the same
/// again fails the same way), said before anything is tried.
pub fn apply(max_memory: Option<u64>) -> Result<(), String> {
    if let Some(limit) = address_space_limit() {
        crate::mem::set_address_limited(true);
        let need = NOT_HEAP + 2 * MIN_HEAP;
        if limit < need {
            return Err(format!(
                "an address-space limit (ulimit -v) of {} is too small: raytrace needs at least {}",
                crate::mem::human(limit as usize),
                crate::mem::human(need as usize)
            ));
        }
    }
    // The default never goes below MIN_HEAP; a budget asked for is kept.
    if let Some(b) = max_memory.or_else(|| default_budget().map(|b| b.max(MIN_HEAP))) {
        crate::mem::set_budget(usize::try_from(b).unwrap_or(usize::MAX));
    }
    Ok(())
}

/// MemTotal from /proc/meminfo (Linux), in bytes.
fn physical_memory() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = text.lines().find(|l| l.starts_with("MemTotal:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}

/// The soft RLIMIT_AS from /proc/self/limits, if one is set.
fn address_space_limit() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/self/limits").ok()?;
    let line = text.lines().find(|l| l.starts_with("Max address space"))?;
    line["Max address space".len()..].split_whitespace().next()?.parse().ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes() {
        assert_eq!(parse_size("512M"), Ok(512 << 20));
        assert_eq!(parse_size("2g"), Ok(2 << 30));
        assert_eq!(parse_size("1.5GiB"), Ok(3 << 29));
        assert_eq!(parse_size("64MB"), Ok(64 << 20));
        assert_eq!(parse_size("1073741824"), Ok(1 << 30));
        assert!(parse_size("12").is_err());
        assert!(parse_size("lots").is_err());
        assert!(parse_size("5X").is_err());
        assert!(parse_size("0%").is_err());
        assert!(parse_size("-1G").is_err());
    }
}
