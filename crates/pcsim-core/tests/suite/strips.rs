//! Issue 43, item 1: collector strips. A head of strips is a set of masses on springs and
//! dampers to the head's frame, each with its own contact point along the track and its own
//! penalty contact. Checked exactly: one strip is the chain whose head it is; two strips at zero
//! spacing with half the parameters each are that one strip; a strip that never touches carries
//! exactly zero; the strips' forces sum to the pantograph's; the head's receptance by a dense
//! solve is the chain's by its own elimination.

use crate::common;

use pcsim_core::input::case::{Case, PantographCase, StripCase};
use pcsim_core::{run_case, CaseError, RunOutput};

/// The en50318-2002 pantograph (head 7.2 kg on 4200 N/m and 10 N·s/m to a 15 kg frame) with its
/// head given as `strips`, each `(share, along_m, height_offset_m)`: the share of the head's
/// mass, spring, damper and contact stiffness.
fn with_strips(mut c: Case, strips: &[(f64, f64, f64)]) -> Case {
    let k_c = c.contact.stiffness_n_per_m;
    if let PantographCase::Lumped {
        masses_kg,
        stiffness_n_per_m,
        damping_ns_per_m,
        strips: s,
        ..
    } = &mut c.pantographs[0]
    {
        let (m, k, d) = (masses_kg[0], stiffness_n_per_m[0], damping_ns_per_m[0]);
        masses_kg.remove(0);
        stiffness_n_per_m.remove(0);
        damping_ns_per_m.remove(0);
        *s = strips
            .iter()
            .map(|&(share, along_m, height_offset_m)| StripCase {
                mass_kg: share * m,
                stiffness_n_per_m: share * k,
                damping_ns_per_m: share * d,
                along_m,
                height_offset_m,
                contact_stiffness_n_per_m: Some(share * k_c),
            })
            .collect();
    }
    c
}

fn short() -> Case {
    common::short_en50318(10, 250.0)
}

fn run(c: &Case) -> RunOutput {
    run_case(c, &mut |_| true).unwrap()
}

/// The largest difference of two series relative to the largest magnitude of the first.
fn apart(a: &[f64], b: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len());
    let scale = a.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
        / scale
}

/// [`common::same_statistics`] and the uplift at the supports.
fn same_statistics(a: &RunOutput, b: &RunOutput, tol: f64, what: &str) {
    common::same_statistics(a, b, tol, what);
    let (x, y) = (
        a.pantographs[0].stats.unwrap().max_uplift_at_support_mm,
        b.pantographs[0].stats.unwrap().max_uplift_at_support_mm,
    );
    assert!((x - y).abs() <= tol * x.abs(), "{what}, uplift: {x} vs {y}");
}

/// One strip carrying the whole head is the chain whose head it is: the contact force at every
/// step and the statistics within 1e-9; its own force is the pantograph's.
#[test]
fn issue_43_1_one_strip_is_the_chain_whose_head_it_is() {
    let chain = run(&short());
    let one = run(&with_strips(short(), &[(1.0, 0.0, 0.0)]));
    same_statistics(&chain, &one, 1e-9, "one strip");
    let d = apart(&chain.pantographs[0].force_n, &one.pantographs[0].force_n);
    assert!(d < 1e-9, "force series {d} apart");
    assert!(chain.pantographs[0].strips.is_empty());
    assert_eq!(one.pantographs[0].strips.len(), 1);
    assert_eq!(
        one.pantographs[0].strips[0].force_n,
        one.pantographs[0].force_n
    );
}

/// Two strips at zero spacing with half the strip parameters each (mass, spring, damper and
/// contact stiffness) are the one strip: the pantograph's force and statistics within 1e-9, and
/// each strip carries half of it at every step (1e-9).
#[test]
fn issue_43_1_two_strips_at_zero_spacing_with_half_parameters_are_one_strip() {
    let one = run(&with_strips(short(), &[(1.0, 0.0, 0.0)]));
    let two = run(&with_strips(short(), &[(0.5, 0.0, 0.0), (0.5, 0.0, 0.0)]));
    same_statistics(&one, &two, 1e-9, "two half strips");
    let f = &one.pantographs[0].force_n;
    assert!(apart(f, &two.pantographs[0].force_n) < 1e-9);
    let half: Vec<f64> = f.iter().map(|x| 0.5 * x).collect();
    for s in &two.pantographs[0].strips {
        assert!(apart(&half, &s.force_n) < 1e-9);
    }
}

