//! Issue 54: current collection. The laws' exact checks on passages made by hand (a trace of
//! known force, gap, lateral path and current): Archard's law for a constant force over a known
//! distance; the lateral sweep of a straight zig-zag is 2sv/L; no loss of contact, no arc; a
//! doubled current doubles the electrical term (the law is linear in the charge); an arc burns
//! exactly until the gap passes its extinction gap; Holm's constriction resistance; the worn
//! depth of a round wire. Then the spec: every value sourced, every error naming its field.

use pcsim_core::analysis::record::PantographTrace;
use pcsim_core::study::wear::{
    archard_volume_m3, contact_resistance_ohm, passage, sweep, worn_depth_m, Bins, Train, WearSpec,
    DEFAULT_SPEC,
};

/// A trace made by hand: `n` steps of `dt` at `v` from `x0`, each step's force, gap and lateral
/// position from the functions of its position.
fn trace(
    x0: f64,
    v: f64,
    dt: f64,
    n: usize,
    force: impl Fn(f64) -> f64,
    gap: impl Fn(f64) -> f64,
    lateral: Option<&dyn Fn(f64) -> f64>,
) -> PantographTrace {
    let x: Vec<f64> = (0..n).map(|k| x0 + v * dt * k as f64).collect();
    PantographTrace {
        name: "leading".into(),
        force_n: x.iter().map(|&p| force(p)).collect(),
        force_filtered_n: vec![0.0; n],
        wire_height_m: vec![0.0; n],
        max_uplift_at_support_m: 0.0,
        stats: None,
        lateral_m: lateral.map_or(Vec::new(), |f| x.iter().map(|&p| f(p)).collect()),
        twist_rad: Vec::new(),
        head_half_width_m: Some(0.8),
        lateral: None,
        wire_forces: Vec::new(),
        overlaps: Vec::new(),
        hard_spots: Vec::new(),
        strips: Vec::new(),
        gap_m: x.iter().map(|&p| gap(p)).collect(),
        position_m: x,
    }
}

/// 3000 steps of 1 ms at 70 m/s, the force 120 ± 40 N and never lost.
fn pressing() -> PantographTrace {
    trace(
        0.0,
        70.0,
        1e-3,
        3000,
        |x| 120.0 + 40.0 * (x / 7.0).sin(),
        |_| -1e-4,
        None,
    )
}

fn spec() -> WearSpec {
    WearSpec::from_toml_str(DEFAULT_SPEC).unwrap()
}

fn train(current_a: f64) -> Train {
    let mut t = spec().trains[0].clone();
    t.current_a.value = current_a;
    t
}

fn bins(section_m: [f64; 2]) -> Bins {
    Bins {
        section_m,
        bin_m: 1.0,
        half_width_m: 0.8,
        strip: 60,
    }
}

#[test]
fn a_constant_force_over_a_known_distance_wears_as_archards_law() {
    let s = spec();
    let (v, dt, f) = (50.0, 1e-3, 150.0);
    // 0.05 m a step from 90 m to 210 m: the section [100, 200] m holds 2001 samples.
    let tr = trace(90.0, v, dt, 2401, |_| f, |_| -1e-4, None);
    let p = passage(&tr, dt, v, &train(0.0), &s.law, &bins([100.0, 200.0]), 0);
    let inside = tr
        .position_m
        .iter()
        .filter(|&&x| (100.0..=200.0).contains(&x))
        .count();
    let (k, h) = (s.law.wire_archard_k.value, s.law.wire_hardness_pa.value);
    let exact = k * f * (inside as f64 * v * dt) / h;
    assert!(
        ((p.wire_terms_m3[0] - exact) / exact).abs() < 1e-12,
        "{} vs {exact}",
        p.wire_terms_m3[0]
    );
    assert_eq!(archard_volume_m3(k, h, f, 100.0), k * f * 100.0 / h);
    // The continuum: K F L / H over the 100 m section, to one step.
    let continuum = k * f * 100.0 / h;
    assert!(((p.wire_terms_m3[0] - continuum) / continuum).abs() < 1e-3);
    // Without current the electrical and arc terms are zero; the profile sums to the total.
    assert_eq!(p.wire_terms_m3[1], 0.0);
    assert_eq!(p.wire_terms_m3[2], 0.0);
    let summed: f64 = p.wire_m3.iter().sum();
    assert!(((summed - exact) / exact).abs() < 1e-12);
    // Each 1 m bin holds K F / H per metre, to one step in twenty.
    let per_m = k * f / h;
    for w in &p.wire_m3[1..99] {
        assert!(((w - per_m) / per_m).abs() < 0.051, "{w} vs {per_m}");
    }
}

