//! Lateral and torsional motion, stagger, crosswind and ice (issue 12): exact solutions, the
//! generated wind field against its targets, decoupling from the vertical model, and the energy
//! balance with the wind doing work.

use pcsim_core::analysis::energy::{
    dissipation_rate, integrate, modal_energy, system_energy, DensityGrid,
};
use pcsim_core::compile::{Setup, Stepper};
use pcsim_core::input::case::Damping;
use pcsim_core::model::elements::dropper::{dropper_energy_3d, dropper_force_3d};
use pcsim_core::model::wind_field::{davenport_coherence, FieldSpec, SpectrumModel, WindField};
use pcsim_core::model::{Direction, ModelBuilder, WireRole};
use pcsim_core::{presets, run_case, Case};

/// The exact static deflection of a pinned tensioned beam under a uniform load `q`:
/// `w = q/T [x(L−x)/2 + (EI/T)(cosh(λ(x − L/2))/cosh(λL/2) − 1)]`, `λ = √(T/EI)`.
fn tensioned_beam_deflection(q: f64, t: f64, ei: f64, l: f64, x: f64) -> f64 {
    let lam = (t / ei).sqrt();
    let c = ((lam * (x - 0.5 * l)).cosh() / (lam * 0.5 * l).cosh()) - 1.0;
    q / t * (0.5 * x * (l - x) + ei / t * c)
}

fn lateral_at(setup: &Setup, st: &pcsim_core::solve::State, x: f64) -> f64 {
    let m = &setup.model;
    let b = m.block(WireRole::Contact, Direction::Lateral).unwrap();
    let q = st.q(m, b);
    let basis = m.layout.basis(b);
    let mut row = vec![0.0; q.len()];
    basis.eval(q, x, &mut row)
}

#[test]
fn uniform_lateral_load_gives_the_tensioned_beam_deflection() {
    // One 60 m wire, 20 kN, EI 195 N·m², 8 N/m: 90 mm at mid-span (q L²/8T).
    let (l, t, ei, q) = (60.0, 20_000.0, 195.0, 8.0);
    let setup = Setup::from_builder(
        ModelBuilder::single_wire(l, 120, 1.35, t, ei)
            .lateral()
            .uniform_lateral_load(q)
            .run(0.0, 1.0, 0.2, 1e-3)
            .build(),
    );
    let mut s = Stepper::new(&setup).unwrap();
    let peak = tensioned_beam_deflection(q, t, ei, l, 0.5 * l);
    assert!((peak - q * l * l / (8.0 * t)).abs() < 0.01 * peak);
    for i in 1..20 {
        let x = i as f64 * l / 20.0;
        let want = tensioned_beam_deflection(q, t, ei, l, x);
        let got = lateral_at(&setup, &s.state, x);
        assert!(
            (got - want).abs() < 0.01 * want.abs().max(0.05 * peak),
            "x = {x}: {got} vs {want}"
        );
    }
    // It is an equilibrium of the dynamics: 200 steps leave it where it is.
    for _ in 0..200 {
        s.integ.step(&mut s.state, &mut s.ws);
    }
    let got = lateral_at(&setup, &s.state, 0.5 * l);
    assert!((got - peak).abs() < 1e-6 * peak, "{got} vs {peak}");
    // A wrong answer is told apart: half the tension would double the deflection.
    assert!((tensioned_beam_deflection(q, 0.5 * t, ei, l, 0.5 * l) - peak).abs() > 0.5 * peak);
}

#[test]
fn uniform_lateral_load_between_registration_points() {
    // Two 60 m spans held at the middle by a stiff registration: q x(S−x)/2T in each span.
    let (s_len, t, q) = (60.0, 20_000.0, 8.0);
    let setup = Setup::from_builder(
        ModelBuilder::single_wire(2.0 * s_len, 240, 1.35, t, 1e-3)
            .lateral()
            .registration(s_len, 1e9)
            .uniform_lateral_load(q)
            // A step the 1e9 N/m registration allows (the coupled stability check refuses 1 ms).
            .run(0.0, s_len, 1.0, 2e-5)
            .build(),
    );
    let st = Stepper::new(&setup).unwrap().state;
    let peak = q * s_len * s_len / (8.0 * t);
    for i in 1..40 {
        let x = i as f64 * 2.0 * s_len / 40.0;
        let xs = x % s_len;
        let want = q * xs * (s_len - xs) / (2.0 * t);
        let got = lateral_at(&setup, &st, x);
        assert!(
            (got - want).abs() < 0.01 * peak,
            "x = {x}: {got} vs {want} (peak {peak})"
        );
    }
}

/// Period of the first zero crossings of a sampled signal, s.
fn period(x: &[f64], dt: f64) -> f64 {
    let mut crossings = Vec::new();
    for i in 1..x.len() {
        if x[i - 1] > 0.0 && x[i] <= 0.0 {
            let f = x[i - 1] / (x[i - 1] - x[i]);
            crossings.push((i as f64 - 1.0 + f) * dt);
        }
    }
    assert!(crossings.len() >= 3, "too few crossings");
    (crossings[crossings.len() - 1] - crossings[0]) / (crossings.len() - 1) as f64
}