/// A strip whose running face sits 0.2 m below the other's never reaches the wire: its force is
/// exactly zero at every step (and its statistics' mean), while the other carries the
/// pantograph's whole force.
#[test]
fn issue_43_1_a_strip_that_is_never_touched_carries_exactly_zero() {
    let out = run(&with_strips(
        short(),
        &[(0.5, 0.25, 0.0), (0.5, -0.25, -0.2)],
    ));
    let p = &out.pantographs[0];
    let low = &p.strips[1];
    assert!(low
        .force_n
        .iter()
        .all(|&f| f == 0.0 && f.is_sign_positive()));
    assert_eq!(low.stats.unwrap().mean_n, 0.0);
    assert_eq!(p.strips[0].force_n, p.force_n);
    assert!(p.stats.unwrap().mean_n > 50.0);
}

/// Strips 0.5 m apart meet the wire at their own points: their forces differ, each is never
/// negative, and they sum to the pantograph's force at every step (to rounding).
#[test]
fn issue_43_1_strips_apart_share_the_force_and_sum_to_the_pantographs() {
    let out = run(&with_strips(
        short(),
        &[(0.5, 0.25, 0.0), (0.5, -0.25, 0.0)],
    ));
    let p = &out.pantographs[0];
    let (a, b) = (&p.strips[0].force_n, &p.strips[1].force_n);
    let sum: Vec<f64> = a.iter().zip(b).map(|(x, y)| x + y).collect();
    assert!(apart(&p.force_n, &sum) < 1e-12);
    assert!(a.iter().chain(b).all(|&f| f >= 0.0));
    assert!(
        apart(a, b) > 1e-3,
        "the strips meet the wire at different points"
    );
    // The sum's statistics are the pantograph's; each strip's mean is about half.
    let (sa, sb) = (p.strips[0].stats.unwrap(), p.strips[1].stats.unwrap());
    let m = p.stats.unwrap().mean_n;
    assert!((sa.mean_n + sb.mean_n - m).abs() < 1e-6 * m);
    assert!(
        (sa.mean_n - 0.5 * m).abs() < 0.1 * m,
        "{} of {m}",
        sa.mean_n
    );
}

/// The receptance of a head of one strip (a dense complex solve over the strips and the frame)
/// is the chain's (its own elimination from the roof up) at 60 frequencies from 0.1 to 50 Hz,
/// within 1e-12 relative.
#[test]
fn issue_43_1_a_heads_receptance_is_the_chains() {
    let lumped = |c: &Case| pcsim_core::compile::lumped_pantograph(c, None).unwrap().1;
    let chain = lumped(&short());
    let one = lumped(&with_strips(short(), &[(1.0, 0.0, 0.0)]));
    let two = lumped(&with_strips(short(), &[(0.5, 0.0, 0.0), (0.5, 0.0, 0.0)]));
    for i in 0..60 {
        let w = 2.0 * std::f64::consts::PI * 0.1 * (500.0f64).powf(i as f64 / 59.0);
        let h = chain.receptance(w).unwrap();
        for (what, p) in [("one strip", &one), ("two half strips", &two)] {
            let g = p.receptance(w).unwrap();
            assert!(
                (g - h).norm() <= 1e-12 * h.norm(),
                "{what} at {w} rad/s: {g} vs {h}"
            );
        }
    }
}

