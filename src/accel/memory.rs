//! The trees' large arrays on huge pages.
//!
//! Incoherent rays through a tree of a million triangles miss the caches at nearly every
//! node, and with 4 KiB pages the TLB too: every miss then costs a page walk as well. Linux
//! backs memory with 2 MiB pages where asked (`madvise(MADV_HUGEPAGE)`, the default policy
//! being "madvise"), as Embree asks for its BVH memory.

/// Arrays smaller than this stay where they are: a few pages fit the TLB anyway.
const MIN_BYTES: usize = 4 << 20;
const PAGE: usize = 4096;

/// `items`, moved to memory advised to be backed by huge pages if it is large (on Linux; as
/// is elsewhere).
pub(crate) fn on_huge_pages<T: Copy>(items: Vec<T>) -> Vec<T> {
    let bytes = std::mem::size_of_val(items.as_slice());
    if bytes < MIN_BYTES || !cfg!(target_os = "linux") {
        return items;
    }
    let mut moved = Vec::with_capacity(items.len());
    #[cfg(target_os = "linux")]
    {
        // The whole pages inside the new, still untouched allocation: advised before the copy
        // first touches them, so that the kernel can fault them in as huge pages.
        let start = (moved.as_mut_ptr() as usize).next_multiple_of(PAGE);
        let end = (moved.as_mut_ptr() as usize + bytes) / PAGE * PAGE;
        if end > start {
            // SAFETY: the range lies within `moved`'s allocation; the advice changes only how
            // the kernel backs those pages, never their contents or mapping. A refusal
            // (returned, not raised) leaves ordinary pages.
            unsafe { libc::madvise(start as *mut libc::c_void, end - start, libc::MADV_HUGEPAGE) };
        }
    }
    moved.extend_from_slice(&items);
    moved
}

/// Asks the CPU to start loading the `lines` cache lines (64 bytes each) from `item` on into
/// the caches, without waiting for them: a hint that changes no result. Traversal issues it for
/// the children it will visit later, so that their loads overlap the work in between.
#[inline(always)]
pub(crate) fn prefetch<T>(item: *const T, lines: usize) {
    #[cfg(target_arch = "x86_64")]
    for line in 0..lines {
        let address = item.cast::<i8>().wrapping_add(64 * line);
        // SAFETY: a prefetch is a hint: it never faults, even for an address outside the
        // item, and SSE (which provides it) is part of the x86-64 baseline.
        unsafe { std::arch::x86_64::_mm_prefetch::<{ std::arch::x86_64::_MM_HINT_T0 }>(address) };
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = (item, lines);
}