#[test]
fn torsional_frequencies_follow_gj_and_rho_ip() {
    // AC-120: GI_p 103 N·m², ρI_p 2.0e-5 kg·m (reference README §3.6); 60 m: f_k = k c / 2L,
    // c = √(GI_p/ρI_p) ≈ 2270 m/s, so f_1 ≈ 18.9 Hz.
    let (l, gj, ip): (f64, f64, f64) = (60.0, 103.0, 2.0e-5);
    let c = (gj / ip).sqrt();
    let setup = Setup::from_builder(
        ModelBuilder::single_wire(l, 60, 1.06, 21_000.0, 126.0)
            .lateral()
            .torsion(gj, ip)
            .run(0.0, 1.0, 1.0, 1e-3)
            .build(),
    );
    let m = &setup.model;
    let b = m.block(WireRole::Contact, Direction::Torsional).unwrap();
    // The series: every mode's frequency.
    let s = m.series(b);
    for k in 0..60 {
        let f = (s.stiffness[k] / s.mass[k]).sqrt() / (2.0 * std::f64::consts::PI);
        let want = (k + 1) as f64 * c / (2.0 * l);
        assert!(
            (f - want).abs() < 1e-9 * want,
            "mode {}: {f} vs {want}",
            k + 1
        );
    }
    // The integrated motion: modes 1 and 2 at Δt = 1 ms, mode 3 at 0.25 ms (the trapezoidal
    // map lags by (ωΔt)²/12), each within 1 %.
    for (mode, dt) in [(1usize, 1e-3), (2, 1e-3), (3, 2.5e-4)] {
        let setup = Setup::from_builder(
            ModelBuilder::single_wire(l, 60, 1.06, 21_000.0, 126.0)
                .lateral()
                .torsion(gj, ip)
                .run(0.0, 1.0, 1.0, dt)
                .build(),
        );
        let mut st = Stepper::new(&setup).unwrap();
        st.state.q_mut(&setup.model, b)[mode - 1] = 0.01;
        let mut x = Vec::new();
        for _ in 0..(0.5 / dt) as usize {
            st.integ.step(&mut st.state, &mut st.ws);
            x.push(st.state.q(&setup.model, b)[mode - 1]);
        }
        let f = 1.0 / period(&x, dt);
        let want = mode as f64 * c / (2.0 * l);
        assert!(
            (f - want).abs() < 0.01 * want,
            "mode {mode} at Δt {dt}: {f} Hz vs {want} Hz"
        );
    }
}

/// The 3D preset over a few spans at low speed.
fn short_3d(speed_kmh: f64, end_m: f64) -> Case {
    let mut c = presets::load("stitched-2018-like-3d").unwrap().0;
    c.pantographs.truncate(1);
    c.run.speed_kmh = speed_kmh;
    c.run.start_m = 250.0;
    c.run.end_m = end_m;
    c.run.analysis_m = [300.0, end_m];
    // The registrations from 300 m on, less than a span after the start: the checks here are
    // positions, not force statistics.
    c.run.allow_start_transient = true;
    c
}

#[test]
fn the_contact_point_sits_at_the_stagger_at_the_registration_points() {
    let case = short_3d(50.0, 430.0);
    let out = run_case(&case, &mut |_| true).unwrap();
    let p = &out.pantographs[0];
    let stagger = case.catenary.lateral.as_ref().unwrap();
    let mut seen = 0;
    for (k, &x) in p.position_m.iter().enumerate() {
        let s = (x / 60.0).round();
        if (x - s * 60.0).abs() < 0.02 && x > 280.0 {
            let want = stagger.stagger_at(s as usize);
            assert!(
                (p.lateral_m[k] - want).abs() < 1e-3,
                "x = {x}: {} vs {want}",
                p.lateral_m[k]
            );
            seen += 1;
        }
    }
    assert!(seen >= 2, "passed {seen} registration points");
    // Half-way between them the wire is on the straight line: zero stagger at mid-span.
    let l = p.lateral.as_ref().unwrap();
    assert!((l.max_lateral_offset_mm - 300.0).abs() < 1.0);
    assert_eq!(l.samples_outside_working_range, 0);
}

#[test]
fn wind_spectrum_matches_its_target_band_by_band() {
    let xs: Vec<f64> = (0..16).map(|i| 40.0 * i as f64).collect();
    let (sigma, u) = (2.5, 22.0);
    let spectra = [
        SpectrumModel::Kaimal {
            integral_length_m: 30.0,
            mean_m_s: u,
        },
        SpectrumModel::Davenport {
            reference_m_s: 25.0,
        },
    ];
    for sp in spectra {
        let (dt, n_t) = (0.05, 2048);
        let df = 1.0 / (n_t as f64 * dt);
        let bands = [(0.05, 0.2), (0.2, 0.5), (0.5, 1.0), (1.0, 2.0), (2.0, 5.0)];
        let mut got = vec![0.0; bands.len()];
        let seeds = 8;
        for seed in 0..seeds {
            let f = WindField::generate(
                &xs,
                &FieldSpec {
                    spectrum: sp,
                    sigma_m_s: sigma,
                    mean_m_s: u,
                    coherence_decay: 8.0,
                },
                dt,
                n_t as f64 * dt - 3.0 * dt,
                seed,
            );
            assert_eq!(f.n_t, n_t);
            for j in 0..xs.len() {
                let spec = periodogram(f.series(j), dt);
                for (b, &(lo, hi)) in bands.iter().enumerate() {
                    got[b] += spec
                        .iter()
                        .enumerate()
                        .filter(|(l, _)| {
                            let fr = *l as f64 * df;
                            fr >= lo && fr < hi
                        })
                        .map(|(_, p)| p * df)
                        .sum::<f64>();
                }
            }
        }
        for (b, &(lo, hi)) in bands.iter().enumerate() {
            let mean = got[b] / (seeds as usize * xs.len()) as f64;
            // The target's variance in the band, on the same frequency grid.
            let want: f64 = (1..n_t / 2)
                .map(|l| l as f64 * df)
                .filter(|&fr| fr >= lo && fr < hi)
                .map(|fr| sigma * sigma * sp.normalised(fr) * df)
                .sum();
            assert!(
                (mean - want).abs() < 0.10 * want,
                "{} band {lo}-{hi} Hz: {mean} vs {want} m²/s²",
                sp.name()
            );
        }
    }
}

