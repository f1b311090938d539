//! Energy density (Eq. 20, consistent form) and the EVA criteria (Eq. 21).

use pcsim_core::analysis::energy::{integrate, modal_energy, DensityGrid};
use pcsim_core::analysis::eva::{eva_by_fraction, eva_by_step, window_energy};
use pcsim_core::compile::{Setup, Stepper};
use pcsim_core::input::case::Damping;
use pcsim_core::model::{Direction, ModelBuilder, WireRole};

fn wire(l: f64, n: usize) -> Setup {
    Setup::from_builder(
        ModelBuilder::single_wire(l, n, 1.35, 20_000.0, 195.0)
            .damping(&Damping::Modal { ratio: 0.0 })
            .run(0.0, 1.0, 1.0, 2e-4)
            .build(),
    )
}

#[test]
fn single_mode_energy_is_half_m_v2_plus_half_k_x2() {
    let (l, n) = (120.0, 40);
    let setup = wire(l, n);
    let model = &setup.model;
    let b = model.block(WireRole::Contact, Direction::Vertical).unwrap();
    let mut st = Stepper::new(&setup).unwrap().state;
    let k = 7; // mode number 7
    st.q_mut(model, b)[k - 1] = 0.013;
    st.qdot_mut(model, b)[k - 1] = -0.21;
    let mut grid = DensityGrid::new(model, 4).unwrap();
    let mut e = vec![0.0; grid.n_points()];
    grid.density(model, &st, &mut e);
    let kap = k as f64 * std::f64::consts::PI / l;
    let m = 1.35 * l / 2.0;
    let stiff = l / 2.0 * (20_000.0 * kap * kap + 195.0 * kap.powi(4));
    let expect = 0.5 * m * 0.21f64.powi(2) + 0.5 * stiff * 0.013f64.powi(2);
    let got = integrate(&e, grid.dx());
    assert!((got - expect).abs() < 1e-10 * expect, "{got} vs {expect}");
    // And pointwise: at x the density is ½ρA v² sin² + ½T (qκ cos)² + ½EI (qκ² sin)².
    let j = 123;
    let x = j as f64 * grid.dx();
    let (s, c) = (kap * x).sin_cos();
    let pointwise = 0.5 * 1.35 * (0.21 * s).powi(2)
        + 0.5 * 20_000.0 * (0.013 * kap * c).powi(2)
        + 0.5 * 195.0 * (0.013 * kap * kap * s).powi(2);
    assert!(
        (e[j] - pointwise).abs() < 1e-9 * pointwise.max(1e-12),
        "{} vs {pointwise}",
        e[j]
    );
}

#[test]
fn free_undamped_wire_keeps_its_integrated_energy() {
    // Both wires, many modes excited, no damping, no point elements: ∫E dx stays constant (to
    // the integrator's O(Δt²) energy error) and equals the modal energy at every sample.
    let (l, n) = (200.0, 150);
    let setup = Setup::from_builder(
        ModelBuilder::single_wire(l, n, 1.35, 20_000.0, 195.0)
            .uncoupled_messenger(1.07, 16_000.0, 131.7)
            .run(0.0, 1.0, 1.0, 2e-4)
            .build(),
    );
    let model = setup.model.clone();
    let c = model.block(WireRole::Contact, Direction::Vertical).unwrap();
    let m = model
        .block(WireRole::Messenger, Direction::Vertical)
        .unwrap();
    let mut s = Stepper::new(&setup).unwrap();
    for i in 0..n {
        s.state.q_mut(&model, c)[i] =
            0.02 / (1.0 + i as f64).powi(2) * if i % 3 == 0 { 1.0 } else { -0.5 };
        s.state.q_mut(&model, m)[i] = 0.01 / (1.0 + i as f64).powi(2);
        s.state.qdot_mut(&model, m)[i] = 0.05 / (1.0 + i as f64);
    }
    let mut grid = DensityGrid::new(&model, 4).unwrap();
    let mut e = vec![0.0; grid.n_points()];
    grid.density(&model, &s.state, &mut e);
    let e0 = integrate(&e, grid.dx());
    assert!(e0 > 0.05, "{e0}");
    let mut worst: f64 = 0.0;
    for step in 1..=20_000 {
        s.step();
        if step % 1000 == 0 {
            grid.density(&model, &s.state, &mut e);
            let total = integrate(&e, grid.dx());
            assert!((total - modal_energy(&model, &s.state)).abs() < 1e-9 * total);
            worst = worst.max((total - e0).abs() / e0);
        }
    }
    assert!(worst < 1e-3, "integrated energy drifts by {worst}");
}