/// What a head of strips cannot be is refused naming its field: a strip on no spring, a strip
/// 5 m along the head, more than 8 strips, a strip too light for its contact at the step; and
/// the fit, which takes a head's strips alike,
/// refuses a starting head whose strips differ.
#[test]
fn issue_43_1_a_heads_strips_refuse_by_name() {
    let field = |c: &Case| match c.validate() {
        Err(CaseError::Invalid { field, .. }) => field,
        other => panic!("{other:?}"),
    };
    let mut c = with_strips(short(), &[(0.5, 0.25, 0.0), (0.5, -0.25, 0.0)]);
    if let PantographCase::Lumped { strips, .. } = &mut c.pantographs[0] {
        strips[1].stiffness_n_per_m = 0.0;
    }
    assert_eq!(field(&c), "pantographs[0].strips[1].stiffness_n_per_m");
    let mut c = with_strips(short(), &[(0.5, 5.0, 0.0), (0.5, -0.25, 0.0)]);
    assert_eq!(field(&c), "pantographs[0].strips[0].along_m");
    c = with_strips(short(), &[(0.1, 0.0, 0.0); 9]);
    assert_eq!(field(&c), "pantographs[0].strips");
    // A strip too light for its contact at the step: the run refuses it by its own field.
    let mut c = with_strips(short(), &[(0.5, 0.25, 0.0), (0.5, -0.25, 0.0)]);
    if let PantographCase::Lumped { strips, .. } = &mut c.pantographs[0] {
        strips[1].mass_kg = 0.02;
    }
    match pcsim_core::compile::Setup::from_case(&c).and_then(|s| s.integrator().map(|_| ())) {
        Err(CaseError::Invalid { field, .. }) => {
            assert_eq!(field, "pantographs[0].strips[1].contact_stiffness_n_per_m")
        }
        other => panic!("{other:?}"),
    }
    let mut head = pcsim_core::compile::lumped_pantograph(
        &with_strips(short(), &[(0.5, 0.25, 0.0), (0.5, -0.25, 0.0)]),
        None,
    )
    .unwrap()
    .1;
    head.strips[1].mass_kg *= 1.1;
    use pcsim_core::study::frf::{Quantity, Response};
    let grid = Response::log_grid(0.5, 20.0, 30).unwrap();
    let measured = Response::of_model(&head, Quantity::Receptance, &grid).unwrap();
    match pcsim_core::study::frf::fit(&head, &measured) {
        Err(CaseError::Invalid { field, .. }) => assert_eq!(field, "pantographs.strips[1]"),
        other => panic!("{:?}", other.map(|_| ())),
    }
}

/// The preset with two strips runs, each strip's statistics beside the sum's, and its static
/// force follows its height table.
#[test]
fn issue_43_4_the_two_strip_preset_runs_with_its_strips() {
    let (c, _) = pcsim_core::presets::load("benchmark-55m-two-strips").unwrap();
    let out = run(&c);
    let p = &out.pantographs[0];
    assert_eq!(p.strips.len(), 2);
    let m = p.stats.unwrap().mean_n;
    let sum: f64 = p.strips.iter().map(|s| s.stats.unwrap().mean_n).sum();
    assert!((sum - m).abs() < 1e-6 * m, "{sum} vs {m}");
    assert_eq!((p.strips[0].along_m, p.strips[1].along_m), (0.25, -0.25));
}

/// The real-time window with strips. In the loop with hardware the rig is the pantograph: the
/// same measured force and positions through a window of `benchmark-55m-two-strips` and of
/// `benchmark-55m` (the same catenary) give the same outputs bit for bit (the force acts once, at
/// the pantograph's position, whatever its head). With pcsim's pantograph in the window (SIL),
/// two half strips at zero spacing are the one strip within 1e-9 over 3 000 steps, and strips
/// 0.5 m apart run.
#[test]
fn issue_43_1_the_real_time_window_carries_a_head_of_strips() {
    use pcsim_core::session::{Coupling, RealtimeSession};
    let (two, _) = pcsim_core::presets::load("benchmark-55m-two-strips").unwrap();
    let (one, _) = pcsim_core::presets::load("benchmark-55m").unwrap();
    let mut a = RealtimeSession::new(&two, 240.0, Coupling::Hil).unwrap();
    let mut b = RealtimeSession::new(&one, 240.0, Coupling::Hil).unwrap();
    let (x0, v, dt) = (a.start_position_m(), two.speed_m_s(), two.run.dt_s);
    assert_eq!(x0, b.start_position_m());
    for i in 0..3000 {
        let x = x0 + v * dt * i as f64;
        let f = 110.0 + 20.0 * (0.01 * i as f64).sin();
        assert_eq!(a.step(f, x).unwrap(), b.step(f, x).unwrap(), "step {i}");
    }
    let sil = |c: &Case| {
        let mut rt = RealtimeSession::new(c, 240.0, Coupling::Sil).unwrap();
        (0..3000)
            .map(|_| rt.step(0.0, 0.0).unwrap().contact_force_n)
            .collect::<Vec<f64>>()
    };
    let one_strip = sil(&with_strips(short(), &[(1.0, 0.0, 0.0)]));
    let halves = sil(&with_strips(short(), &[(0.5, 0.0, 0.0), (0.5, 0.0, 0.0)]));
    assert!(apart(&one_strip, &halves) < 1e-9);
    let spread = sil(&two);
    assert!(spread.iter().all(|f| f.is_finite() && *f >= 0.0));
}