/// One-sided periodogram `|X_l|² · 2 dt / n` at `f_l = l / (n dt)`, `X_l = Σ x_k e^{−2πi lk/n}`
/// (the DFT by rustfft's FFT: the same sums as the direct one, which took 10 s here).
fn periodogram(x: &[f64], dt: f64) -> Vec<f64> {
    use rustfft::num_complex::Complex;
    let n = x.len();
    let mut buf: Vec<Complex<f64>> = x.iter().map(|&v| Complex::new(v, 0.0)).collect();
    rustfft::FftPlanner::<f64>::new()
        .plan_fft_forward(n)
        .process(&mut buf);
    let mut p = vec![0.0; n / 2];
    for (l, pl) in p.iter_mut().enumerate().skip(1) {
        *pl = 2.0 * dt / n as f64 * buf[l].norm_sqr();
    }
    p
}

#[test]
fn wind_coherence_matches_davenport() {
    let (u, decay, dt, n_t) = (22.0, 8.0, 0.05, 1024);
    let xs = [0.0, 2.5, 5.0, 10.0];
    let df = 1.0 / (n_t as f64 * dt);
    let sp = SpectrumModel::Kaimal {
        integral_length_m: 30.0,
        mean_m_s: u,
    };
    // Cross-spectra averaged over 160 seeds and about 16 frequencies per band (about 2500
    // samples: the estimate's own scatter is then about 0.02), around 0.5, 1 and 2 Hz.
    let bands = [(0.35, 0.65), (0.85, 1.15), (1.85, 2.15)];
    for (pair, &dx) in [(1usize, 2.5), (2, 5.0), (3, 10.0)]
        .iter()
        .map(|(j, d)| (j, d))
    {
        for &(lo, hi) in &bands {
            let (mut sxy_re, mut sxy_im, mut sxx, mut syy) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
            for seed in 0..160 {
                let f = WindField::generate(
                    &xs,
                    &FieldSpec {
                        spectrum: sp,
                        sigma_m_s: 2.0,
                        mean_m_s: u,
                        coherence_decay: decay,
                    },
                    dt,
                    n_t as f64 * dt - 3.0 * dt,
                    100 + seed,
                );
                let (a, b) = (f.series(0), f.series(*pair));
                let lo_l = (lo / df).ceil() as usize;
                let hi_l = (hi / df).floor() as usize;
                for l in lo_l..=hi_l {
                    let (ar, ai) = dft(a, l);
                    let (br, bi) = dft(b, l);
                    sxy_re += ar * br + ai * bi;
                    sxy_im += ai * br - ar * bi;
                    sxx += ar * ar + ai * ai;
                    syy += br * br + bi * bi;
                }
            }
            let coh = (sxy_re * sxy_re + sxy_im * sxy_im).sqrt() / (sxx * syy).sqrt();
            let want = davenport_coherence(decay, 0.5 * (lo + hi), dx, u);
            assert!(
                (coh - want).abs() < 0.05,
                "Δx {dx} m, {lo}-{hi} Hz: coherence {coh} vs {want}"
            );
        }
    }
}

fn dft(x: &[f64], l: usize) -> (f64, f64) {
    let n = x.len();
    let (mut re, mut im) = (0.0, 0.0);
    for (k, v) in x.iter().enumerate() {
        let a = -2.0 * std::f64::consts::PI * (l * k) as f64 / n as f64;
        re += v * a.cos();
        im += v * a.sin();
    }
    (re, im)
}

#[test]
fn the_same_seed_gives_the_same_wind_and_another_seed_does_not() {
    let xs: Vec<f64> = (1..50).map(|i| 5.0 * i as f64).collect();
    let sp = SpectrumModel::Davenport {
        reference_m_s: 25.0,
    };
    let a = WindField::generate(
        &xs,
        &FieldSpec {
            spectrum: sp,
            sigma_m_s: 2.5,
            mean_m_s: 22.0,
            coherence_decay: 8.0,
        },
        0.02,
        20.0,
        7,
    );
    let b = WindField::generate(
        &xs,
        &FieldSpec {
            spectrum: sp,
            sigma_m_s: 2.5,
            mean_m_s: 22.0,
            coherence_decay: 8.0,
        },
        0.02,
        20.0,
        7,
    );
    let c = WindField::generate(
        &xs,
        &FieldSpec {
            spectrum: sp,
            sigma_m_s: 2.5,
            mean_m_s: 22.0,
            coherence_decay: 8.0,
        },
        0.02,
        20.0,
        8,
    );
    let bits = |f: &WindField| f.u.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&a), bits(&b));
    assert_ne!(bits(&a), bits(&c));
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs().max(1e-12)
}

