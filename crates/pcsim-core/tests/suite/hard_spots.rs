//! The line's hard spots (issue 55): section insulators and neutral sections. Exact checks of the
//! insulator's law on a string (its mass shifts a mode as the closed form says; its bending holds
//! the wire as the discrete law's exact static solution says, between the plain string and the
//! rigid bar), and that an insulator of zero mass and the wire's own stiffness changes nothing.

use pcsim_core::input::case::Damping;
use pcsim_core::model::basis::SineBasis;
use pcsim_core::model::ModelBuilder;
use std::f64::consts::PI;

use crate::common::{
    central_mode_omega, mean_period, stepper, string_with_central_mass_omega, wire, zero_crossings,
};

#[test]
fn an_insulators_mass_shifts_the_first_mode_as_the_closed_form_says() {
    // A string with a mass m at its centre, symmetric modes: cot(βL/2) = m β / (2ρ), ω = c β.
    let (l, rho, t, m): (f64, f64, f64, f64) = (20.0, 1.0, 100.0, 2.0);
    let c = (t / rho).sqrt();
    let omega = string_with_central_mass_omega(l, rho, t, m);
    let n = 400;
    // The insulator (1 m long, the string's own stiffness: no added bending) carries the mass.
    let mut s = stepper(
        ModelBuilder::single_wire(l, n, rho, t, 0.0)
            .section_insulator(l / 2.0, 1.0, m, 0.0)
            .moving_force("probe", 0.0)
            .run(0.0, l / 2.0, 1.0, 2e-4),
    );
    let measured = central_mode_omega(&mut s, l, n, t, 100_000);
    assert!(
        (measured - omega).abs() < 5e-3 * omega,
        "ω measured {measured} vs closed form {omega}"
    );
    // Without the mass the frequency would be πc/L: the test can tell.
    assert!((PI * c / l - omega).abs() > 0.05 * omega);
}

/// The static deflection at the centre of a string (tension `t`, length `l`) under a force `f`
/// at the centre of an insulator of length `len` whose curvature stiffness is `c`: with `s` the
/// outer segments' length and `h = len/2`, the ends sit at `p = f s/(2t)` and the centre at
/// `p + f/(2t/h + 4c)` (the discrete law solved by hand; `c = 0` the plain string `f l/(4t)`,
/// `c → ∞` the rigid bar).
fn centre_deflection(f: f64, l: f64, t: f64, len: f64, c: f64) -> f64 {
    let (s, h) = (0.5 * (l - len), 0.5 * len);
    f * s / (2.0 * t) + f / (2.0 * t / h + 4.0 * c)
}

#[test]
fn an_insulators_bending_holds_the_wire_as_its_law_says() {
    use pcsim_core::model::elements::section_insulator::curvature_stiffness_n_per_m;
    let (l, t, f, len) = (100.0, 20_000.0, 100.0, 20.0);
    for added_ei in [0.0, 5.0e5, 5.0e7] {
        let c = curvature_stiffness_n_per_m(added_ei, len);
        let mut s = stepper(
            ModelBuilder::single_wire(l, 400, 1.35, t, 0.0)
                .damping(&Damping::Modal { ratio: 0.3 })
                .section_insulator(l / 2.0, len, 0.0, added_ei)
                .moving_force("load", f)
                .run(0.0, l / 2.0, 20.0, 2e-4),
        );
        for _ in 0..60_000 {
            s.step();
        }
        let w = s.samples()[0].wire_height_m;
        let exact = centre_deflection(f, l, t, len, c);
        assert!(
            (w - exact).abs() < 2e-3 * exact,
            "ΔEI {added_ei} N·m²: integrated {w} m vs exact {exact} m"
        );
    }
    // The three answers differ by far more than the tolerance: the string, the law, the bar.
    let string = f * l / (4.0 * t);
    let bar = centre_deflection(f, l, t, len, f64::INFINITY);
    let mid = centre_deflection(f, l, t, len, curvature_stiffness_n_per_m(5.0e5, len));
    assert!((string - mid) > 0.05 * string && (mid - bar) > 0.05 * bar);
}

/// The run of `case` (no progress).
fn run(case: &pcsim_core::Case) -> pcsim_core::RunOutput {
    pcsim_core::run_case(case, &mut |_| true).unwrap()
}

