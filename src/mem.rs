//! The memory budget: how much heap the process may hold.
//!
//! Every allocation goes through a counting allocator (the `cap` crate over
//! the system allocator), so the bytes in use are one atomic load away.
//! Growth that can be big (strings, lists, file reads, the scene, images, a
//! BVH) asks `reserve` first and is refused with an error when it would take
//! the heap past the budget; loops that grow by many small steps ask `over`
//! now and then, and the interpreter asks `grew_past` after every command
//! (a command that only reads or frees is never refused). Nothing
//! here refuses an allocation itself: running out is always an error with a
//! place, never an abort.
//!
//! The budget starts unlimited; the shell sets it from `--max-memory` or,
//! by default, from the machine's memory and `RLIMIT_AS`. This module is a
//! leaf: every layer may use it, and it uses nothing of the crate.

use std::fmt;
use std::sync::atomic::{AtomicUsize, Ordering};

#[global_allocator]
static HEAP: cap::Cap<mimalloc::MiMalloc> = cap::Cap::new(mimalloc::MiMalloc, usize::MAX);

static BUDGET: AtomicUsize = AtomicUsize::new(usize::MAX);
/// What the allocator's count-down reads when the budget is all in use
/// (`over` is then one comparison).
static FLOOR: AtomicUsize = AtomicUsize::new(0);

/// Heap bytes allocated and not yet freed.
pub fn in_use() -> usize {
    // The allocator counts down from usize::MAX.
    usize::MAX - HEAP.remaining()
}

/// The budget in bytes (`usize::MAX`: none).
pub fn budget() -> usize {
    BUDGET.load(Ordering::Relaxed)
}

pub fn set_budget(bytes: usize) {
    BUDGET.store(bytes, Ordering::Relaxed);
    FLOOR.store(usize::MAX - bytes, Ordering::Relaxed);
}

/// Whether the process runs under an address-space limit (`ulimit -v`),
/// where memory that is only reserved counts as much as memory used.
static ADDRESS_LIMITED: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

pub fn set_address_limited(limited: bool) {
    ADDRESS_LIMITED.store(limited, Ordering::Relaxed);
}

pub fn address_limited() -> bool {
    ADDRESS_LIMITED.load(Ordering::Relaxed)
}

/// Whether the heap is already past the budget.
#[inline]
pub fn over() -> bool {
    HEAP.remaining() < FLOOR.load(Ordering::Relaxed)
}

/// A reading for `grew_past`.
#[derive(Clone, Copy)]
pub struct Mark(usize);

#[inline]
pub fn mark() -> Mark {
    Mark(HEAP.remaining())
}

/// Whether the heap grew since `m` and is now past the budget (work that
/// only reads, or frees, is not stopped by memory already held).
#[inline]
pub fn grew_past(m: Mark) -> bool {
    let now = HEAP.remaining();
    now < m.0 && now < FLOOR.load(Ordering::Relaxed)
}

/// Growth the budget does not allow.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct OverBudget {
    /// Bytes asked for (0: the heap was found past the budget).
    pub wanted: usize,
    pub in_use: usize,
    pub budget: usize,
}

/// Checks that `extra` more bytes fit in the budget.
#[inline]
pub fn reserve(extra: usize) -> Result<(), OverBudget> {
    let (in_use, budget) = (in_use(), budget());
    if extra > budget.saturating_sub(in_use) {
        Err(OverBudget { wanted: extra, in_use, budget })
    } else {
        Ok(())
    }
}

/// `reserve` for `n` items of `size` bytes each.
#[inline]
pub fn reserve_n(n: usize, size: usize) -> Result<(), OverBudget> {
    reserve(n.saturating_mul(size))
}

/// Checks that `v` can take `extra` more items: when that takes a new
/// buffer (twice the old one, as `Vec` grows), the new buffer must fit.
#[inline]
pub fn room<T>(v: &Vec<T>, extra: usize) -> Result<(), OverBudget> {
    let need = v.len().saturating_add(extra);
    if need <= v.capacity() {
        return Ok(());
    }
    reserve_n(need.max(v.capacity() * 2), std::mem::size_of::<T>())
}

/// Errs when the heap is already past the budget.
#[inline]
pub fn check() -> Result<(), OverBudget> {
    if over() { Err(OverBudget { wanted: 0, in_use: in_use(), budget: budget() }) } else { Ok(()) }
}

/// Bytes as people read them: "512 KiB", "1.5 GiB".
pub fn human(bytes: usize) -> String {
    const UNITS: [&str; 5] = ["bytes", "KiB", "MiB", "GiB", "TiB"];
    let mut x = bytes as f64;
    let mut u = 0;
    while x >= 1024.0 && u + 1 < UNITS.len() {
        x /= 1024.0;
        u += 1;
    }
    if u == 0 {
        format!("{bytes} bytes")
    } else if x.fract() == 0.0 {
        format!("{x} {}", UNITS[u])
    } else {
        format!("{x:.1} {}", UNITS[u])
    }
}

impl fmt::Display for OverBudget {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        write!(f, "not enough memory: ")?;
        if self.wanted > 0 {
            write!(f, "{} more would pass ", human(self.wanted))?;
        } else {
            write!(f, "past ")?;
        }
        write!(
            f,
            "the budget of {} ({} in use; raise it with --max-memory)",
            human(self.budget),
            human(self.in_use)
        )
    }
}

impl std::error::Error for OverBudget {}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_what_is_held_and_refuses_past_the_budget() {
        let v = std::hint::black_box(vec![1u8; 64 << 20]);
        assert!(in_use() >= 64 << 20);
        drop(v);
        assert!(reserve(usize::MAX).is_err());
        assert!(reserve(1 << 20).is_ok());
        let e = reserve(usize::MAX).unwrap_err();
        assert!(e.to_string().starts_with("not enough memory: "), "{e}");
    }

    #[test]
    fn human_sizes() {
        assert_eq!(human(512), "512 bytes");
        assert_eq!(human(1 << 30), "1 GiB");
        assert_eq!(human(3 << 29), "1.5 GiB");
    }
}