#[test]
fn all_directions_without_wind_or_stagger_leave_the_vertical_statistics_unchanged() {
    let mut vertical = presets::load("stitched-2018-like").unwrap().0;
    vertical.pantographs.truncate(1);
    vertical.run.end_m = 900.0;
    vertical.run.analysis_m = [480.0, 900.0];
    let mut all = presets::load("stitched-2018-like-3d").unwrap().0;
    all.pantographs.truncate(1);
    all.run.end_m = 900.0;
    all.run.analysis_m = [480.0, 900.0];
    let a = run_case(&vertical, &mut |_| true).unwrap();
    for stagger in [0.0, 0.3] {
        all.catenary.lateral.as_mut().unwrap().stagger_m = Some(stagger);
        let b = run_case(&all, &mut |_| true).unwrap();
        let (sa, sb) = (
            a.pantographs[0].stats.unwrap(),
            b.pantographs[0].stats.unwrap(),
        );
        for (x, y, what) in [
            (sa.mean_n, sb.mean_n, "mean"),
            (sa.std_n, sb.std_n, "σ"),
            (sa.actual_max_n, sb.actual_max_n, "max"),
            (sa.actual_min_n, sb.actual_min_n, "min"),
            (
                sa.max_uplift_at_support_mm,
                sb.max_uplift_at_support_mm,
                "uplift",
            ),
        ] {
            assert!(rel(y, x) < 1e-9, "stagger {stagger}: {what} {y} vs {x}");
        }
        // Still air: the wire stays on its static line; no blow-out.
        assert!(sb.max_contact_wire_blowout_mm.unwrap() < 1e-6);
    }
}

#[test]
fn the_dropper_pendulum_law_is_the_derivative_of_its_energy() {
    // The documented coupling of lateral and vertical motion: T δ / L laterally, Eq. 15 at the
    // stretched length vertically, the clamp's moment; slack droppers carry nothing.
    let (f0, k, len, ecc) = (120.0, 1e5, 1.1, 0.008);
    for &(e, d, phi) in &[
        (0.0, 0.02, 0.0),
        (-0.0005, 0.03, 0.05),
        (0.001, -0.01, -0.1),
    ] {
        let (df, fl, m, slack) = dropper_force_3d(f0, k, len, ecc, e, d, phi);
        let h = 1e-7;
        let v = |e: f64, d: f64, p: f64| dropper_energy_3d(f0, k, len, ecc, e, d, p);
        let de = (v(e + h, d, phi) - v(e - h, d, phi)) / (2.0 * h);
        let dd = (v(e, d + h, phi) - v(e, d - h, phi)) / (2.0 * h);
        let dp = (v(e, d, phi + h) - v(e, d, phi - h)) / (2.0 * h);
        assert!(
            (df - de).abs() < 1e-4 * (1.0 + de.abs()),
            "vertical {df} vs {de}"
        );
        assert!(
            (fl - dd).abs() < 1e-4 * (1.0 + dd.abs()),
            "lateral {fl} vs {dd}"
        );
        // δ depends on φ through the clamp: ∂V/∂φ = −e_d ∂V/∂δ|direct + T e_d φ.
        let t = f0 + df;
        assert!((m - (ecc * fl - t * ecc * phi)).abs() < 1e-12);
        assert!(
            (dp - (t * ecc * phi)).abs() < 1e-3 * (1.0 + dp.abs()),
            "{dp}"
        );
        assert!(!slack);
        assert!((fl - t * d / len).abs() < 1e-12);
    }
    let (_, fl, m, slack) = dropper_force_3d(f0, k, len, ecc, -0.01, 0.05, 0.0);
    assert!(slack && fl == 0.0 && m == 0.0);
}

#[test]
fn energy_balance_holds_with_the_wind_doing_work() {
    let mut case = presets::load("stitched-2018-like-3d-crosswind").unwrap().0;
    case.catenary.spans = 6;
    case.pantographs.truncate(1);
    case.run.start_m = 150.0;
    case.run.end_m = 250.0;
    case.run.analysis_m = [150.0, 250.0];
    case.run.allow_start_transient = true; // an energy balance, not statistics
    case.run.modes = Some(240);
    case.run.dt_s = 2.5e-4;
    if let Some(w) = case.wind.as_mut() {
        w.turbulence_intensity = 0.2;
    }
    let mut setup = Setup::from_case(&case).unwrap();
    setup.plan.speed_m_s = 0.0;
    let Stepper {
        integ,
        state: mut st,
        mut ws,
    } = Stepper::new(&setup).unwrap();
    let e0 = system_energy(integ.compiled(), &st, &mut ws).total();
    let dt = integ.dt_s();
    let mut d_prev = dissipation_rate(integ.compiled(), &st, &mut ws);
    let mut p_prev = 0.0;
    let (mut dissipated, mut work) = (0.0, 0.0);
    let (mut worst, mut scale): (f64, f64) = (0.0, 0.0);
    for i in 0..8000 {
        integ.step(&mut st, &mut ws);
        let d = dissipation_rate(integ.compiled(), &st, &mut ws);
        dissipated += 0.5 * dt * (d + d_prev);
        d_prev = d;
        let p = integ.compiled().wind_power(&st, &ws);
        if i > 0 {
            work += 0.5 * dt * (p + p_prev);
        }
        p_prev = p;
        let e = system_energy(integ.compiled(), &st, &mut ws).total();
        worst = worst.max((e - e0 + dissipated - work).abs());
        scale = scale.max((e - e0).abs()).max(dissipated).max(work.abs());
    }
    assert!(scale > 0.1, "the wind should do work: {scale} J");
    assert!(
        worst < 5e-3 * scale,
        "energy residual {worst} J against {scale} J"
    );
}

