//! Memory: allocation of the traversal arrays on 2 MiB pages, and cache prefetch hints.
//!
//! A BVH over a million triangles spans tens of megabytes; incoherent rays touch it at random, so
//! with 4 KiB pages most node visits also miss the TLB. Embree backs its BVHs with transparent huge
//! pages, and so do we: on Linux the arrays are advised `MADV_HUGEPAGE` before their first touch,
//! so the kernel can map them with 2 MiB pages when transparent huge pages are in `madvise` or
//! `always` mode (it silently uses small pages otherwise).

/// Size of a huge page.
#[cfg(target_os = "linux")]
const HUGE_PAGE: usize = 2 << 20;

/// An empty vector with room for `capacity` elements whose storage is advised for huge pages.
/// Only the capacity reserved here is advised: grow it past that and the new storage is not.
/// Besides the BVH arrays, a renderer's frame-sized buffers profit too: a 1080p film of linear
/// RGB is 24 MB, six thousand page faults on small pages and a dozen on huge ones.
pub fn huge_page_vec<T>(capacity: usize) -> Vec<T> {
    let v = Vec::with_capacity(capacity);
    #[cfg(target_os = "linux")]
    {
        let start = v.as_ptr() as usize;
        let end = start + capacity * size_of::<T>();
        // Only whole, aligned huge pages inside the allocation can be mapped as such.
        let (first, last) = (start.next_multiple_of(HUGE_PAGE), end / HUGE_PAGE * HUGE_PAGE);
        if last > first {
            // SAFETY: the range lies inside the vector's own allocation; the advice changes how
            // it is backed, never its contents. A failure only means small pages.
            unsafe { libc::madvise(first as *mut libc::c_void, last - first, libc::MADV_HUGEPAGE) };
        }
    }
    v
}

/// Starts loading `items[index]` into the cache, if it exists: a hint that costs the caller
/// nothing to wait for. Renderers call it for per-triangle data (shader ids, vertex indices) of
/// a packet's hits as they come out of the kernel, so that shading, which reads them a little
/// later, finds them in cache.
#[inline]
pub fn prefetch<T>(items: &[T], index: usize) {
    #[cfg(target_arch = "x86_64")]
    if let Some(item) = items.get(index) {
        use std::arch::x86_64::{_MM_HINT_T0, _mm_prefetch};
        // SAFETY: SSE is part of every x86-64 CPU; a prefetch reads nothing the program sees.
        unsafe { _mm_prefetch::<_MM_HINT_T0>((item as *const T).cast::<i8>()) };
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = (items, index);
}