#[test]
fn the_lateral_sweep_of_a_straight_zigzag_is_2sv_over_l() {
    let (s, l, v, dt) = (0.3, 60.0, 80.0, 1e-4);
    // The stagger +s, −s, +s … at supports every L, straight between.
    let zig = move |x: f64| {
        let j = (x / l).floor();
        let u = x / l - j;
        let sign = if (j as i64) % 2 == 0 { 1.0 } else { -1.0 };
        sign * s * (1.0 - 2.0 * u)
    };
    let n = (600.0 / (v * dt)) as usize + 1;
    let tr = trace(0.0, v, dt, n, |_| 100.0, |_| -1e-4, Some(&zig));
    let supports: Vec<f64> = (0..=10).map(|j| j as f64 * l).collect();
    let spans = sweep(&tr, dt, &supports, [0.0, 600.0]);
    assert_eq!(spans.len(), 10);
    let exact = 2.0 * s * v / l;
    for sp in &spans {
        assert!(
            ((sp.speed_m_s - exact) / exact).abs() < 1e-9,
            "{} vs {exact}",
            sp.speed_m_s
        );
    }
    // Below 330 mm/s at 30 km/h, above it at 80 m/s: the figure of merit counts them.
    let merit = pcsim_core::study::wear::sweep_output(spans, 0.33).unwrap();
    assert_eq!(merit.share_below_limit_percent, 0.0);
    let slow = trace(0.0, 8.0, 1e-3, 75_001, |_| 100.0, |_| -1e-4, Some(&zig));
    let m =
        pcsim_core::study::wear::sweep_output(sweep(&slow, 1e-3, &supports, [0.0, 600.0]), 0.33)
            .unwrap();
    assert_eq!(m.share_below_limit_percent, 100.0);
    assert!((m.least_m_s - 2.0 * s * 8.0 / l).abs() < 1e-9);
}

#[test]
fn without_a_loss_of_contact_there_is_no_arc() {
    let s = spec();
    let tr = pressing();
    let p = passage(
        &tr,
        1e-3,
        70.0,
        &train(600.0),
        &s.law,
        &bins([10.0, 200.0]),
        0,
    );
    assert!(p.arcs.is_empty());
    assert_eq!(p.arc_time_s, 0.0);
    assert_eq!(p.loss_time_s, 0.0);
    assert_eq!(p.wire_terms_m3[2], 0.0);
    assert!(p.joule_j > 0.0 && p.wire_terms_m3[1] > 0.0);
}

#[test]
fn a_doubled_current_doubles_the_electrical_term() {
    let s = spec();
    let tr = pressing();
    let b = bins([10.0, 200.0]);
    let one = passage(&tr, 1e-3, 70.0, &train(300.0), &s.law, &b, 0);
    let two = passage(&tr, 1e-3, 70.0, &train(600.0), &s.law, &b, 0);
    for k in 0..2 {
        let (a, b) = (
            [one.wire_terms_m3[1], one.strip_terms_m3[1]][k],
            [two.wire_terms_m3[1], two.strip_terms_m3[1]][k],
        );
        assert!((b / a - 2.0).abs() < 1e-12, "{b} / {a}");
    }
    // The mechanical term does not see the current; the Joule heat goes as its square.
    assert_eq!(one.wire_terms_m3[0], two.wire_terms_m3[0]);
    assert!((two.joule_j / one.joule_j - 4.0).abs() < 1e-12);
}