#[test]
fn lateral_and_torsional_energy_density_integrates_to_the_modal_energy() {
    let (l, n) = (120.0, 40);
    let setup = Setup::from_builder(
        ModelBuilder::single_wire(l, n, 1.06, 21_000.0, 126.0)
            .lateral()
            .torsion(103.0, 2.0e-5)
            .damping(&Damping::Modal { ratio: 0.0 })
            .build(),
    );
    let m = &setup.model;
    let mut st = Stepper::new(&setup).unwrap().state;
    for dir in [Direction::Lateral, Direction::Torsional] {
        let b = m.block(WireRole::Contact, dir).unwrap();
        for k in 0..n {
            st.q_mut(m, b)[k] = 1e-3 / (1.0 + k as f64);
            st.qdot_mut(m, b)[k] = 0.02 * ((k % 3) as f64 - 1.0);
        }
    }
    let mut grid = DensityGrid::new(m, 4).unwrap();
    let mut e = vec![0.0; grid.n_points()];
    grid.density(m, &st, &mut e);
    let total = integrate(&e, grid.dx());
    let modal = modal_energy(m, &st);
    assert!(modal > 0.0);
    assert!((total - modal).abs() < 1e-9 * modal, "{total} vs {modal}");
}

#[test]
fn steady_crosswind_blow_off_lies_between_the_design_formulas() {
    // The quasi-static design formula (EN 50119 form, reference README §3.6): mid-span blow-off
    // q S²/8T of a wire between fixed registration points. The droppers tie the contact wire to
    // the messenger, which carries a larger load per tension, so the contact wire's blow-off
    // lies between the formula for the contact wire alone and for the messenger alone; the
    // registration springs (1e5 N/m) add their own give at the supports.
    let mut case = presets::load("stitched-2018-like-3d-crosswind").unwrap().0;
    case.wind.as_mut().unwrap().turbulence_intensity = 0.0;
    let setup = Setup::from_case(&case).unwrap();
    let s = Stepper::new(&setup).unwrap();
    let wl = setup.model.wind.as_ref().unwrap();
    let c = &case.catenary;
    let (span, tc, tm) = (c.span_m, c.contact_wire.tension_n, c.messenger.tension_n);
    let q = |w: usize| wl.wires[w].lateral_m * wl.mean_pressure(w);
    let (qm, qc) = (q(0), q(1));
    let contact_alone = qc * span * span / (8.0 * tc);
    let messenger_alone = qm * span * span / (8.0 * tm);
    let together = (qc + qm) * span * span / (8.0 * (tc + tm));
    // Mid-spans inside the analysis section.
    let mut mids = Vec::new();
    let mut k = 0.5;
    while k * span < case.run.analysis_m[1] {
        if k * span > case.run.analysis_m[0] {
            mids.push(lateral_at(&setup, &s.state, k * span));
        }
        k += 1.0;
    }
    let mean = mids.iter().sum::<f64>() / mids.len() as f64;
    eprintln!(
        "blow-off at mid-span {:.1} mm (spread {:.2} mm); q_c {qc:.3} N/m, q_m {qm:.3} N/m; formula: contact alone {:.1} mm, messenger alone {:.1} mm, both wires as one {:.1} mm",
        mean * 1e3,
        (mids.iter().cloned().fold(f64::MIN, f64::max) - mids.iter().cloned().fold(f64::MAX, f64::min)) * 1e3,
        contact_alone * 1e3,
        messenger_alone * 1e3,
        together * 1e3
    );
    assert!(mean > contact_alone && mean < messenger_alone, "{mean}");
    // Every span alike (the model is long enough for the ends not to matter there).
    for m in &mids {
        assert!((m - mean).abs() < 0.01 * mean);
    }
}

#[test]
fn ice_adds_its_annulus_mass_and_widens_the_wire_for_drag() {
    use pcsim_core::compile::model::ice_mass;
    use pcsim_core::input::case::IceCase;
    // 10 mm of glaze (900 kg/m³) on a 12.4 mm wire: ρ π ((d/2 + t)² − (d/2)²) = 0.6334 kg/m.
    let (m, _) = ice_mass(900.0, 0.0124, 0.010);
    let pi = std::f64::consts::PI;
    assert!((m - 900.0 * pi * (0.0162f64.powi(2) - 0.0062f64.powi(2))).abs() < 1e-12);
    assert!((m - 0.6334).abs() < 1e-3);
    let mut case = presets::load("stitched-2018-like-3d-crosswind").unwrap().0;
    case.wind.as_mut().unwrap().turbulence_intensity = 0.0;
    let bare = Setup::from_case(&case).unwrap();
    case.catenary.ice = Some(IceCase {
        density_kg_m3: 900.0,
        contact_wire_m: 0.010,
        messenger_m: 0.010,
    });
    let iced = Setup::from_case(&case).unwrap();
    let cw = |s: &Setup| s.model.wires[1].section.mass_per_m_kg;
    // (the dropper masses smeared into the wire move a little with the iced statics' dropper
    // lengths)
    assert!(
        (cw(&iced) - cw(&bare) - m).abs() < 0.005 * m,
        "{} vs {m}",
        cw(&iced) - cw(&bare)
    );
    // Drag on the iced diameter: 32.4 / 12.4 mm.
    let drag = |s: &Setup| s.model.wind.as_ref().unwrap().wires[1].lateral_m;
    assert!((drag(&iced) / drag(&bare) - 0.0324 / 0.0124).abs() < 1e-9);
}

