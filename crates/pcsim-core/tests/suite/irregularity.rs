//! Contact-wire irregularity, the window-length search and Monte Carlo (issue 13).

use pcsim_core::compile::Budget;
use pcsim_core::input::case::IrregularityCase;
use pcsim_core::model::irregularity::{psd_amplitudes, psd_shape, IrregularityProfile};
use pcsim_core::solve::realtime::Coupling;
use pcsim_core::study::montecarlo::{monte_carlo, Spread};
use pcsim_core::study::window_search::{search, SearchSettings, Tolerances, WindowErrors};
use pcsim_core::{presets, run_case, Case};

fn psd(rms: f64, seed: u64) -> IrregularityCase {
    IrregularityCase::Psd {
        rms_m: rms,
        min_wavelength_m: 2.0,
        max_wavelength_m: 60.0,
        exponent: 2.0,
        table: None,
        seed,
    }
}

/// SYT over a few spans, one pantograph.
fn short_syt(speed_kmh: f64, end_m: f64) -> Case {
    let mut c = presets::load("syt-7.0-9.8").unwrap().0;
    c.run.speed_kmh = speed_kmh;
    c.run.end_m = end_m;
    c.run.analysis_m = [c.run.start_m + 60.0, end_m];
    c
}

#[test]
fn zero_irregularity_gives_the_same_bytes_as_none() {
    let base = short_syt(222.0, 800.0);
    let mut zero = base.clone();
    zero.irregularity = vec![
        psd(0.0, 7),
        IrregularityCase::Droppers {
            rms_m: 0.0,
            seed: 3,
        },
        IrregularityCase::Table {
            position_m: vec![0.0, 1000.0],
            deviation_m: vec![0.0, 0.0],
            source_file: String::new(),
        },
    ];
    let a = run_case(&base, &mut |_| true).unwrap();
    let b = run_case(&zero, &mut |_| true).unwrap();
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    for (pa, pb) in a.pantographs.iter().zip(&b.pantographs) {
        assert_eq!(bits(&pa.force_n), bits(&pb.force_n));
        assert_eq!(bits(&pa.wire_height_m), bits(&pb.wire_height_m));
        assert_eq!(pa.stats, pb.stats);
    }
    assert_eq!(b.irregularity.len(), 3);
    assert!(b.irregularity.iter().all(|r| r.rms_achieved_m == 0.0));
}

