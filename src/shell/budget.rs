//! The memory budget's size (`crate::mem` does the counting): `--max-memory`,
//! or by default a share of the machine's memory and of the address-space
//! limit (`ulimit -v`, `prlimit --as`) when one is set.

/// The share of physical memory the budget takes by default.
const RAM_SHARE: f64 = 0.75;
/// Address space that is not heap: the interpreter's stack, thread stacks,
/// the allocator's per-thread arenas, the program itself.
const NOT_HEAP: u64 = super::INTERP_STACK_BYTES as u64 + (512 << 20);

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

/// Sets the budget from `--max-memory` or the default.
pub fn apply(max_memory: Option<u64>) {
    if let Some(b) = max_memory.or_else(default_budget) {
        crate::mem::set_budget(usize::try_from(b).unwrap_or(usize::MAX));
    }
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
