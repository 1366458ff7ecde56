//! The allocator of the command line: the system's, with a failed
//! allocation refused like the memory estimate (a message, the run's staged
//! files removed, exit status 1) instead of Rust's abort, which leaves
//! staged files and folders behind. The estimates of [`crate::memory`]
//! stop most runs that would not fit before they start; this catches what
//! they cannot see (an address-space limit of a few tens of megabytes,
//! another process taking the memory meanwhile).

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicPtr, Ordering};

/// Memory set aside at start and given back when an allocation fails, so
/// that removing the staged files and saying why can still allocate.
const RESERVE: Layout = match Layout::from_size_align(1 << 20, 16) {
    Ok(layout) => layout,
    Err(_) => panic!("a valid layout"),
};

static RESERVED: AtomicPtr<u8> = AtomicPtr::new(std::ptr::null_mut());

/// The system allocator, refusing a failed allocation.
pub struct Refusing;

/// Sets [`RESERVE`] aside; call first thing in `main`.
pub fn reserve() {
    // SAFETY: `RESERVE` has a non-zero size.
    let block = unsafe { System.alloc(RESERVE) };
    RESERVED.store(block, Ordering::SeqCst);
}

#[cold]
fn refuse(layout: Layout) -> ! {
    let block = RESERVED.swap(std::ptr::null_mut(), Ordering::SeqCst);
    if !block.is_null() {
        // SAFETY: allocated in `reserve` with `RESERVE`, freed once (swapped out).
        unsafe { System.dealloc(block, RESERVE) };
    }
    crate::outputs::abandon(&format!(
        "out of memory: an allocation of {} bytes failed (the memory this process may use, `ulimit -v` or the system's, is exhausted); use a smaller input or allow more memory",
        layout.size()
    ))
}

// SAFETY: every call is passed to `System` unchanged; a null result (a
// failed allocation) never returns.
unsafe impl GlobalAlloc for Refusing {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let p = System.alloc(layout);
        if p.is_null() {
            refuse(layout);
        }
        p
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        let p = System.alloc_zeroed(layout);
        if p.is_null() {
            refuse(layout);
        }
        p
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        System.dealloc(ptr, layout);
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        let p = System.realloc(ptr, layout, new_size);
        if p.is_null() {
            refuse(Layout::from_size_align_unchecked(new_size, layout.align()));
        }
        p
    }
}
