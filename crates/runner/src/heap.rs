//! Memory a finished stage freed, handed back to the system.
//!
//! glibc's malloc keeps freed blocks in its arenas (one per thread that
//! allocated) and returns only the top of the main heap on its own, so a
//! long run's resident memory climbs with every stage that used the worker
//! threads: the paper pipeline held 0.6-1.1 GB more than its live products
//! by its last sample, and that sat under each sample's 1.5 GB scan phase
//! (measured 2026-12-07, issue #48: peak 2.05 GB, against 1.69 GB with the
//! arenas trimmed). `malloc_trim(0)` releases the free pages of every arena
//! (glibc >= 2.8 also returns whole free pages inside the heap, with
//! madvise), so the runner calls it each time products leave memory.

/// Returns the free pages of malloc's arenas to the system (glibc); a
/// no-op where the C library is another.
#[cfg(all(target_os = "linux", target_env = "gnu"))]
#[allow(unsafe_code)]
pub fn return_freed() {
    // SAFETY: malloc_trim takes no pointer and touches only malloc's own
    // free lists, under each arena's lock, so it is sound from any thread
    // at any time (glibc manual, "Memory Allocation Tunables"/malloc_trim).
    unsafe {
        libc::malloc_trim(0);
    }
}

/// Returns the free pages of malloc's arenas to the system (glibc); a
/// no-op where the C library is another.
#[cfg(not(all(target_os = "linux", target_env = "gnu")))]
pub fn return_freed() {}

#[cfg(test)]
mod tests {
    use super::*;

    fn resident_kib() -> Option<u64> {
        let status = std::fs::read_to_string("/proc/self/status").ok()?;
        let line = status.lines().find(|l| l.starts_with("VmRSS:"))?;
        line.split_whitespace().nth(1)?.parse().ok()
    }

    /// Mid-sized blocks (below glibc's mmap threshold, so they come from
    /// this thread's arena), each followed by a small one that stays:
    /// freeing the large ones leaves holes malloc cannot shrink its heap
    /// past, and their pages stay resident until the trim gives them back.
    #[test]
    fn freed_arena_memory_leaves_the_process() {
        if !cfg!(all(target_os = "linux", target_env = "gnu")) {
            return;
        }
        let (blocks, pins): (Vec<Vec<u8>>, Vec<Vec<u8>>) = (0..3000)
            .map(|i| (vec![(i % 251) as u8 | 1; 64 * 1024], vec![7u8; 64]))
            .unzip();
        let touched: u64 = blocks.iter().map(|b| u64::from(b[0])).sum();
        drop(blocks);
        let freed = resident_kib().unwrap();
        return_freed();
        let trimmed = resident_kib().unwrap();
        assert!(touched > 0 && pins.iter().all(|p| p[0] == 7));
        // ~197 MB were touched and freed; at least half of it must leave.
        assert!(
            freed > trimmed + 100_000,
            "resident {freed} KiB after the free, {trimmed} KiB after the trim"
        );
    }
}
