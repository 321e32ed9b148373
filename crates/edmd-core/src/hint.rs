//! Hints to the processor: they change speed, never results.

/// Asks the processor to start loading `x` into the cache (a hint: no effect on results).
#[inline(always)]
pub(crate) fn prefetch<T>(x: &T) {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
        // SAFETY: a prefetch never faults and changes no state; the address is a live reference.
        #[allow(unsafe_code)]
        unsafe {
            _mm_prefetch::<_MM_HINT_T0>((x as *const T).cast::<i8>());
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = x;
}

/// A huge page on x86-64 Linux.
const HUGE_PAGE: usize = 2 << 20;

/// The size from which an array asks for huge pages: smaller ones would gain one at most.
const HUGE_FROM: usize = 2 * HUGE_PAGE;

/// Asks the kernel to back the spare capacity of `v` with huge pages (2 MiB on x86-64; a hint:
/// no effect on results). Call it before that memory is first written: pages are chosen when
/// first touched. For the large arrays read at random by the event loop (the records of the
/// spheres around each event): with 4 KiB pages, a record array past the TLB's reach (about
/// 8 MB) costs a page walk on most reads (BENCHMARKS.md). Small arrays are
/// left alone.
pub(crate) fn huge_pages<T>(v: &mut Vec<T>) {
    #[cfg(target_os = "linux")]
    {
        let spare = v.spare_capacity_mut();
        let len = std::mem::size_of_val(spare);
        if len < HUGE_FROM {
            return;
        }
        advise(spare.as_mut_ptr() as usize, len);
    }
    #[cfg(not(target_os = "linux"))]
    let _ = v;
}

/// `madvise(MADV_HUGEPAGE)` for the `len` bytes from `start`, within one allocation.
#[cfg(target_os = "linux")]
fn advise(start: usize, len: usize) {
    // `madvise` wants a page-aligned start; the kernel uses the huge pages that fit.
    let aligned = start.next_multiple_of(4096);
    if aligned >= start + len {
        return;
    }
    // SAFETY: `MADV_HUGEPAGE` changes no contents and no mapping, only how pages of the
    // range are chosen; the callers pass a range within one allocation of theirs. Its result
    // is a hint's: ignored.
    #[allow(unsafe_code)]
    unsafe {
        libc::madvise(
            aligned as *mut libc::c_void,
            start + len - aligned,
            libc::MADV_HUGEPAGE,
        );
    }
}

/// An array of records aligned for the cache, or for huge pages when large.
pub(crate) type Records<T> = aligned_vec::AVec<T, aligned_vec::RuntimeAlign>;

/// An empty [`Records`] with room for `n`: its start aligned to a cache line (64 bytes), so
/// that 64-byte records each sit in one line, or to a huge page (2 MiB) when it takes 4 MiB
/// or more, with [`huge_pages`]' advice for the whole of it.
pub(crate) fn records<T>(n: usize) -> Records<T> {
    let bytes = n.saturating_mul(std::mem::size_of::<T>());
    let align = if bytes >= HUGE_FROM { HUGE_PAGE } else { 64 };
    let v = Records::with_capacity(align, n);
    #[cfg(target_os = "linux")]
    if bytes >= HUGE_FROM {
        advise(v.as_ptr() as usize, bytes);
    }
    v
}

/// `vec![value; n]`, with [`huge_pages`] asked for before it is filled.
pub(crate) fn filled<T: Clone>(value: T, n: usize) -> Vec<T> {
    let mut v = Vec::with_capacity(n);
    huge_pages(&mut v);
    v.resize(n, value);
    v
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn filled_is_vec_macro() {
        assert_eq!(filled(7u32, 3), vec![7u32; 3]);
        let big = filled([1.5f64; 3], 300_000);
        assert_eq!(big.len(), 300_000);
        assert!(big.iter().all(|x| *x == [1.5; 3]));
    }

    #[test]
    fn records_start_on_a_line_or_a_huge_page() {
        let small = records::<[u8; 80]>(1000);
        assert_eq!(small.as_ptr() as usize % 64, 0);
        let large = records::<[u8; 80]>(100_000); // 8 MB
        assert_eq!(large.as_ptr() as usize % HUGE_PAGE, 0);
        assert!(small.capacity() >= 1000 && large.capacity() >= 100_000);
    }

    /// The kernel marks a mapping it was asked to back with huge pages `hg` in
    /// `/proc/self/smaps` (proc(5)), whether or not it finds free huge pages. Checked where the
    /// kernel has transparent huge pages at all.
    #[cfg(target_os = "linux")]
    #[test]
    fn large_arrays_ask_for_huge_pages() {
        let thp = "/sys/kernel/mm/transparent_hugepage/enabled";
        match std::fs::read_to_string(thp) {
            Ok(mode) if !mode.contains("[never]") => {}
            _ => {
                eprintln!("no transparent huge pages on this kernel ({thp}): nothing to check");
                return;
            }
        }
        let flags = |addr: usize| -> String {
            let smaps = std::fs::read_to_string("/proc/self/smaps").unwrap();
            let mut inside = false;
            for line in smaps.lines() {
                let range = line.split(' ').next().unwrap_or("");
                if let Some((lo, hi)) = range.split_once('-') {
                    if let (Ok(lo), Ok(hi)) =
                        (usize::from_str_radix(lo, 16), usize::from_str_radix(hi, 16))
                    {
                        inside = (lo..hi).contains(&addr);
                        continue;
                    }
                }
                if let Some(f) = line.strip_prefix("VmFlags:") {
                    if inside {
                        return f.to_string();
                    }
                }
            }
            panic!("no mapping holds {addr:#x}");
        };
        let marked = |addr: usize| flags(addr).split_whitespace().any(|f| f == "hg");
        let large = filled(0u64, 1 << 20); // 8 MiB
        let recs = records::<[u8; 80]>(100_000); // 8 MB
        for (what, start) in [
            ("filled", large.as_ptr() as usize),
            ("records", recs.as_ptr() as usize),
        ] {
            let middle = start + (4 << 20);
            assert!(
                marked(middle),
                "8 MB from {what} not marked for huge pages: {}",
                flags(middle)
            );
        }
        // That small arrays are left alone cannot be seen here: a small allocation may reuse
        // memory a large array freed with its advice (glibc serves large blocks from its heap
        // once its mmap threshold has grown), and a CI run found one so marked.
    }
}