#[test]
fn generated_profiles_match_their_rms_and_psd() {
    // A length of 2^14 − 2 samples of 0.125 m: the profile then fills its FFT period exactly, so
    // each bin's amplitude is read back without leakage.
    let (length, rms): (f64, f64) = (16382.0 * 0.125, 0.005);
    let seeds = 12;
    let dx: f64 = 2.0 / 16.0;
    let n = (length / dx).ceil() as usize + 2;
    let (nn, amps) = psd_amplitudes(n, dx, rms, (2.0, 60.0), 2.0, None);
    let d_omega = 1.0 / (nn as f64 * dx);
    // Bands over wavelength: 2–5, 5–15, 15–60 m.
    let bands = [(2.0, 5.0), (5.0, 15.0), (15.0, 60.0)];
    let mut got = [0.0; 3];
    let mut rms_sum = 0.0;
    for seed in 0..seeds {
        let p = IrregularityProfile::build(
            &pcsim_core::compile::model::irregularity_sources(&[psd(rms, seed)]),
            length,
            60.0,
            &[],
        );
        let achieved = p.reports[0].rms_achieved_m;
        assert!(
            (achieved - rms).abs() < 0.05 * rms,
            "seed {seed}: RMS {achieved}"
        );
        rms_sum += achieved;
        // The periodogram of the generated samples over the FFT period.
        let samples: Vec<f64> = (0..nn).map(|k| p.at(k as f64 * dx)).collect();
        for (b, &(lo, hi)) in bands.iter().enumerate() {
            for &(k, _) in &amps {
                let lam = 1.0 / (k as f64 * d_omega);
                if lam >= lo && lam < hi {
                    let (mut re, mut im) = (0.0, 0.0);
                    for (j, v) in samples.iter().enumerate().take(n) {
                        let a = 2.0 * std::f64::consts::PI * (k * j) as f64 / nn as f64;
                        re += v * a.cos();
                        im += v * a.sin();
                    }
                    // Amplitude of the cosine at bin k: 2|X_k|/N (the profile is cut at n ≤ N
                    // samples, so use the samples that exist).
                    let amp = 2.0 * (re * re + im * im).sqrt() / n as f64;
                    got[b] += 0.5 * amp * amp;
                }
            }
        }
    }
    assert!((rms_sum / seeds as f64 - rms).abs() < 0.05 * rms);
    for (b, &(lo, hi)) in bands.iter().enumerate() {
        let mean = got[b] / seeds as f64;
        // Target variance in the band: ∫ c S(λ) dΩ with c from the RMS.
        let shape_total: f64 = amps.iter().map(|_| 0.0).sum::<f64>()
            + (1..nn / 2)
                .map(|k| 1.0 / (k as f64 * d_omega))
                .filter(|&l| (2.0..=60.0).contains(&l))
                .map(|l| psd_shape(l, 2.0, None) * d_omega)
                .sum::<f64>();
        let want: f64 = (1..nn / 2)
            .map(|k| 1.0 / (k as f64 * d_omega))
            .filter(|&l| l >= lo && l < hi)
            .map(|l| rms * rms * psd_shape(l, 2.0, None) * d_omega / shape_total)
            .sum();
        assert!(
            (mean - want).abs() < 0.05 * want,
            "band {lo}-{hi} m: {mean:.3e} vs {want:.3e} m²"
        );
    }
}

fn harmonic(amp: f64, lam: f64) -> IrregularityCase {
    let xs: Vec<f64> = (0..=3600).map(|i| 0.5 * i as f64).collect();
    let ys: Vec<f64> = xs
        .iter()
        .map(|x| amp * (2.0 * std::f64::consts::PI * x / lam).sin())
        .collect();
    IrregularityCase::Table {
        position_m: xs,
        deviation_m: ys,
        source_file: String::new(),
    }
}

/// Largest `|Δheight − r(x)|` over the analysis section between a run with the harmonic and one
/// without, and the largest `|Δheight|`.
fn following(base: &Case, amp: f64, lam: f64) -> (f64, f64) {
    let mut with = base.clone();
    with.irregularity = vec![harmonic(amp, lam)];
    let a = run_case(base, &mut |_| true).unwrap();
    let b = run_case(&with, &mut |_| true).unwrap();
    let (pa, pb) = (&a.pantographs[0], &b.pantographs[0]);
    let (mut worst, mut peak): (f64, f64) = (0.0, 0.0);
    for k in 0..pa.position_m.len() {
        let x = pa.position_m[k];
        if x < base.run.analysis_m[0] || x > base.run.analysis_m[1] {
            continue;
        }
        // The table is linear between 0.5 m points: compare with what the model sees.
        let r = match &with.irregularity[0] {
            IrregularityCase::Table {
                position_m,
                deviation_m,
                ..
            } => {
                let i = (x / 0.5).floor() as usize;
                let t = (x - position_m[i]) / 0.5;
                deviation_m[i] + t * (deviation_m[i + 1] - deviation_m[i])
            }
            _ => unreachable!(),
        };
        let d = pb.wire_height_m[k] - pa.wire_height_m[k];
        worst = worst.max((d - r).abs());
        peak = peak.max(d.abs());
    }
    (worst, peak)
}