#[test]
fn eva_criteria_on_a_synthetic_exponential_profile() {
    // E(x) = A e^{−|x − x_p|/λ}: E(d) = 2Aλ (1 − e^{−d/2λ}), total 2Aλ (far from the ends).
    let (a, lam, xp, l, dx) = (0.5, 20.0, 1000.0, 2000.0, 0.05);
    let dens: Vec<f64> = (0..=(l / dx) as usize)
        .map(|j| a * (-((j as f64 * dx - xp).abs()) / lam).exp())
        .collect();
    let step = 2.0;
    let d: Vec<f64> = (1..=600).map(|i| i as f64 * step).collect();
    let e = window_energy(&dens, dx, xp, &d);
    let exact = |w: f64| 2.0 * a * lam * (1.0 - (-w / (2.0 * lam)).exp());
    for (w, v) in d.iter().zip(&e) {
        assert!(
            (v - exact(*w)).abs() < 1e-4 * exact(*w),
            "E({w}) = {v} vs {}",
            exact(*w)
        );
    }
    let total = 2.0 * a * lam;
    // Fraction criterion: d = 2λ ln(1/(1 − f)).
    let f = eva_by_fraction(&d, &e, total, 0.99).unwrap();
    let want = 2.0 * lam * 100.0f64.ln();
    assert!((f - want).abs() < 0.05, "fraction EVA {f} vs {want}");
    // Step criterion: first d_i with E(d_i + Δd) − E(d_i) < tol, i.e.
    // 2Aλ e^{−d/2λ} (1 − e^{−Δd/2λ}) < tol  ⇒  d > 2λ ln(2Aλ (1 − e^{−Δd/2λ}) / tol).
    let tol = 0.01;
    let s = eva_by_step(&d, &e, tol).unwrap();
    let bound = 2.0 * lam * (2.0 * a * lam * (1.0 - (-step / (2.0 * lam)).exp()) / tol).ln();
    let want = d.iter().copied().find(|&w| w > bound).unwrap();
    assert_eq!(s, want, "step EVA {s}, analytic threshold {bound}");
    // The step criterion depends on Δd; the fraction one does not.
    let d10: Vec<f64> = (1..=120).map(|i| i as f64 * 10.0).collect();
    let e10 = window_energy(&dens, dx, xp, &d10);
    assert!(eva_by_step(&d10, &e10, tol).unwrap() > s);
    assert!((eva_by_fraction(&d10, &e10, total, 0.99).unwrap() - want_fraction(lam)).abs() < 1.0);
}

fn want_fraction(lam: f64) -> f64 {
    2.0 * lam * 100.0f64.ln()
}

/// An observer that has seen enough after `after` steps.
struct Enough {
    seen: usize,
    after: usize,
}

impl pcsim_core::solve::Observer for Enough {
    fn observe(
        &mut self,
        _: &pcsim_core::solve::CompiledModel,
        _: &mut pcsim_core::solve::State,
        _: &pcsim_core::solve::Workspace,
    ) -> Result<(), pcsim_core::SimError> {
        self.seen += 1;
        Ok(())
    }

    fn finished(&self) -> bool {
        self.seen >= self.after
    }
}

#[test]
fn the_run_loop_stops_when_every_observer_has_seen_enough() {
    let setup = pcsim_core::zoo::stitched_three_spans();
    let n = setup.n_steps();
    let integ = setup.integrator().unwrap();
    let run = |observers: &mut [&mut dyn pcsim_core::solve::Observer]| {
        let mut st = integ.initial_state(setup.plan.start_m);
        let mut ws = integ.workspace();
        pcsim_core::solve::run(&integ, &mut st, &mut ws, n, observers, &mut |_| true).unwrap()
    };
    let mut a = Enough { seen: 0, after: 37 };
    assert_eq!(run(&mut [&mut a]).steps, 37);
    assert_eq!(a.seen, 37);
    // One observer that wants the whole run keeps it going.
    let (mut a, mut b) = (
        Enough { seen: 0, after: 37 },
        Enough {
            seen: 0,
            after: usize::MAX,
        },
    );
    assert_eq!(run(&mut [&mut a, &mut b]).steps, n as u64);
    assert_eq!((a.seen, b.seen), (n, n));
    // No observer: every step.
    assert_eq!(run(&mut []).steps, n as u64);
}

