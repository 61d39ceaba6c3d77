//! Memory hints for the big arrays a frame reads out of order: huge pages, so those reads do not also miss the TLB.

/// Asks the kernel to back `v`'s buffer with huge pages where it can (Linux, transparent huge
/// pages in `madvise` mode): a frame reads its big arrays out of order, and with 4 KiB pages
/// nearly every such read would also miss the TLB. A hint only: it changes no contents, and a
/// refusal is harmless.
pub(crate) fn huge_pages<T>(v: &mut Vec<T>) {
    #[cfg(target_os = "linux")]
    {
        const HUGE: usize = 2 << 20;
        let start = v.as_mut_ptr() as usize;
        let end = start + v.capacity() * std::mem::size_of::<T>();
        let (a, b) = (start.next_multiple_of(HUGE), end / HUGE * HUGE);
        if b > a {
            // SAFETY: the range lies inside the vector's own allocation, and MADV_HUGEPAGE
            // leaves its contents as they are.
            unsafe {
                libc::madvise(a as *mut libc::c_void, b - a, libc::MADV_HUGEPAGE);
            }
        }
    }
    #[cfg(not(target_os = "linux"))]
    let _ = v;
}

/// Asks the kernel to back the whole 2 MiB pages inside `s` with huge pages now (Linux 6.1+
/// `MADV_COLLAPSE`), for a big array read out of order that was allocated without
/// [`huge_pages`] (the mesh's tets: the visibility order visits them all over, and with 4 KiB
/// pages nearly every visit misses the TLB). The first call copies the range into huge pages
/// once; later calls find it collapsed. A hint only: the contents stay as they are, and a
/// refusal (an older kernel, no huge page free) is harmless.
pub(crate) fn collapse_huge<T>(s: &[T]) {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    {
        const HUGE: usize = 2 << 20;
        let start = s.as_ptr() as usize;
        let end = start + std::mem::size_of_val(s);
        let (a, b) = (start.next_multiple_of(HUGE), end / HUGE * HUGE);
        if b > a {
            // SAFETY: the range lies inside `s`'s memory, and MADV_COLLAPSE only changes which
            // physical pages back it, never what a read of it returns.
            unsafe {
                libc::madvise(a as *mut libc::c_void, b - a, libc::MADV_COLLAPSE);
            }
        }
    }
    #[cfg(not(all(target_os = "linux", target_env = "gnu")))]
    let _ = s;
}