/// Issue 20, item 2: contact exists only on the head. With a stagger of 0.6 m and a 65 m/s
/// crosswind the wire is blown beyond the ±0.8 m head; there the contact force is zero, the run
/// reports a dewirement (an error-level event), and the statistics differ from the on-head run
/// (they did not: the force was the 0.3 m-stagger run's to the bit). (A static stagger beyond
/// the head, 1.9 m as this test had, is refused before the run since issue 51.)
#[test]
fn contact_exists_only_on_the_head() {
    let mut wide = short_3d(200.0, 700.0);
    wide.run.analysis_m = [360.0, 700.0];
    let hw = match &wide.pantographs[0] {
        pcsim_core::input::case::PantographCase::Lumped {
            head_half_width_m, ..
        } => head_half_width_m.expect("the 3D preset gives the head"),
        _ => unreachable!(),
    };
    let narrow = wide.clone();
    let windy = presets::load("stitched-2018-like-3d-crosswind").unwrap().0;
    wide.wind = windy.wind.map(|w| pcsim_core::input::lateral::WindCase {
        mean_speed_m_s: 65.0,
        ..w
    });
    wide.catenary.messenger.section = windy.catenary.messenger.section;
    wide.catenary.contact_wire.section = windy.catenary.contact_wire.section;
    wide.catenary.lateral.as_mut().unwrap().stagger_m = Some(0.6);
    let on = run_case(&narrow, &mut |_| true).unwrap();
    let off = run_case(&wide, &mut |_| true).unwrap();
    let p = &off.pantographs[0];
    let (mut beyond, mut touching) = (0, 0);
    for (k, z) in p.lateral_m.iter().enumerate() {
        if z.abs() > hw {
            beyond += 1;
            assert_eq!(
                p.force_n[k], 0.0,
                "a force beyond the head at sample {k} (z = {z} m)"
            );
        } else if p.force_n[k] > 0.0 {
            touching += 1;
        }
    }
    assert!(
        beyond > 100 && touching > 100,
        "{beyond} beyond, {touching} touching"
    );
    let errors = pcsim_core::analysis::events::run_errors(&off);
    use pcsim_core::analysis::events::RunErrorKind;
    assert!(
        errors
            .iter()
            .any(|e| e.kind == RunErrorKind::Dewirement && e.message.contains("dewirement")),
        "{errors:?}"
    );
    assert!(pcsim_core::analysis::events::run_errors(&on).is_empty());
    let (s_on, s_off) = (
        on.pantographs[0].stats.unwrap(),
        off.pantographs[0].stats.unwrap(),
    );
    assert_eq!(s_on.loss_of_contact_percent, 0.0);
    eprintln!(
        "on the head: Fm {:.1} N, σ {:.1} N, loss {:.2} %; blown off: Fm {:.1} N, σ {:.1} N, loss {:.2} %",
        s_on.mean_n, s_on.std_n, s_on.loss_of_contact_percent,
        s_off.mean_n, s_off.std_n, s_off.loss_of_contact_percent
    );
    assert!(
        s_off.loss_of_contact_percent > 5.0,
        "{}",
        s_off.loss_of_contact_percent
    );
    // The pantograph leaves and meets the wire again: the force spreads far more.
    assert!(
        s_off.std_n > 1.5 * s_on.std_n,
        "σ {} against {}",
        s_off.std_n,
        s_on.std_n
    );
}

/// Issue 20, item 7: the contact wire's twist at the contact point is an output
/// (`<pantograph>_twist_rad`), present when torsion is modelled and only then; under a crosswind
/// moment it moves, and it is the twist that shifts the contact point: without torsion the
/// column is absent and the other columns stay as they were (the byte goldens, without it).
#[test]
fn the_twist_at_the_contact_point_is_an_output() {
    use pcsim_core::analysis::report::timeseries_columns;
    let mut case = presets::load("stitched-2018-like-3d-crosswind").unwrap().0;
    case.catenary.spans = 8;
    case.pantographs.truncate(1);
    case.run.start_m = 150.0;
    case.run.end_m = 360.0;
    case.run.analysis_m = [210.0, 360.0];
    case.run.modes = Some(320);
    let out = run_case(&case, &mut |_| true).unwrap();
    let p = &out.pantographs[0];
    assert_eq!(p.twist_rad.len(), out.time_s.len());
    assert!(p.twist_rad.iter().all(|t| t.is_finite()));
    let spread = p.twist_rad.iter().cloned().fold(f64::MIN, f64::max)
        - p.twist_rad.iter().cloned().fold(f64::MAX, f64::min);
    assert!(spread > 1e-5, "the twist does not move: {spread} rad");
    let cols = timeseries_columns(&out);
    assert!(cols.iter().any(|c| c.name == "leading_twist_rad"));
    // Lateral motion without torsion: no twist column.
    let mut flat = case.clone();
    flat.run.dofs = vec![
        pcsim_core::input::lateral::Dof::Vertical,
        pcsim_core::input::lateral::Dof::Lateral,
    ];
    flat.wind = None;
    let out = run_case(&flat, &mut |_| true).unwrap();
    assert!(out.pantographs[0].twist_rad.is_empty());
    assert!(!timeseries_columns(&out)
        .iter()
        .any(|c| c.name.ends_with("_twist_rad")));
}

