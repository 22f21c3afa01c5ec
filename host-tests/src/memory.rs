//! Large buffers in 2 MiB pages: [`HugePages`], the global allocator of the `volsample` CLI and
//! the benchmarks.
//!
//! A volume is read along rays that cross a z-plane (`nx·ny` voxels, 1 MiB for 256² voxels of
//! 16 bytes) at every step, so in 4 KiB pages nearly every tap row of a step lies in a page of
//! its own and the translation misses add to the memory's latency. Linux backs a region with
//! 2 MiB pages where the process asks for them (`madvise(MADV_HUGEPAGE)`, the default policy
//! `madvise` of `/sys/kernel/mm/transparent_hugepage/enabled`); the system allocator does not
//! ask. [`HugePages`] is the system allocator that asks for every allocation of at least
//! [`HUGE_FROM`] bytes: the volumes, images and tables of the CLI, the report and the
//! benchmarks, without a change to the code that allocates them. The effect on the
//! `ray_march` benchmark is in the performance log (2026-12-06, afternoon).
//!
//! The core allocates nothing; a program that links it chooses its own allocator. Elsewhere
//! than on Linux, and where the kernel has no transparent huge pages, [`HugePages`] is the
//! system allocator and nothing more.
//!
//! ```
//! // In a binary that renders large volumes (as `volsample` and the benches do):
//! #[global_allocator]
//! static ALLOCATOR: volsample_host::memory::HugePages = volsample_host::memory::HugePages;
//! # fn main() {}
//! ```

use std::alloc::{GlobalAlloc, Layout, System};

/// The smallest allocation [`HugePages`] advises: two 2 MiB pages, so that one whole page
/// lies inside it wherever it starts.
pub const HUGE_FROM: usize = 4 << 20;

/// The size of a huge page on x86-64 and AArch64 Linux.
const HUGE_PAGE: usize = 2 << 20;

/// The system allocator, asking Linux to back every allocation of at least [`HUGE_FROM`]
/// bytes with 2 MiB pages (the whole huge pages inside it; see the module doc).
#[derive(Debug, Clone, Copy, Default)]
pub struct HugePages;

impl HugePages {
    /// Asks for 2 MiB pages for the whole huge pages inside the block `[ptr, ptr + size)` the
    /// system allocator has just returned, where `size ≥ HUGE_FROM`; returns whether the
    /// kernel accepted (`false` without Linux's transparent huge pages, and for a smaller
    /// `size`). Private: `advise_huge`'s proof rests on the range being such a block.
    fn advise(ptr: *mut u8, size: usize) -> bool {
        if ptr.is_null() || size < HUGE_FROM {
            return false;
        }
        let start = (ptr as usize).next_multiple_of(HUGE_PAGE);
        let end = (ptr as usize).saturating_add(size) / HUGE_PAGE * HUGE_PAGE;
        if end <= start {
            return false;
        }
        advise_huge(start, end - start)
    }
}

#[cfg(target_os = "linux")]
fn advise_huge(start: usize, len: usize) -> bool {
    // SAFETY: `madvise` with `MADV_HUGEPAGE` changes how the kernel backs the pages of the
    // range (2 MiB pages where it can), never their contents, and fails without effect where
    // the range is not mapped; `start` is aligned to 2 MiB (a multiple of the page size, as
    // `madvise` requires) and the range lies inside one allocation of the caller's.
    unsafe { libc::madvise(start as *mut libc::c_void, len, libc::MADV_HUGEPAGE) == 0 }
}

#[cfg(not(target_os = "linux"))]
fn advise_huge(_start: usize, _len: usize) -> bool {
    false
}

