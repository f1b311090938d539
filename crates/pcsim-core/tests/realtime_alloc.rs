//! The real-time step must not allocate: a counting global allocator watches 10 000 steps in
//! each coupling mode, window moves included.

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};

use pcsim_core::presets;
use pcsim_core::realtime::{Coupling, RealtimeCatenary};

struct Counting;

static ALLOCS: AtomicUsize = AtomicUsize::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCS.fetch_add(1, Ordering::SeqCst);
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        ALLOCS.fetch_add(1, Ordering::SeqCst);
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

#[test]
fn ten_thousand_steps_allocate_nothing() {
    let (case, _) = presets::load("syt-7.0-9.8").unwrap();
    for coupling in [Coupling::Sil, Coupling::Hil] {
        let c0 = ALLOCS.load(Ordering::SeqCst);
        let mut rt = RealtimeCatenary::new(&case, 215.0, coupling).unwrap();
        assert!(
            ALLOCS.load(Ordering::SeqCst) > c0,
            "the counter must see the set-up's allocations"
        );
        let v = case.run.speed_kmh / 3.6;
        let x0 = case.run.start_m;
        let dt = rt.dt_s();
        let before = ALLOCS.load(Ordering::SeqCst);
        let mut check = 0.0;
        for k in 0..10_000 {
            let t = k as f64 * dt;
            rt.set_input(85.0 + 15.0 * (7.0 * t).sin(), x0 + v * t);
            let o = rt.step();
            check += o.wire_height_m;
        }
        let after = ALLOCS.load(Ordering::SeqCst);
        assert!(check.is_finite());
        assert!(
            rt.moves() >= 5,
            "{coupling:?}: the window must move during the test ({} moves)",
            rt.moves()
        );
        assert_eq!(
            after - before,
            0,
            "{coupling:?}: {} allocations in 10 000 steps",
            after - before
        );
    }
}