#[test]
fn an_arc_burns_until_the_gap_passes_its_extinction_gap() {
    let s = spec();
    let (v, dt, i) = (50.0, 1e-4, 300.0);
    // Contact lost from 100 m to 101 m (20 ms), the gap opening at 0.5 m/s: it passes the
    // extinction gap (1e-5 m/A × 300 A = 3 mm) after 6 ms, 0.3 m after the loss.
    let lost = |x: f64| (100.0..101.0).contains(&x);
    let tr = trace(
        90.0,
        v,
        dt,
        4001,
        |x| if lost(x) { 0.0 } else { 140.0 },
        |x| {
            if lost(x) {
                0.5 * (x - 100.0) / v + 1e-6
            } else {
                -1e-4
            }
        },
        None,
    );
    let p = passage(&tr, dt, v, &train(i), &s.law, &bins([95.0, 105.0]), 0);
    assert_eq!(p.arcs.len(), 1, "{:?}", p.arcs);
    let g_ext = s.law.arc_gap_m_per_a.value * i;
    let burning = (0..tr.position_m.len())
        .filter(|&k| lost(tr.position_m[k]) && tr.gap_m[k] <= g_ext)
        .count();
    let a = &p.arcs[0];
    assert!((a.duration_s - burning as f64 * dt).abs() < 1e-12);
    assert!(
        (a.duration_s - 6e-3).abs() <= dt + 1e-12,
        "{}",
        a.duration_s
    );
    assert!((a.energy_j - s.law.arc_voltage_v.value * i * a.duration_s).abs() < 1e-9);
    assert!((a.start_m - 100.0).abs() < v * dt + 1e-9);
    assert!((p.arc_time_s - a.duration_s).abs() < 1e-15);
    let wire_arc = s.law.wire_arc_m3_per_j.value * a.energy_j;
    assert!(((p.wire_terms_m3[2] - wire_arc) / wire_arc).abs() < 1e-12);
    // The loss lasts 20 ms; NQ counts the arc only.
    assert!((p.loss_time_s - 0.02).abs() <= dt + 1e-12);
    // No current, no arc.
    let q = passage(&tr, dt, v, &train(0.0), &s.law, &bins([95.0, 105.0]), 0);
    assert!(q.arcs.is_empty() && q.arc_time_s == 0.0);
}

#[test]
fn holms_constriction_resistance_and_the_worn_depth_of_a_round_wire() {
    // R = (ρ1 + ρ2) / (4a), a = √(F / (πH)): 3e-5 Ω·m, 0.2 GPa, 100 N → 18.80 mΩ.
    let a = (100.0 / (std::f64::consts::PI * 0.2e9)).sqrt();
    let r = contact_resistance_ohm(3e-5, 0.2e9, 100.0);
    assert!((r - 3e-5 / (4.0 * a)).abs() < 1e-15);
    assert!((r - 0.018_800).abs() < 1e-5, "{r}");
    assert!((contact_resistance_ohm(3e-5, 0.2e9, 400.0) - r / 2.0).abs() < 1e-15);
    assert!(contact_resistance_ohm(3e-5, 0.2e9, 0.0).is_infinite());
    // Half the section worn: the depth is the radius; a thin flat: h ≈ (3A / (4√(2r)))^(2/3).
    let rad = 0.0062;
    let half = std::f64::consts::PI * rad * rad / 2.0;
    assert!((worn_depth_m(half, rad) - rad).abs() < 1e-12);
    assert_eq!(worn_depth_m(0.0, rad), 0.0);
    let small = 1e-8;
    let approx = (3.0 * small / (4.0 * (2.0 * rad).sqrt())).powf(2.0 / 3.0);
    assert!(((worn_depth_m(small, rad) - approx) / approx).abs() < 1e-2);
}