#[test]
fn an_insulator_of_zero_mass_and_the_wires_stiffness_changes_nothing() {
    use pcsim_core::zoo::geometries::{section_insulator, short_en50318};
    let plain = short_en50318(8, 250.0);
    let mut with = plain.clone();
    let mut si = section_insulator(200.0);
    (si.mass_kg, si.ei_nm2, si.prelift_m) = (0.0, plain.catenary.contact_wire.ei_nm2, 0.0);
    with.section_insulator = vec![si];
    let (a, b) = (run(&plain), run(&with));
    let (fa, fb) = (&a.pantographs[0].force_n, &b.pantographs[0].force_n);
    assert_eq!(fa.len(), fb.len());
    let worst = fa
        .iter()
        .zip(fb)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max);
    assert!(worst <= 1e-9, "the force moved by {worst} N");
    // It is still reported as a hard spot that was passed.
    assert_eq!(b.pantographs[0].hard_spots.len(), 1);
}

#[test]
fn a_neutral_section_is_a_hard_spot_its_run_reports() {
    use pcsim_core::model::HardSpotKind;
    use pcsim_core::zoo::geometries::{neutral_section, short_en50318};
    let plain = short_en50318(8, 250.0);
    let ns = neutral_section(plain.clone(), 190.0, 25.0);
    let (a, b) = (run(&plain), run(&ns));
    let spots = &b.pantographs[0].hard_spots;
    let kinds: Vec<_> = spots.iter().map(|h| h.kind).collect();
    assert_eq!(
        kinds,
        [
            HardSpotKind::SectionInsulator,
            HardSpotKind::SectionInsulator,
            HardSpotKind::NeutralSection
        ]
    );
    // Over each insulator the force swings wider than over the same stretch of the plain
    // line: 12 kg and a stiff rod in the wire are a hard spot.
    for h in &spots[..2] {
        let over = |out: &pcsim_core::RunOutput| {
            let p = &out.pantographs[0];
            let f: Vec<f64> = (p.position_m.iter().zip(&p.force_n))
                .filter(|(x, _)| **x >= h.section_m[0] && **x <= h.section_m[1])
                .map(|(_, f)| *f)
                .collect();
            f.iter().cloned().fold(f64::NEG_INFINITY, f64::max)
                - f.iter().cloned().fold(f64::INFINITY, f64::min)
        };
        assert!(
            over(&b) > over(&a),
            "insulator at {:?}: force range {} N with it, {} N without",
            h.section_m,
            over(&b),
            over(&a)
        );
        assert!(h.samples > 0 && h.max_force_n >= h.min_force_n);
        assert!(h.max_uplift_mm.is_finite());
    }
}

#[test]
fn insulators_and_neutral_sections_are_refused_by_name_where_they_cannot_be() {
    use pcsim_core::error::CaseError;
    use pcsim_core::zoo::geometries::{neutral_section, overlap_line, short_en50318};
    let field = |c: &pcsim_core::Case| match c.validate() {
        Err(CaseError::Invalid { field, reason, .. }) => (field, reason),
        other => panic!("not refused by name: {other:?}"),
    };
    let base = neutral_section(short_en50318(8, 250.0), 190.0, 25.0);
    let mut soft = base.clone();
    soft.section_insulator[0].ei_nm2 = 1.0;
    assert_eq!(field(&soft).0, "section_insulator[0].ei_nm2");
    let mut off = base.clone();
    off.neutral_section[0].end_m = 230.0;
    let (f, reason) = field(&off);
    assert_eq!(f, "neutral_section[0].end_m");
    assert!(reason.contains("section insulator"), "{reason}");
    let mut ramp = base.clone();
    ramp.section_insulator[1].ramp_m = 1.5;
    assert_eq!(field(&ramp).0, "section_insulator[1].ramp_m");
    let mut outside = base.clone();
    outside.section_insulator[1].position_m = 479.5;
    assert_eq!(field(&outside).0, "section_insulator[1].position_m");
    // In an overlap two contact wires run side by side: refused, saying so.
    let in_overlap = neutral_section(overlap_line(), 250.0, 25.0);
    let (f, reason) = field(&in_overlap);
    assert_eq!(f, "section_insulator[0].position_m");
    assert!(reason.contains("overlap"), "{reason}");
}

// The rigid overhead conductor rail, the engine's part (issue 55, item 2): a beam with no
// tension on elastic supports at its own spacing is what the modal wire and the point springs
// already are. The case kind (a `[line]` without messenger and droppers, its static start, its
// transition to a catenary) is not built: docs/hard-spots.md.

/// The deflection at `x` of a simply supported beam (length `l`, bending stiffness `ei`) under a
/// unit load at `a` (the Green's function of a pinned–pinned Euler–Bernoulli beam).
fn pinned_beam_green(x: f64, a: f64, l: f64, ei: f64) -> f64 {
    let (x, a) = if x <= a { (x, a) } else { (l - x, l - a) };
    let b = l - a;
    b * x * (l * l - b * b - x * x) / (6.0 * l * ei)
}

