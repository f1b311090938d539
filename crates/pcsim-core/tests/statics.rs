//! Static shape from the design geometry: heights at the droppers within 1 mm of the design (by
//! an independent modal solve of each wire, EI included), and the vertical force balance.

use pcsim_core::basis::SineBasis;
use pcsim_core::case::G;
use pcsim_core::model::static_balance;
use pcsim_core::presets;
use pcsim_core::statics::{modal_static_deflection, presag_at_droppers, StaticSolution};

fn check_heights(preset: &str) {
    let (mut case, _) = presets::load(preset).unwrap();
    case.catenary.spans = 6; // a short model is enough for the statics; spans are identical
    let c = &case.catenary;
    let s = StaticSolution::solve(c);
    let l = case.length_m();
    let n = (8.0 * l) as usize;
    let basis = SineBasis::new(l, n);
    let mut row = vec![0.0; n];
    // The modal model pins both wires at the model ends; where the steady arm does not hold the
    // contact wire (stitched), the first and last spans feel that, so compare interior spans.
    let spans: Vec<usize> = if c.steady_arm.static_support {
        (0..c.spans).collect()
    } else {
        (1..c.spans - 1).collect()
    };

    // Contact wire: weight down, dropper tensions (minus the clamp weight they also carry) up,
    // steady arms up at the interior supports.
    let mut loads = Vec::new();
    for k in 0..c.spans {
        for (i, d) in c.droppers.positions_m.iter().enumerate() {
            loads.push((
                k as f64 * c.span_m + d,
                s.dropper_force_contact_n[i] - c.droppers.clamp_mass_contact_kg * G,
            ));
        }
    }
    for k in 1..c.spans {
        loads.push((k as f64 * c.span_m, s.arm_force_n));
    }
    let q = modal_static_deflection(
        &basis,
        c.contact_wire.tension_n,
        c.contact_wire.ei_nm2,
        -c.contact_wire.mass_per_m_kg * G,
        &loads,
    );
    let presag = presag_at_droppers(c);
    for &k in &spans {
        for (i, d) in c.droppers.positions_m.iter().enumerate() {
            let x = k as f64 * c.span_m + d;
            let h = basis.eval(&q, x, &mut row);
            assert!(
                (h + presag[i]).abs() < 1e-3,
                "{preset}: contact wire at x={x}: {h} vs design {}",
                -presag[i]
            );
            // The analytic profile agrees too.
            assert!((s.contact_height(x) + presag[i]).abs() < 1e-12);
        }
    }

    // Messenger: weight, the loads hanging at each dropper position (dropper tension, clamp; or
    // the whole stitch element force) down, supports up.
    let hanging: Vec<f64> = (0..c.droppers.positions_m.len())
        .map(|i| match s.stitch[i] {
            Some(st) => st.force_n,
            None => s.dropper_force_messenger_n[i] + c.droppers.clamp_mass_messenger_kg * G,
        })
        .collect();
    let mut loads = Vec::new();
    for k in 0..c.spans {
        for (i, d) in c.droppers.positions_m.iter().enumerate() {
            loads.push((k as f64 * c.span_m + d, -hanging[i]));
        }
    }
    for k in 1..c.spans {
        loads.push((k as f64 * c.span_m, s.support_force_n));
    }
    let q = modal_static_deflection(
        &basis,
        c.messenger.tension_n,
        c.messenger.ei_nm2,
        -c.messenger.mass_per_m_kg * G,
        &loads,
    );
    for k in 0..c.spans {
        for (i, d) in c.droppers.positions_m.iter().enumerate() {
            let x = k as f64 * c.span_m + d;
            let h = basis.eval(&q, x, &mut row) + c.encumbrance_m;
            let expect = s.messenger_height_at_dropper(i);
            assert!(
                (h - expect).abs() < 1e-3,
                "{preset}: messenger at x={x}: {h} vs {expect}"
            );
        }
    }
    // Dropper lengths are the height differences (less the stitch sag) and positive.
    for (i, len) in s.dropper_length_m.iter().enumerate() {
        let sag = s.stitch[i].map_or(0.0, |st| st.force_n / st.stiffness_n_per_m);
        let expect =
            s.messenger_height_at_dropper(i) - sag - s.contact_height(c.droppers.positions_m[i]);
        assert!((len - expect).abs() < 1e-12);
        assert!(
            *len > 0.1 && *len < c.encumbrance_m + 0.1,
            "dropper {i}: {len}"
        );
    }
}

#[test]
fn design_heights_within_1mm_en50318_2002() {
    check_heights("en50318-2002");
}

#[test]
fn design_heights_within_1mm_benchmark_55m() {
    check_heights("benchmark-55m");
}

#[test]
fn vertical_forces_balance() {
    for preset in ["en50318-2002", "benchmark-55m"] {
        let (case, _) = presets::load(preset).unwrap();
        let b = static_balance(&case);
        assert!(b.weight_n > 1e4);
        assert!(
            (b.weight_n - b.support_n).abs() < 1e-9 * b.weight_n,
            "{preset}: weights {} vs supports {}",
            b.weight_n,
            b.support_n
        );
    }
}

#[test]
fn steady_arm_carries_the_large_static_force_readme_reports() {
    // README §5: about 200 N when the pre-sag is zero at the supports (§3.1 data).
    let (case, _) = presets::load("en50318-2002").unwrap();
    let s = StaticSolution::solve(&case.catenary);
    assert!(
        (s.arm_force_n - 200.0).abs() < 20.0,
        "arm force {}",
        s.arm_force_n
    );
}

#[test]
fn benchmark_dropper_lengths_close_to_published_nominal_lengths() {
    // ref §3.2 lists nominal dropper lengths; our statics derive them from the design heights.
    let nominal = [
        1.017, 0.896, 0.810, 0.758, 0.741, 0.758, 0.810, 0.896, 1.017,
    ];
    let (case, _) = presets::load("benchmark-55m").unwrap();
    let s = StaticSolution::solve(&case.catenary);
    // Absolute lengths agree within 10 mm (ours are ~8 mm longer throughout: a constant such as
    // clamp length in the published definition); the shape relative to the mid-span dropper
    // agrees within 2 mm.
    let mid = s.dropper_length_m[4];
    for (i, (got, want)) in s.dropper_length_m.iter().zip(nominal).enumerate() {
        assert!(
            (got - want).abs() < 0.010,
            "dropper {i}: {got:.4} m vs nominal {want} m"
        );
        assert!(
            ((got - mid) - (want - nominal[4])).abs() < 0.002,
            "dropper {i}: shape {:.4} vs {:.4}",
            got - mid,
            want - nominal[4]
        );
    }
}