#[test]
fn the_default_spec_sources_every_value_and_errors_name_their_field() {
    let s = spec();
    for (field, v) in s.sourced() {
        assert!(!v.source.trim().is_empty(), "{field} has no source");
    }
    let case = pcsim_core::input::case_from_preset(&s.case).unwrap();
    s.check(&case).unwrap();
    let refused = |text: String, field: &str| {
        let e = match WearSpec::from_toml_str(&text) {
            Ok(sp) => sp.check(&case).unwrap_err().to_string(),
            Err(e) => e.to_string(),
        };
        assert!(e.contains(field), "{field}: {e}");
    };
    refused(DEFAULT_SPEC.replace("bin_m =", "bin_mm ="), "bin_mm");
    refused(
        DEFAULT_SPEC.replace("years = { value = 10.0", "years = { value = -1.0"),
        "years",
    );
    refused(
        DEFAULT_SPEC.replace(
            "source = \"hard-drawn copper, about 100 HV (handbook value)\"",
            "source = \" \"",
        ),
        "law.wire_hardness_pa",
    );
    refused(
        DEFAULT_SPEC.replace("realisations = 1", "realisations = 3"),
        "realisations",
    );
    refused(
        DEFAULT_SPEC.replace("kind = \"wear\"", "kind = \"weir\""),
        "kind",
    );
    refused(
        DEFAULT_SPEC.replace("bin_m = { value = 1.0", "bin_m = { value = 1e-9"),
        "bin_m",
    );
    refused(DEFAULT_SPEC.replace("[[trains]]", "[[trainz]]"), "trainz");
}

#[test]
fn realisations_over_the_seeds_give_the_same_bytes_twice_and_name_their_seeds() {
    use pcsim_core::study::wear::WearStudy;
    use pcsim_core::study::Study;
    // The zoo's catenary with an irregularity of its own: two realisations of one train.
    let (_, case) = pcsim_core::zoo::geometries::geometries()
        .into_iter()
        .find(|(g, _)| *g == "catenary, irregularity")
        .unwrap();
    let mut s = spec();
    s.trains.truncate(1);
    s.trains[0].speed_kmh.value = case.run.speed_kmh;
    s.realisations = 2;
    let study = WearStudy { spec: s, case };
    Study::check(&study).unwrap();
    let a = study.run(&|| {}).unwrap();
    let b = study.run(&|| {}).unwrap();
    let bytes = |o| serde_json::to_string(&o).unwrap();
    assert_eq!(bytes(a.clone()), bytes(b));
    assert_eq!(a.seed_offsets, vec![0, 1]);
    // A single realisation of the same case differs from their mean (the seeds matter).
    let mut one = study.clone();
    one.spec.realisations = 1;
    let c = one.run(&|| {}).unwrap();
    assert_ne!(c.wire.daily_mm3_per_m, a.wire.daily_mm3_per_m);
}

#[test]
fn no_current_flows_over_a_neutral_sections_dead_length() {
    use pcsim_core::study::wear::{current_at, without_current_over};
    // A constant current, and a profile: zero over each dead length, their own value elsewhere.
    let mut profiled = train(300.0);
    profiled.current_profile = vec![[0.0, 100.0], [1000.0, 500.0]];
    for t in [train(300.0), profiled] {
        let cut = without_current_over(&t, &[[200.0, 230.0], [600.0, 604.0]]);
        for x in [200.0, 215.0, 230.0, 600.0, 602.0, 604.0] {
            assert_eq!(current_at(&cut, x), 0.0, "at {x} m");
        }
        for x in [0.0, 150.0, 199.9, 230.1, 400.0, 599.5, 604.5, 900.0, 2000.0] {
            assert!(
                (current_at(&cut, x) - current_at(&t, x)).abs() < 1e-9,
                "at {x} m: {} vs {}",
                current_at(&cut, x),
                current_at(&t, x)
            );
        }
    }
}

#[test]
fn a_trains_speed_the_case_refuses_is_named_as_that_trains() {
    use pcsim_core::error::{CaseError, SimError};
    use pcsim_core::study::wear::WearStudy;
    use pcsim_core::study::Study;
    // The zoo's catenary.
    let case = crate::common::short_en50318(8, 250.0);
    let mut s = spec();
    s.trains.truncate(2);
    s.trains[0].speed_kmh.value = case.run.speed_kmh;
    s.trains[1].speed_kmh.value = 1500.0;
    let study = WearStudy { spec: s, case };
    match study.run(&|| {}) {
        Err(SimError::Case(CaseError::Invalid { field, .. })) => {
            assert_eq!(field, "trains[1].speed_kmh")
        }
        other => panic!("not refused by the train's field: {other:?}"),
    }
}