/// The deflection under a point load `f` at `a` of a continuous beam pinned at its ends on
/// springs `k` at `supports` (the flexibility method, solved by Gaussian elimination: an
/// independent solve of the same beam).
fn beam_on_springs(f: f64, a: f64, l: f64, ei: f64, supports: &[f64], k: f64) -> f64 {
    let n = supports.len();
    // (I/k + G_ss) R = G_sa f, the support reactions R.
    let mut m: Vec<Vec<f64>> = (0..n)
        .map(|i| {
            let mut row: Vec<f64> = (0..n)
                .map(|j| pinned_beam_green(supports[i], supports[j], l, ei))
                .collect();
            row[i] += 1.0 / k;
            row.push(pinned_beam_green(supports[i], a, l, ei) * f);
            row
        })
        .collect();
    for c in 0..n {
        let p = (c..n)
            .max_by(|&i, &j| m[i][c].abs().total_cmp(&m[j][c].abs()))
            .unwrap();
        m.swap(c, p);
        let pivot = m[c].clone();
        for (r, row) in m.iter_mut().enumerate() {
            if r != c {
                let q = row[c] / pivot[c];
                for (x, p) in row.iter_mut().zip(&pivot).skip(c) {
                    *x -= q * p;
                }
            }
        }
    }
    let reactions: Vec<f64> = (0..n).map(|i| m[i][n] / m[i][i]).collect();
    pinned_beam_green(a, a, l, ei) * f
        - (supports.iter().zip(&reactions))
            .map(|(&s, r)| pinned_beam_green(a, s, l, ei) * r)
            .sum::<f64>()
}

#[test]
fn a_rigid_rail_on_elastic_supports_deflects_as_the_continuous_beam() {
    // An aluminium profile with its contact wire (EI and mass guesses of the order of the
    // published profiles), no tension, supports every 10 m of 10⁵ N/m (a guess, soft enough
    // that their elasticity shows), a pantograph's force between two.
    let (l, ei, rho, k, f, a) = (100.0, 1.5e5, 6.5, 1.0e5, 150.0, 45.0);
    let supports: Vec<f64> = (1..10).map(|j| 10.0 * j as f64).collect();
    let mut b = ModelBuilder::single_wire(l, 150, rho, 0.0, ei)
        .damping(&Damping::Modal { ratio: 0.3 })
        .moving_force("load", f)
        .run(0.0, a, 20.0, 2e-4);
    for &s in &supports {
        b = b.point_mass(s, 0.0, k);
    }
    let mut s = stepper(b);
    for _ in 0..50_000 {
        s.step();
    }
    let w = s.samples()[0].wire_height_m;
    let exact = beam_on_springs(f, a, l, ei, &supports, k);
    assert!(
        (w - exact).abs() < 1e-3 * exact,
        "modal {w} m vs the continuous beam {exact} m"
    );
    // The supports matter: the beam without them, and on rigid ones, are far off.
    let free = pinned_beam_green(a, a, l, ei) * f;
    let rigid = beam_on_springs(f, a, l, ei, &supports, 1e15);
    assert!(free > 10.0 * exact && (exact - rigid) > 0.05 * exact);
}

#[test]
fn a_rigid_rails_bending_mode_between_supports_is_the_beams() {
    // The mode that alternates span to span has its nodes on the supports: each span vibrates
    // as a pinned beam of the support spacing s, ω = (π/s)² √(EI/ρ), whatever the supports.
    let (l, ei, rho, k, spacing) = (100.0, 1.5e5, 6.5, 2.0e6, 10.0);
    let n = 200;
    let mut b = ModelBuilder::single_wire(l, n, rho, 0.0, ei)
        .moving_force("probe", 0.0)
        .run(0.0, 5.0, 1.0, 1e-4);
    for j in 1..10 {
        b = b.point_mass(spacing * j as f64, 0.0, k);
    }
    let mut s = stepper(b);
    let blk = wire(&s);
    // sin(πx/s) is the basis' mode L/s.
    let m = (l / spacing) as usize;
    s.state.q_mut(s.integ.model(), blk)[m - 1] = 0.001;
    let basis = SineBasis::new(l, n);
    let mut row = vec![0.0; n];
    let (mut ts, mut ys) = (Vec::new(), Vec::new());
    for _ in 0..20_000 {
        s.step();
        ts.push(s.state.t);
        ys.push(basis.eval(s.state.q(s.model(), blk), 0.5 * spacing, &mut row));
    }
    let measured = 2.0 * PI / mean_period(&zero_crossings(&ts, &ys));
    let exact = (PI / spacing).powi(2) * (ei / rho).sqrt();
    assert!(
        (measured - exact).abs() < 1e-3 * exact,
        "ω measured {measured} vs the pinned span's {exact}"
    );
}