/// Issue 20, item 7: a moving force pushes sideways too. On a wire whose lateral series equals
/// its vertical one (the builder's), a lateral force F gives the lateral deviation at the contact
/// point that the vertical force F gives vertically, step by step (exact: two identical
/// decoupled strings); the lateral force of zero leaves the wire on its centre line.
#[test]
fn a_lateral_force_on_a_moving_force_probe_moves_the_wire_as_the_vertical_one() {
    let build = |fv: f64, fl: f64| {
        Setup::from_builder(
            ModelBuilder::single_wire(100.0, 100, 1.35, 20_000.0, 100.0)
                .lateral()
                .damping(&pcsim_core::input::case::Damping::Modal { ratio: 0.01 })
                .moving_force_3d("probe", fv, fl)
                .run(30.0, 10.0, 1.0, 5e-4)
                .build(),
        )
    };
    let mut s = Stepper::new(&build(120.0, 120.0)).unwrap();
    let mut quiet = Stepper::new(&build(120.0, 0.0)).unwrap();
    let (mut worst, mut peak) = (0.0f64, 0.0f64);
    for _ in 0..1500 {
        s.step();
        quiet.step();
        let (a, q) = (s.samples()[0], quiet.samples()[0]);
        worst = worst.max((a.lateral_m - a.wire_height_m).abs());
        peak = peak.max(a.lateral_m.abs());
        assert!(q.lateral_m.abs() < 1e-15, "{}", q.lateral_m);
        assert_eq!(
            a.wire_height_m, q.wire_height_m,
            "the lateral force leaves the vertical alone"
        );
    }
    assert!(peak > 0.01, "the lateral force moved the wire: {peak} m");
    assert!(
        worst < 1e-12 * peak.max(1.0),
        "lateral against vertical: {worst:e} m"
    );
}

/// Issue 20, item 8: a case with lateral motion below the mode density that the study needs for
/// 1 % on the blow-off is warned about, naming the density and the study; at that density not.
#[test]
fn a_lateral_case_below_the_studied_mode_density_is_warned_about() {
    let (mut c, _) = presets::load("stitched-2018-like-3d").unwrap();
    let has = |c: &Case| {
        Setup::from_case(c)
            .unwrap()
            .warnings
            .iter()
            .any(|w| w.0.contains("modes per metre") && w.0.contains("mode-density study"))
    };
    assert!(has(&c), "0.67 modes per metre");
    c.run.modes = None;
    c.run.modes_per_m = Some(pcsim_core::input::bounds::LATERAL_MODES_PER_M_FOR_1_PCT);
    c.run.dt_s = 8e-4;
    assert!(!has(&c));
}

/// Issue 20, item 5: the crosswind damps the torsion too. The quasi-steady torsional
/// aerodynamic damping `½ρ d² R U C_M'(0)` (R = d/2) is uniform along the wire, so every
/// torsional mode's damping grows by `c L/2`, computed here by hand from the preset's moment table
/// (C_M from −0.02 to 0.02 over ±10°); the vertical and lateral additions are unchanged by it.
#[test]
fn the_crosswind_damps_the_torsion_by_the_moment_slope() {
    let mut case = presets::load("stitched-2018-like-3d-crosswind").unwrap().0;
    case.catenary.spans = 8;
    case.pantographs.truncate(1);
    case.run.modes = Some(320);
    case.run.start_m = 150.0;
    case.run.end_m = 360.0;
    case.run.analysis_m = [210.0, 360.0];
    case.wind.as_mut().unwrap().turbulence_intensity = 0.0;
    let windy = Setup::from_case(&case).unwrap();
    let mut calm = case.clone();
    calm.wind = None;
    let calm = Setup::from_case(&calm).unwrap();
    let wl = windy.model.wind.as_ref().unwrap();
    let rho = case.wind.as_ref().unwrap().air_density_kg_m3;
    let dcm = 0.04 / 20f64.to_radians();
    let l = windy.model.layout.basis(0).length_m();
    let mut seen = 0;
    for ww in &wl.wires {
        let role = windy.model.wires[ww.wire].role;
        // The messenger's moment table is zero and no clamp holds it eccentrically: its torsion
        // is not modelled (issue 23, item 2), with or without the wind.
        if role == WireRole::Messenger {
            assert_eq!(ww.torsional_m2, 0.0);
            assert!(windy.model.block(role, Direction::Torsional).is_none());
            assert!(calm.model.block(role, Direction::Torsional).is_none());
            continue;
        }
        let b = windy.model.block(role, Direction::Torsional).unwrap();
        let added: Vec<f64> = windy
            .model
            .series(b)
            .damping
            .iter()
            .zip(&calm.model.series(b).damping)
            .map(|(w, c)| w - c)
            .collect();
        let section = if role == WireRole::Contact {
            case.catenary.contact_wire.section.as_ref().unwrap()
        } else {
            case.catenary.messenger.section.as_ref().unwrap()
        };
        let slope = if role == WireRole::Contact { dcm } else { 0.0 };
        let dia = section.diameter_m;
        let want = 0.5 * rho * dia * dia * (0.5 * dia) * ww.mean_normal_m_s * slope * l / 2.0;
        for a in &added {
            assert!(
                (a - want).abs() <= 1e-9 * want.abs().max(1e-18),
                "{a} vs {want}"
            );
        }
        if slope != 0.0 {
            assert!(want > 0.0);
            seen += 1;
        }
    }
    assert_eq!(seen, 1, "the contact wire's moment table has a slope");
}