#[test]
fn a_harmonic_irregularity_is_followed_at_low_speed() {
    // A constant moving force: the same force, so the contact point's height differs by the
    // irregularity exactly.
    let mut force = short_syt(20.0, 560.0);
    force.pantographs = vec![pcsim_core::input::case::PantographCase::MovingForce {
        name: "force".into(),
        offset_m: 0.0,
        force_n: 80.0,
        lateral_force_n: 0.0,
    }];
    let (worst, peak) = following(&force, 0.010, 20.0);
    assert!(worst < 1e-9 && peak > 0.0099, "{worst} {peak}");
    // The DSA380-type pantograph at 3 km/h over a 60 m wave: the head follows the 10 mm
    // irregularity; what the roof damper (70 N·s/m) adds moves the wire by less than 1 % of it.
    // (At 20 km/h over 20 m it adds 1.2 N and 16 %: that is dynamics, not a defect.)
    // On 8 spans (the model's mode density kept) from one span before the section: the same
    // quasi-static following, a ninth of the steps of the whole 30-span model from 60 m.
    let mut slow = short_syt(3.0, 380.0);
    slow.catenary.spans = 8;
    slow.run.modes = Some(320);
    slow.run.start_m = 240.0;
    slow.run.analysis_m = [300.0, 380.0];
    let (worst, peak) = following(&slow, 0.010, 60.0);
    assert!(worst < 0.01 * 0.010, "worst deviation {worst} m of 0.010 m");
    assert!(peak > 0.009, "the contact point moves by {peak} m");
}

/// A synthetic error curve falling with the window length: σ error `c / (L − 40)` %.
fn synthetic(c: f64) -> impl FnMut(f64) -> Result<WindowErrors, ()> {
    move |w| {
        Ok(WindowErrors {
            window_m: w,
            mean_pct: 0.1,
            sigma_pct: c / (w - 40.0).max(1e-9),
            max_pct: 0.2,
        })
    }
}

#[test]
fn the_window_search_is_exact_and_monotone() {
    let s = SearchSettings {
        min_m: 50.0,
        max_m: 400.0,
        coarse_m: 20.0,
        resolution_m: 1.0,
        full_scan: false,
    };
    for (c, tol) in [(300.0, 3.0), (300.0, 2.0), (120.0, 3.0), (3000.0, 3.0)] {
        let t = Tolerances {
            mean_pct: 1.0,
            sigma_pct: tol,
            max_pct: 5.0,
        };
        let r = search(&s, &t, synthetic(c)).unwrap();
        // Exact: σ error ≤ tol ⇔ L ≥ 40 + c/tol; the smallest lattice point there.
        let want = 50.0 + ((40.0 + c / tol - 50.0) / 1.0).ceil().max(0.0);
        let want = (want <= 400.0).then_some(want);
        assert_eq!(r.length_m, want, "c {c}, tol {tol}");
        // Far fewer runs than the lattice.
        assert!(r.evaluated.len() < 60, "{} runs", r.evaluated.len());
    }
    // Monotone: a tighter tolerance never gives a shorter window, also on a bumpy curve.
    let bumpy = |w: f64| -> Result<WindowErrors, ()> {
        Ok(WindowErrors {
            window_m: w,
            mean_pct: 0.0,
            sigma_pct: 400.0 / w + 1.5 * (w / 7.0).sin().abs(),
            max_pct: 0.0,
        })
    };
    let mut last = 0.0;
    for tol in [6.0, 5.0, 4.0, 3.5, 3.0, 2.8, 2.6, 2.5] {
        let t = Tolerances {
            mean_pct: 1.0,
            sigma_pct: tol,
            max_pct: 5.0,
        };
        let r = search(&s, &t, bumpy).unwrap();
        let l = r.length_m.unwrap_or(f64::INFINITY);
        assert!(l >= last, "tolerance {tol}: {l} shorter than {last}");
        // Every evaluated window at or above the answer passes.
        for e in &r.evaluated {
            if e.window_m >= l {
                assert!(e.passes(&t), "{} fails above the answer {l}", e.window_m);
            }
        }
        last = l;
    }
}