// SAFETY: every method is `System`'s with the same arguments, its result returned unchanged;
// `advise` only changes how the pages of a block `System` returned are backed.
unsafe impl GlobalAlloc for HugePages {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        // SAFETY: the caller's contract of `GlobalAlloc::alloc`, passed on.
        let p = unsafe { System.alloc(layout) };
        Self::advise(p, layout.size());
        p
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        // SAFETY: as above.
        let p = unsafe { System.alloc_zeroed(layout) };
        Self::advise(p, layout.size());
        p
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: as above (`ptr` came from `System` through this allocator).
        unsafe { System.dealloc(ptr, layout) }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        // SAFETY: as above.
        let p = unsafe { System.realloc(ptr, layout, new_size) };
        Self::advise(p, new_size);
        p
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The `VmFlags` line of the mapping of `/proc/self/smaps` that holds `addr`.
    #[cfg(target_os = "linux")]
    fn vm_flags(addr: usize) -> Option<String> {
        let smaps = std::fs::read_to_string("/proc/self/smaps").ok()?;
        let mut inside = false;
        for line in smaps.lines() {
            let range = line
                .split_whitespace()
                .next()
                .and_then(|r| r.split_once('-'));
            if let Some((lo, hi)) = range {
                if let (Ok(lo), Ok(hi)) =
                    (usize::from_str_radix(lo, 16), usize::from_str_radix(hi, 16))
                {
                    inside = (lo..hi).contains(&addr);
                    continue;
                }
            }
            if inside {
                if let Some(flags) = line.strip_prefix("VmFlags:") {
                    return Some(flags.to_owned());
                }
            }
        }
        None
    }

    /// A large block is advised (its mapping carries the kernel's `hg` flag where Linux has
    /// transparent huge pages), a small one is not, and the blocks hold what is written.
    #[test]
    fn large_blocks_are_advised_small_ones_not() {
        let layout = Layout::from_size_align(3 * HUGE_FROM, 64).expect("layout");
        // SAFETY: a non-zero size; the block is freed below with the same layout.
        let p = unsafe { HugePages.alloc_zeroed(layout) };
        assert!(!p.is_null());
        // SAFETY: `p` is a live block of `layout.size()` bytes.
        let block = unsafe { std::slice::from_raw_parts_mut(p, layout.size()) };
        assert!(block.iter().all(|&b| b == 0));
        block.fill(7);
        assert!(block.iter().all(|&b| b == 7));
        let thp = std::path::Path::new("/sys/kernel/mm/transparent_hugepage/enabled").exists();
        #[cfg(target_os = "linux")]
        if thp {
            let inner = (p as usize).next_multiple_of(HUGE_PAGE);
            let flags = vm_flags(inner).expect("the block's mapping in /proc/self/smaps");
            assert!(
                flags.split_whitespace().any(|f| f == "hg"),
                "no `hg` in {flags}"
            );
        }
        assert_eq!(
            HugePages::advise(p, layout.size()),
            thp && cfg!(target_os = "linux")
        );
        assert!(!HugePages::advise(p, HUGE_FROM - 1));
        assert!(!HugePages::advise(std::ptr::null_mut(), layout.size()));
        // SAFETY: allocated above with `layout`.
        unsafe { HugePages.dealloc(p, layout) };
    }

    /// A `Vec` grown past [`HUGE_FROM`] through `realloc` keeps its contents.
    #[test]
    fn realloc_keeps_the_contents() {
        let small = Layout::from_size_align(1 << 10, 8).expect("layout");
        // SAFETY: a non-zero size; reallocated and freed below with the matching layouts.
        let p = unsafe { HugePages.alloc(small) };
        assert!(!p.is_null());
        // SAFETY: `p` is a live block of `small.size()` bytes.
        unsafe { std::slice::from_raw_parts_mut(p, small.size()) }.fill(3);
        let big = 2 * HUGE_FROM;
        // SAFETY: `p` came from this allocator with `small`; `big` is non-zero.
        let q = unsafe { HugePages.realloc(p, small, big) };
        assert!(!q.is_null());
        // SAFETY: `q` is a live block of `big` bytes whose first `small.size()` were copied.
        let kept = unsafe { std::slice::from_raw_parts(q, small.size()) };
        assert!(kept.iter().all(|&b| b == 3));
        let layout = Layout::from_size_align(big, 8).expect("layout");
        // SAFETY: `q` is the block `realloc` returned, of `big` bytes.
        unsafe { HugePages.dealloc(q, layout) };
    }
}
