//! Heap bytes held and at their peak, counted by a global allocator.
//!
//! [`CountingAllocator`] wraps the system allocator and keeps two counters:
//! the bytes live now and the most ever live since the last
//! [`reset_peak`]. The binary installs it (`#[global_allocator]` in
//! `main.rs`); a program that does not (the tests) reads zeros, which
//! [`is_counting`] reports. Counting costs two relaxed atomic operations per
//! allocation, negligible next to the allocations of a scene load.

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};

static LIVE_BYTES: AtomicUsize = AtomicUsize::new(0);
static PEAK_BYTES: AtomicUsize = AtomicUsize::new(0);

/// The system allocator, counting live and peak heap bytes.
pub struct CountingAllocator;

// SAFETY: every call is forwarded to `System` unchanged; the counters are
// only bookkeeping.
unsafe impl GlobalAlloc for CountingAllocator {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let pointer = unsafe { System.alloc(layout) };
        if !pointer.is_null() {
            grow(layout.size());
        }
        pointer
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        let pointer = unsafe { System.alloc_zeroed(layout) };
        if !pointer.is_null() {
            grow(layout.size());
        }
        pointer
    }

    unsafe fn dealloc(&self, pointer: *mut u8, layout: Layout) {
        unsafe { System.dealloc(pointer, layout) };
        LIVE_BYTES.fetch_sub(layout.size(), Ordering::Relaxed);
    }

    unsafe fn realloc(&self, pointer: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        let moved = unsafe { System.realloc(pointer, layout, new_size) };
        if !moved.is_null() {
            LIVE_BYTES.fetch_sub(layout.size(), Ordering::Relaxed);
            grow(new_size);
        }
        moved
    }
}

fn grow(bytes: usize) {
    let live = LIVE_BYTES.fetch_add(bytes, Ordering::Relaxed) + bytes;
    PEAK_BYTES.fetch_max(live, Ordering::Relaxed);
}

/// Heap bytes live now.
pub fn live_bytes() -> usize {
    LIVE_BYTES.load(Ordering::Relaxed)
}

/// Most heap bytes live since the last [`reset_peak`].
pub fn peak_bytes() -> usize {
    PEAK_BYTES.load(Ordering::Relaxed)
}

/// Starts a new peak from the bytes live now.
pub fn reset_peak() {
    PEAK_BYTES.store(live_bytes(), Ordering::Relaxed);
}

/// Whether [`CountingAllocator`] is the program's allocator.
pub fn is_counting() -> bool {
    live_bytes() > 0
}

/// Heap growth over a piece of work: the peak above the start, and what is still held at the end.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct MemoryUse {
    pub peak_bytes: usize,
    pub retained_bytes: usize,
}

/// Runs `work`, measuring its heap growth while its result is still alive
/// (`None` if the counting allocator is not installed).
pub fn measure<T>(work: impl FnOnce() -> T) -> (T, Option<MemoryUse>) {
    let start = live_bytes();
    reset_peak();
    let result = work();
    let usage = MemoryUse {
        peak_bytes: peak_bytes().saturating_sub(start),
        retained_bytes: live_bytes().saturating_sub(start),
    };
    (result, is_counting().then_some(usage))
}
