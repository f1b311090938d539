//! Stepping must not allocate: a counting global allocator (per thread, so that tests running
//! side by side do not disturb each other) watches 10 000 real-time steps in each coupling mode
//! (window moves included), full-model steps, and the energy and dissipation evaluations.

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

use pcsim_core::analysis::energy::{dissipation_rate, system_energy};
use pcsim_core::compile::Stepper;
use pcsim_core::presets;
use pcsim_core::solve::realtime::Coupling;

struct Counting;

thread_local! {
    static ALLOCS: Cell<usize> = const { Cell::new(0) };
}

fn allocs() -> usize {
    ALLOCS.with(|c| c.get())
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCS.with(|c| c.set(c.get() + 1));
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        ALLOCS.with(|c| c.set(c.get() + 1));
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

#[test]
fn ten_thousand_realtime_steps_allocate_nothing() {
    realtime_steps_allocate_nothing("syt-7.0-9.8", 215.0, 10_000);
}

/// On a line the window moves between a model per position (issue 21, item 7): across both
/// overlaps of the 2018-like line, in both coupling modes.
#[test]
fn realtime_steps_across_a_lines_overlaps_allocate_nothing() {
    let (case, _) = presets::load("en50318-2018-like-simple").unwrap();
    let rt = pcsim_core::compile::realtime_window(&case, 240.0, Coupling::Sil).unwrap();
    assert!(rt.is_line());
    // From the start to beyond the second overlap (1 200–1 380 m).
    let steps = ((1400.0 - case.run.start_m) / (case.run.speed_kmh / 3.6) / rt.dt_s()) as usize;
    realtime_steps_allocate_nothing("en50318-2018-like-simple", 240.0, steps);
}

fn realtime_steps_allocate_nothing(preset: &str, window_m: f64, steps: usize) {
    let (case, _) = presets::load(preset).unwrap();
    for coupling in [Coupling::Sil, Coupling::Hil] {
        let c0 = allocs();
        let mut rt = pcsim_core::compile::realtime_window(&case, window_m, coupling).unwrap();
        assert!(
            allocs() > c0,
            "the counter must see the set-up's allocations"
        );
        let v = case.run.speed_kmh / 3.6;
        let x0 = case.run.start_m;
        let dt = rt.dt_s();
        let before = allocs();
        let mut check = 0.0;
        for k in 0..steps {
            let t = k as f64 * dt;
            rt.set_input(85.0 + 15.0 * (7.0 * t).sin(), x0 + v * t);
            let o = rt.step();
            check += o.wire_height_m;
        }
        let after = allocs();
        assert!(check.is_finite());
        assert!(
            rt.moves() >= 5,
            "{coupling:?}: the window must move during the test ({} moves)",
            rt.moves()
        );
        assert_eq!(
            after - before,
            0,
            "{preset}, {coupling:?}: {} allocations in {steps} steps",
            after - before
        );
    }
}

/// The session's whole step contract (checks, save, step, soundness), its refusals and roll-backs,
/// and saving into and restoring from an existing state, allocate nothing either (issue 18).
#[test]
fn the_session_contract_allocates_nothing() {
    use pcsim_core::session::RealtimeSession;
    let (case, _) = presets::load("syt-7.0-9.8").unwrap();
    let mut rt = RealtimeSession::new(&case, 215.0, Coupling::Hil).unwrap();
    let mut saved = rt.state([0.0; 4]);
    let (x0, dt, v) = (rt.start_position_m(), rt.dt_s(), case.run.speed_kmh / 3.6);
    let before = allocs();
    let mut refused = 0;
    for k in 0..10_000 {
        let t = k as f64 * dt;
        let x = x0 + v * t;
        if rt.step(85.0 + 15.0 * (7.0 * t).sin(), x).is_err() {
            refused += 1;
        }
        if k % 1000 == 500 {
            // A refused input (1e300 N) and a NaN: refused without allocating.
            assert!(rt.step(1e300, x).is_err());
            assert!(rt.step(f64::NAN, x).is_err());
            rt.save_into(&mut saved, [t, 0.0, 0.0, 0.0]);
        }
    }
    rt.restore(&saved).unwrap();
    let after = allocs();
    assert_eq!(refused, 0);
    assert!(rt.moves() >= 5, "{} moves", rt.moves());
    assert_eq!(after - before, 0, "{} allocations", after - before);
    // A roll-back allocates nothing (the force bound lifted so that 1e300 N is stepped).
    rt.set_force_limit_n(1e301).unwrap();
    let before = allocs();
    let e = rt.step(1e300, x0 + v * 9500.0 * dt).unwrap_err();
    assert_eq!(e.code(), "rolled_back");
    assert_eq!(allocs() - before, 0);
}

#[test]
fn full_model_steps_and_energy_evaluations_allocate_nothing() {
    // The stitched zoo model has every element kind: droppers, supports, arms, stitch nodes.
    let setup = pcsim_core::zoo::model("stitched_three_spans").unwrap();
    let mut s = Stepper::new(&setup).unwrap();
    let before = allocs();
    let mut check = 0.0;
    for _ in 0..2_000 {
        s.step();
        check += system_energy(s.integ.compiled(), &s.state, &mut s.ws).total()
            + dissipation_rate(s.integ.compiled(), &s.state, &mut s.ws);
    }
    let after = allocs();
    assert!(check.is_finite() && check > 0.0);
    assert_eq!(after - before, 0, "{} allocations", after - before);
}

#[test]
fn three_direction_steps_with_wind_allocate_nothing() {
    // Lateral and torsional blocks, 3D droppers, registrations, the contact's twist and the
    // crosswind's per-step scatter.
    let (mut case, _) = presets::load("stitched-2018-like-3d-crosswind").unwrap();
    case.catenary.spans = 8;
    case.pantographs.truncate(1);
    case.run.start_m = 150.0;
    case.run.end_m = 300.0;
    case.run.analysis_m = [150.0, 300.0];
    case.run.allow_start_transient = true; // an allocation count, not statistics
    case.run.modes = Some(240);
    let setup = pcsim_core::compile::Setup::from_case(&case).unwrap();
    let mut s = Stepper::new(&setup).unwrap();
    let before = allocs();
    let mut check = 0.0;
    for _ in 0..1_000 {
        s.step();
        check += s.ws.samples()[0].lateral_m + s.integ.compiled().wind_power(&s.state, &s.ws);
    }
    let after = allocs();
    assert!(check.is_finite() && check != 0.0);
    assert_eq!(after - before, 0, "{} allocations", after - before);
}

#[test]
fn the_real_time_window_steps_with_lateral_motion_allocate_nothing() {
    let (case, _) = presets::load("stitched-2018-like-3d").unwrap();
    let mut rt = pcsim_core::compile::realtime_window(&case, 240.0, Coupling::Sil).unwrap();
    let before = allocs();
    let (mut lo, mut hi) = (f64::MAX, f64::MIN);
    for _ in 0..6_000 {
        let o = rt.step();
        lo = lo.min(o.lateral_m);
        hi = hi.max(o.lateral_m);
    }
    let after = allocs();
    assert_eq!(after - before, 0, "{} allocations", after - before);
    assert!(
        rt.moves() >= 2,
        "the window must move ({} moves)",
        rt.moves()
    );
    // The contact point zig-zags over the ±0.3 m stagger in the moving window too.
    assert!(hi < 0.302 && lo > -0.302 && hi - lo > 0.5, "{lo} … {hi}");
}