/// A head of two strips on a frame fitted to its own response with 2 % noise (seeded), from a
/// start 25 % off: the frame's mass, spring and damper and the strip design's are recovered
/// within 3 standard deviations of the uncertainty the fit reports; the fitted block carries both
/// strips, each with the fitted design at its own place.
#[test]
fn issue_43_3_a_head_of_two_strips_is_fitted_within_its_uncertainty() {
    use pcsim_core::study::frf::{fit, Quantity, Response};
    let two = with_strips(short(), &[(0.5, 0.25, 0.0), (0.5, -0.25, 0.0)]);
    let truth = pcsim_core::compile::lumped_pantograph(&two, None)
        .unwrap()
        .1;
    let f = Response::log_grid(0.2, 20.0, 120).unwrap();
    let mut measured = Response::of_model(&truth, Quantity::ApparentMass, &f).unwrap();
    common::with_noise(&mut measured, 4301);
    measured.source = "synthetic".into();
    let measured = Response::from_csv(&measured.to_csv(), "synthetic.csv").unwrap();
    let mut start = truth.clone();
    start.masses_kg[0] *= 1.25;
    start.stiffness_n_per_m[0] *= 0.75;
    start.damping_ns_per_m[0] *= 1.25;
    for s in &mut start.strips {
        s.mass_kg *= 0.75;
        s.stiffness_n_per_m *= 1.25;
        s.damping_ns_per_m *= 0.75;
    }
    let r = fit(&start, &measured).unwrap();
    let want = [15.0, 50.0, 90.0, 3.6, 2100.0, 5.0];
    assert_eq!(r.record.parameters.len(), want.len());
    assert_eq!(r.record.parameters[3].name, "strips[*].mass_kg");
    for (p, t) in r.record.parameters.iter().zip(want) {
        assert!(!p.at_bound && p.std.is_finite() && p.std > 0.0, "{p:?}");
        assert!(
            (p.value - t).abs() <= 3.0 * p.std,
            "{}: {} ± {} against {t}",
            p.name,
            p.value,
            p.std
        );
    }
    let block = r.case_block("leading", "synthetic.csv");
    assert_eq!(block.matches("[[pantographs.strips]]").count(), 2);
    assert!(
        block.contains("along_m = 0.25") && block.contains("along_m = -0.25"),
        "{block}"
    );
}

/// The verification's model check doubles every contact stiffness, a strip's own included: the
/// preset's strips (25 000 N/m each) at 50 000 N/m in the stiffer case.
#[test]
fn issue_43_1_the_stiffer_contact_check_stiffens_every_strip() {
    let (c, _) = pcsim_core::presets::load("benchmark-55m-two-strips").unwrap();
    let stiff = pcsim_core::analysis::verify::stiff_contact_case(&c);
    let k = |c: &Case| match &c.pantographs[0] {
        PantographCase::Lumped { strips, .. } => strips
            .iter()
            .map(|s| s.contact_stiffness_n_per_m.unwrap())
            .collect::<Vec<_>>(),
        _ => unreachable!(),
    };
    assert_eq!(k(&c), vec![25_000.0; 2]);
    assert_eq!(k(&stiff), vec![50_000.0; 2]);
}

/// Issue 51, item 6: names that would write one file are refused. Figures are named by the
/// pantograph's name with every character but letters, digits, - and _ as _ (and a file system
/// may fold case): "panto<A>" and "panto[A]" would both write `contact_force_panto_A_`, and
/// "Lead" and "lead" one file on such a system. Refused by the second name's field, naming both.
#[test]
fn issue_51_pantograph_names_alike_in_a_file_name_are_refused() {
    let mut c = pcsim_core::presets::load("stitched-2018-like").unwrap().0;
    for (a, b) in [("panto<A>", "panto[A]"), ("Lead", "lead")] {
        for (p, n) in c.pantographs.iter_mut().zip([a, b]) {
            if let pcsim_core::input::case::PantographCase::Lumped { name, .. } = p {
                *name = n.into();
            }
        }
        match c.validate() {
            Err(pcsim_core::CaseError::Invalid { field, reason, .. }) => {
                assert_eq!(field, "pantographs[1].name");
                assert!(
                    reason.contains(a) && reason.contains("overwrite"),
                    "{reason}"
                );
            }
            other => panic!("{a} / {b}: {other:?}"),
        }
    }
}
