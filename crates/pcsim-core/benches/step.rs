//! Benchmarks of the core (criterion): a step of every zoo model and of the full preset, a step of
//! the real-time window through the session's contract, the sampler's gather and scatter, and
//! building the model. Wall time on a noisy machine: the figures in docs/performance.md are
//! callgrind instruction counts and medians of pinned runs; these benches are for comparing two
//! builds on one machine (`cargo bench -p pcsim-core -- --save-baseline before`, then
//! `--baseline before`).
//!
//! ```sh
//! cargo bench -p pcsim-core --bench step
//! ```

use criterion::{criterion_group, criterion_main, Criterion};
use pcsim_core::compile::{Setup, Stepper};
use pcsim_core::model::basis::SineBasis;
use pcsim_core::presets;
use pcsim_core::session::{Coupling, RealtimeSession};
use pcsim_core::solve::sampler::PointSampler;
use pcsim_core::solve::Isa;
use pcsim_core::zoo;
use std::hint::black_box;

/// One step of each zoo model (each entry's reference: `zoo::reference`), stepped from its
/// initial state.
fn zoo_steps(c: &mut Criterion) {
    for name in zoo::NAMES {
        let setup = zoo::model(name).expect("zoo model");
        let mut s = Stepper::new(&setup).expect("stepper");
        c.bench_function(&format!("step/zoo/{name}"), |b| b.iter(|| s.step()));
    }
}

/// One step of the full model: `stitched-2018-like` at 320 km/h, two pantographs.
fn preset_step(c: &mut Criterion) {
    let (case, _) = presets::load("stitched-2018-like").unwrap();
    let setup = Setup::from_case(&case).unwrap();
    let mut s = Stepper::new(&setup).unwrap();
    // Past the start, where the pantographs touch.
    for _ in 0..200 {
        s.step();
    }
    c.bench_function("step/preset/stitched-2018-like", |b| b.iter(|| s.step()));
}

/// Each named stage of the full model's step alone (`Integrator::step_stage`), on
/// `stitched-2018-like` at 320 km/h past the start. For the instruction count of one stage, run
/// its bench alone under callgrind and divide `step_stage`'s inclusive cost by its calls
/// (docs/performance.md).
fn stages(c: &mut Criterion) {
    let (case, _) = presets::load("stitched-2018-like").unwrap();
    let setup = Setup::from_case(&case).unwrap();
    let integ = setup.integrator().unwrap();
    let mut st = integ.initial_state(setup.plan.start_m);
    let mut ws = integ.workspace();
    for _ in 0..200 {
        integ.step(&mut st, &mut ws);
    }
    for s in pcsim_core::solve::Stage::ALL {
        c.bench_function(&format!("stage/{}", s.name()), |b| {
            b.iter(|| integ.step_stage(s, &mut st, &mut ws))
        });
    }
}

/// A step of the 215 m real-time window under the whole contract (checks, save, step,
/// soundness), with the window moving as the pantograph runs.
fn realtime_step(c: &mut Criterion) {
    let (case, _) = presets::load("syt-7.0-9.8").unwrap();
    let mut rt = RealtimeSession::new(&case, 215.0, Coupling::Hil).unwrap();
    let start = rt.state([0.0; 4]);
    let (x0, dt, v) = (rt.start_position_m(), rt.dt_s(), 222.0 / 3.6);
    let mut k = 0u64;
    c.bench_function("step/realtime/215m", |b| {
        b.iter(|| {
            // Over and over the first 1500 steps (the window moves once): back to the start by
            // a restore, a copy without allocation.
            if k == 1500 {
                rt.restore(&start).unwrap();
                k = 0;
            }
            let x = x0 + v * dt * k as f64;
            k += 1;
            black_box(rt.step(85.0, x).unwrap())
        })
    });
}

/// The sampler alone: gather and scatter of one block of 1200 modes at 30 spans' droppers.
fn sampler(c: &mut Criterion) {
    let (span, spans, n) = (60.0, 30usize, 1200usize);
    let basis = SineBasis::new(span * spans as f64, n);
    let offsets = [4.5, 10.0, 17.5, 25.0, 35.0, 42.5, 50.0, 55.5];
    let xs: Vec<f64> = (0..spans)
        .flat_map(|s| offsets.iter().map(move |d| s as f64 * span + d))
        .collect();
    let p = PointSampler::new(&basis, &xs, Some(span), Isa::default());
    let mut sc = p.scratch();
    let q: Vec<f64> = (0..n).map(|k| 1e-3 / (1.0 + k as f64)).collect();
    let mut u = vec![0.0; xs.len()];
    c.bench_function("sampler/gather/1200x240", |b| {
        b.iter(|| p.gather(black_box(&q), 1, &mut u, &mut sc))
    });
    let f: Vec<f64> = (0..xs.len()).map(|i| (i % 7) as f64).collect();
    let mut a = vec![0.0; n];
    c.bench_function("sampler/scatter/1200x240", |b| {
        b.iter(|| p.scatter_add(black_box(&f), 1, &mut a, &mut sc))
    });
}

/// Compiling a case into its set-up (validation, statics, elements, the plan).
fn build(c: &mut Criterion) {
    let (case, _) = presets::load("stitched-2018-like").unwrap();
    c.bench_function("build/stitched-2018-like", |b| {
        b.iter(|| Setup::from_case(black_box(&case)).unwrap())
    });
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20);
    targets = zoo_steps, preset_step, stages, realtime_step, sampler, build
}
criterion_main!(benches);