/// Issue 23, item 2: a messenger's torsion is modelled only where a wind moment drives it (no
/// clamp holds it eccentrically): the 3D preset steps five blocks, not six; a moment table on the
/// messenger with a mean moment brings its torsion back (a slope alone damps, it does not drive).
#[test]
fn an_undriven_messenger_torsion_leaves_the_model() {
    let short = |mut c: pcsim_core::Case| {
        c.catenary.spans = 8;
        c.pantographs.truncate(1);
        c.run.modes = Some(320);
        c.run.start_m = 150.0;
        c.run.end_m = 360.0;
        c.run.analysis_m = [210.0, 360.0];
        c
    };
    let case = short(presets::load("stitched-2018-like-3d").unwrap().0);
    let m = Setup::from_case(&case).unwrap().model;
    assert_eq!(m.layout.blocks.len(), 5);
    assert!(m.block(WireRole::Messenger, Direction::Torsional).is_none());
    assert!(m.block(WireRole::Contact, Direction::Torsional).is_some());
    assert!(m.block(WireRole::Messenger, Direction::Lateral).is_some());
    let mut windy = short(presets::load("stitched-2018-like-3d-crosswind").unwrap().0);
    let m = Setup::from_case(&windy).unwrap().model;
    assert!(m.block(WireRole::Messenger, Direction::Torsional).is_none());
    let aero = windy
        .catenary
        .messenger
        .section
        .as_mut()
        .unwrap()
        .aero
        .as_mut()
        .unwrap();
    aero.moment = vec![0.01, 0.01, 0.01]; // a mean moment (C_M(0) ≠ 0)
    let m = Setup::from_case(&windy).unwrap().model;
    assert_eq!(m.layout.blocks.len(), 6);
    assert!(m.block(WireRole::Messenger, Direction::Torsional).is_some());
}

/// Issue 51, item 4: every statistic that decides a verdict is in every study's output. In a
/// crosswind a Monte Carlo study reports the contact point's largest offset, the head's smallest
/// margin and the contact wire's blow-out beside the vertical statistics (they decide a
/// dewirement; σ spreads by 0.002 N there), each from the runs' own values; a vertical case has
/// none of them. A sensitivity study bands them too.
#[test]
fn issue_51_studies_in_wind_report_the_lateral_statistics() {
    use pcsim_core::compile::Budget;
    use pcsim_core::study::montecarlo::{monte_carlo, stat_of, statistics_of, LATERAL_STATS};
    let windy = crate::common::short_preset("stitched-2018-like-3d-crosswind", 8, 250.0);
    let r = monte_carlo(&windy, 2, Some(2), &Budget::default(), &|| {}).unwrap();
    let names = statistics_of(r.iter().map(|x| &x.output));
    for s in LATERAL_STATS {
        assert!(names.contains(&s), "{s} missing from {names:?}");
        for x in &r {
            let want = pcsim_core::analysis::verify::statistic(
                x.output.pantographs[0].stats.as_ref().unwrap(),
                s,
            )
            .unwrap();
            assert_eq!(stat_of(&x.output, 0, s), want);
        }
    }
    let flat = run_case(&short_3d(200.0, 430.0), &mut |_| true).unwrap();
    let vertical = run_case(&crate::common::short_en50318(6, 250.0), &mut |_| true).unwrap();
    assert!(statistics_of([&flat]).contains(&"max_lateral_offset_mm"));
    assert!(!statistics_of([&vertical])
        .iter()
        .any(|s| LATERAL_STATS.contains(s)));
    // The sensitivity's bands hold them too.
    use pcsim_core::analysis::events::AllowedErrors;
    use pcsim_core::analysis::sensitivity::{sensitivity, SensitivitySpec};
    let out = &r[0].output;
    let t = windy.catenary.contact_wire.tension_n;
    let ranged = pcsim_core::input::RangedValue {
        path: "catenary.contact_wire.tension_n".into(),
        value: t,
        low: 0.95 * t,
        high: 1.05 * t,
        source: None,
        range_source: None,
        integer: false,
    };
    let spec = SensitivitySpec {
        samples: 0,
        ..SensitivitySpec::default()
    };
    let s = sensitivity(
        &windy,
        out,
        &[ranged],
        &[],
        &spec,
        AllowedErrors::default(),
        &Budget::default(),
        Some(2),
        &|_, _| {},
    )
    .unwrap();
    for name in LATERAL_STATS {
        assert!(s.band(&out.pantographs[0].name, name).is_some(), "{name}");
    }
}