/// Issue 20, item 4: the search states the lattice of its claim, and the full scan's claim holds
/// for every window at the resolution (checked against a 1 m brute-force scan) on an error
/// curve that fails between coarse points above the coarse answer.
#[test]
fn the_window_search_claim_is_what_a_one_metre_scan_confirms() {
    // σ error: falls with the length, with a narrow bump at 165–169 m above the tolerance.
    let curve = |w: f64| -> Result<WindowErrors, ()> {
        let bump = if (165.0..=169.0).contains(&w) {
            2.0
        } else {
            0.0
        };
        Ok(WindowErrors {
            window_m: w,
            mean_pct: 0.0,
            sigma_pct: 300.0 / w + bump,
            max_pct: 0.0,
        })
    };
    let t = Tolerances {
        mean_pct: 1.0,
        sigma_pct: 3.0,
        max_pct: 5.0,
    };
    let passes = |w: f64| curve(w).unwrap().passes(&t);
    let mut s = SearchSettings {
        min_m: 50.0,
        max_m: 400.0,
        coarse_m: 20.0,
        resolution_m: 1.0,
        full_scan: false,
    };
    // The brute-force 1 m scan: the shortest L with every window in [L, 400] passing.
    let lattice: Vec<f64> = (0..=350).map(|k| 50.0 + k as f64).collect();
    let truth = lattice
        .iter()
        .copied()
        .filter(|&l| lattice.iter().filter(|&&w| w >= l).all(|&w| passes(w)))
        .fold(f64::INFINITY, f64::min);
    assert_eq!(truth, 170.0);
    // The lattice search answers 100 m (the bump lies between its coarse points 150 and 170)
    // and says so: its claim's fine band ends at the lowest passing coarse window, and every
    // window it claims passes.
    let r = search(&s, &t, curve).unwrap();
    let (l, to) = (r.length_m.unwrap(), r.fine_checked_to_m.unwrap());
    assert!(l < truth, "{l}");
    assert!(to < 165.0, "{to}");
    assert!(lattice
        .iter()
        .filter(|&&w| w >= l && w <= to)
        .all(|&w| passes(w)));
    assert!(r.claim(&s).contains("were not run"), "{}", r.claim(&s));
    // The full scan finds the truth, and claims the whole range.
    s.full_scan = true;
    let r = search(&s, &t, curve).unwrap();
    assert_eq!(r.length_m, Some(truth));
    assert_eq!(r.fine_checked_to_m, Some(400.0));
    assert_eq!(
        r.evaluated.len(),
        400 - 170 + 2,
        "every window from the top to the first failure"
    );
    assert!(
        r.claim(&s).contains("every window from 170 m to 400 m"),
        "{}",
        r.claim(&s)
    );
}

#[test]
fn monte_carlo_gives_the_same_bytes_with_one_or_two_jobs() {
    let mut case = short_syt(222.0, 600.0);
    case.irregularity = vec![psd(0.004, 11)];
    let a = monte_carlo(&case, 3, Some(1), &Budget::default(), &|| {}).unwrap();
    let b = monte_carlo(&case, 3, Some(2), &Budget::default(), &|| {}).unwrap();
    assert_eq!(a, b);
    // The realisations differ (their seeds do), and the spread says so.
    let sig: Vec<f64> = a
        .iter()
        .map(|r| r.output.pantographs[0].stats.unwrap().std_n)
        .collect();
    assert!(sig[0] != sig[1] && sig[1] != sig[2]);
    let s = Spread::of(&sig).unwrap();
    assert!(s.std.unwrap() > 0.0 && s.ci95_low.unwrap() < s.mean && s.mean < s.ci95_high.unwrap());
    // One realisation: the spread is undefined, not zero (issue 19, item 5).
    let one = Spread::of(&sig[..1]).unwrap();
    assert_eq!(
        (one.n, one.std, one.ci95_low, one.ci95_high),
        (1, None, None, None)
    );
    assert_eq!(a[2].output.irregularity[0].seed, Some(13));
}