#[test]
fn the_energy_run_stops_after_the_section_with_a_whole_runs_outputs() {
    use pcsim_core::analysis::eva::{run_eva, simulate_with_eva, EvaSettings};
    let setup = pcsim_core::zoo::stitched_three_spans();
    let s = EvaSettings::default();
    let (mut last_alone, mut last_beside) = (0.0, 0.0);
    let alone = run_eva(&setup, &s, &mut |f| {
        if f < 1.0 {
            last_alone = f;
        }
        true
    })
    .unwrap();
    let (out, beside) = simulate_with_eva(&setup, &s, &mut |f| {
        if f < 1.0 {
            last_beside = f;
        }
        true
    })
    .unwrap();
    // The same energy views whether the run stops after the section or records to its end, and
    // the same record as a run without the energy sampler.
    assert_eq!(alone, beside);
    assert!(alone.samples > 5, "{} samples", alone.samples);
    assert_eq!(out, pcsim_core::simulate(&setup, &mut |_| true).unwrap());
    // The energy run alone stopped once the pantograph left the section (60–120 m of a run from
    // 20 m to 160 m: 5/7 of the steps), the recording one ran to the end.
    let stop = (setup.plan.analysis_m[1] - 20.0) / (160.0 - 20.0);
    assert!(
        last_alone > stop - 0.01 && last_alone < stop + 0.01,
        "stopped at {last_alone} of the run, the section ends at {stop}"
    );
    // (progress is reported every 256 steps: the last report before the end is within 256 steps
    // of it)
    let to_end = 1.0 - 256.0 / setup.n_steps() as f64;
    assert!(last_beside >= to_end, "{last_beside} < {to_end}");
}

/// Issue 53, item 4: the snapshot's EVA is also taken at `span_positions` positions evenly
/// across the span that holds the snapshot, from its first support; the row gives the band.
/// The positions are the span's, the one at the snapshot gives the snapshot's own EVA, the band
/// holds it, and the run goes on until the last position is passed.
#[test]
fn issue_53_4_the_eva_is_taken_across_the_snapshots_span() {
    use pcsim_core::analysis::eva::{run_eva, EvaRow, EvaSettings};
    let setup = pcsim_core::zoo::stitched_three_spans();
    let supports = setup.model.supports_m.clone();
    let mid = 0.5 * setup.model.length_m();
    let span = supports
        .windows(2)
        .find(|w| w[0] <= mid && mid < w[1])
        .map(|w| (w[0], w[1]))
        .or_else(|| setup.model.span_m.map(|l| (mid, mid + l)))
        .expect("the zoo model has supports or a span");
    // The snapshot at the span's first support: the first position is the snapshot's.
    let s = EvaSettings {
        snapshot_at_m: Some(span.0),
        ..EvaSettings::default()
    };
    assert_eq!(s.span_positions, 8);
    let o = run_eva(&setup, &s, &mut |_| true).unwrap();
    assert_eq!(o.span_positions_m.len(), 8);
    for (k, x) in o.span_positions_m.iter().enumerate() {
        let want = span.0 + (span.1 - span.0) * k as f64 / 8.0;
        assert!((x - want).abs() < 1e-9, "position {k}: {x} against {want}");
    }
    assert_eq!(o.span_eva_step_m[0], o.snapshot.eva_step_m);
    assert_eq!(o.span_eva_fraction_m[0], o.snapshot.eva_fraction_m);
    // Every position is passed (the run goes on until the last): the step criterion has an
    // answer at each (the fraction criterion may not, past the model's middle, where a window
    // centred on the pantograph cannot hold the far end within the largest window).
    assert!(
        o.span_eva_step_m.iter().all(Option::is_some),
        "every position passed: {:?}",
        o.span_eva_step_m
    );
    let row = EvaRow::new(0, 250.0, 20.0, "case", &o);
    let (lo, hi) = (
        row.eva_step_span_min_m.unwrap(),
        row.eva_step_span_max_m.unwrap(),
    );
    let at = o.snapshot.eva_step_m.unwrap();
    assert!(lo <= at && at <= hi, "{lo} ≤ {at} ≤ {hi}");
    assert!(lo < hi, "the EVA moves across the span: {lo} to {hi}");
    // The fraction criterion is not reached past the model's middle here: its band has a lower
    // end and no upper one (never an upper end it did not see).
    if o.span_eva_fraction_m.iter().any(Option::is_none) {
        assert!(row.eva_fraction_span_min_m.is_some());
        assert_eq!(row.eva_fraction_span_max_m, None);
    }
    assert!(row.to_csv().split(',').count() == EvaRow::HEADER.split(',').count());
    // None asked: no positions, empty band.
    let none = run_eva(
        &setup,
        &EvaSettings {
            span_positions: 0,
            ..s
        },
        &mut |_| true,
    )
    .unwrap();
    assert!(none.span_positions_m.is_empty());
    assert_eq!(
        EvaRow::new(0, 250.0, 20.0, "case", &none).eva_step_span_min_m,
        None
    );
}