#[test]
fn the_real_time_window_sees_the_irregularity() {
    let mut case = short_syt(222.0, 900.0);
    case.irregularity = vec![psd(0.004, 5)];
    let full = run_case(&case, &mut |_| true).unwrap();
    let fs = full.pantographs[0].stats.unwrap();
    let w = pcsim_core::study::realtime::run_window_sil(&case, 215.0).unwrap();
    let ws = w.stats.unwrap();
    // The irregularity raises σ; the 215 m window follows the full model's (within 3 %), which
    // it could not do without the profile.
    let smooth = run_case(&short_syt(222.0, 900.0), &mut |_| true)
        .unwrap()
        .pantographs[0]
        .stats
        .unwrap();
    assert!(
        fs.std_n > 1.2 * smooth.std_n,
        "{} vs {}",
        fs.std_n,
        smooth.std_n
    );
    assert!(
        (ws.std_n - fs.std_n).abs() < 0.03 * fs.std_n,
        "{} vs {}",
        ws.std_n,
        fs.std_n
    );
    let _ = pcsim_core::compile::realtime_window(&case, 215.0, Coupling::Hil).unwrap();
}

/// Issue 20, item 8: a seeded perturbation of the uplift by 1e-9 puts an error bar on the
/// threshold-sensitive statistics. `benchmark-55m` (droppers go slack): the actual maximum moves
/// by more than 0.1 % between realisations while the mean moves by less than a tenth of that (and
/// 0.1 %); the same seed
/// gives the same bytes, the perturbation is in the seeded inputs (`--seeds` accepts the case),
/// and a perturbation above 1e-3 is refused naming the field.
#[test]
fn a_tiny_uplift_perturbation_gives_the_spread_of_the_actual_extremes() {
    let (mut c, _) = pcsim_core::presets::load("benchmark-55m").unwrap();
    c.run.perturb_uplift_rel = 1e-9;
    assert!(c.is_random());
    assert_eq!(pcsim_core::analysis::sweep::check_seeds(Some(4), &c), Ok(4));
    let stats = |k: u64| {
        pcsim_core::run_case(&c.with_seed_offset(k), &mut |_| true)
            .unwrap()
            .pantographs[0]
            .stats
            .unwrap()
    };
    let runs: Vec<_> = (0..4).map(stats).collect();
    let spread = |f: &dyn Fn(&pcsim_core::analysis::stats::ContactStats) -> f64| {
        let v: Vec<f64> = runs.iter().map(f).collect();
        let (lo, hi) = v
            .iter()
            .fold((f64::MAX, f64::MIN), |a, &x| (a.0.min(x), a.1.max(x)));
        (hi - lo) / hi.abs()
    };
    assert!(
        spread(&|s| s.actual_max_n) > 1e-3,
        "actual max spread {}",
        spread(&|s| s.actual_max_n)
    );
    // The mean hardly moves against the extremes: at most a tenth of their spread, and 0.1 %.
    // (The bound was 1e-4 until issue 23: that build's four realisations spread the mean by
    // 4.3e-5 and the maximum by 2.1e-2; a rounding-level change of the implicit solve gave
    // 1.5e-4 and 6.2e-3, this chaotic run's sampling spread, not a drift of the mean.)
    let (mean, max) = (spread(&|s| s.mean_n), spread(&|s| s.actual_max_n));
    assert!(
        mean < 1e-3 && mean < 0.1 * max,
        "mean spread {mean} against the maximum's {max}"
    );
    assert_eq!(stats(2), runs[2], "the same seed gives the same statistics");
    c.run.perturb_uplift_rel = 0.01;
    let e = pcsim_core::run_case(&c, &mut |_| true)
        .unwrap_err()
        .to_string();
    assert!(e.contains("run.perturb_uplift_rel"), "{e}");
}
