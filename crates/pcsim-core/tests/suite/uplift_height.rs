//! Issue 43, item 2: a frame whose static force depends on the head's working height. A table
//! constant at the case's uplift gives the run without it to the bit; the static start solves
//! the chain with the force at the height it settles at; a run's mean contact force follows the
//! table's slope over the heights the head works at; a bad table is refused by its field.

use crate::common;

use pcsim_core::input::case::{PantographCase, UpliftByHeight};
use pcsim_core::model::pantograph::{Lumped, UpliftTable};
use pcsim_core::run_case;

fn with_table(mut c: pcsim_core::Case, table: UpliftByHeight) -> pcsim_core::Case {
    if let PantographCase::Lumped {
        uplift_by_height, ..
    } = &mut c.pantographs[0]
    {
        *uplift_by_height = Some(table);
    }
    c
}

#[test]
fn issue_43_2_a_constant_table_is_the_constant_uplift_to_the_bit() {
    let case = common::short_en50318(8, 250.0);
    let flat = with_table(
        case.clone(),
        UpliftByHeight {
            height_m: vec![-1.0, 1.0],
            uplift_n: vec![117.0, 117.0],
        },
    );
    let (a, b) = (
        run_case(&case, &mut |_| true).unwrap(),
        run_case(&flat, &mut |_| true).unwrap(),
    );
    assert_eq!(a.pantographs[0].force_n, b.pantographs[0].force_n);
}

#[test]
fn issue_43_2_the_static_start_uses_the_force_at_its_own_height() {
    let p = Lumped {
        masses_kg: vec![7.2, 15.0],
        stiffness_n_per_m: vec![4200.0, 50.0],
        damping_ns_per_m: vec![10.0, 90.0],
        uplift_n: 117.0,
        uplift_by_height: Some(UpliftTable {
            height_m: vec![-0.5, 0.0, 0.5],
            uplift_n: vec![137.0, 117.0, 107.0],
        }),
        aero_coeffs_kmh: vec![0.0],
        strips: Vec::new(),
    };
    let ops = p.operators(1e-3, 250.0).unwrap();
    let kn = 50_000.0;
    for wire in [-0.3, -0.05, 0.0, 0.2] {
        let y = ops.static_equilibrium(kn, wire).unwrap();
        // (K + k_n e₀e₀ᵀ) y = uplift(y₀) e₁ + k_n h e₀, to the iteration's tolerance.
        let f = p.uplift_by_height.as_ref().unwrap().at(y[0]);
        let r0 = (4200.0 + kn) * y[0] - 4200.0 * y[1] - kn * wire;
        let r1 = -4200.0 * y[0] + (4200.0 + 50.0) * y[1] - f;
        assert!(r0.abs() < 1e-6 && r1.abs() < 1e-6, "{wire}: {r0} {r1}");
        // The contact force is the table's force at the head less the roof spring's share.
        let contact = kn * (y[0] - wire);
        assert!((contact - (f - 50.0 * y[1])).abs() < 1e-6, "{wire}");
    }
    // Linear between the points, the end values beyond.
    let t = p.uplift_by_height.as_ref().unwrap();
    assert_eq!(
        (t.at(-1.0), t.at(-0.25), t.at(0.25), t.at(2.0)),
        (137.0, 127.0, 112.0, 107.0)
    );
}

#[test]
fn issue_43_2_the_mean_force_follows_the_table_over_the_working_heights() {
    let case = common::short_en50318(8, 250.0);
    // 100 N per metre of height: the pressed wire lifts the head a few centimetres.
    let sloped = with_table(
        case.clone(),
        UpliftByHeight {
            height_m: vec![-1.0, 1.0],
            uplift_n: vec![17.0, 217.0],
        },
    );
    let (a, b) = (
        run_case(&case, &mut |_| true).unwrap(),
        run_case(&sloped, &mut |_| true).unwrap(),
    );
    let (sa, sb) = (
        a.pantographs[0].stats.unwrap(),
        b.pantographs[0].stats.unwrap(),
    );
    let p = &b.pantographs[0];
    let [x0, x1] = b.analysis_m;
    let heights: Vec<f64> = p
        .position_m
        .iter()
        .zip(&p.wire_height_m)
        .filter(|(x, _)| (x0..=x1).contains(*x))
        .map(|(_, h)| *h)
        .collect();
    let mean_h = heights.iter().sum::<f64>() / heights.len() as f64;
    // The mean force moves by the slope times the mean working height (within 0.3 N: the
    // dynamics and the roof spring's share).
    let expected = 100.0 * mean_h;
    assert!(
        mean_h.abs() > 0.005,
        "the head works away from height 0: {mean_h}"
    );
    assert!(
        (sb.mean_n - sa.mean_n - expected).abs() < 0.3,
        "{} − {} against {expected}",
        sb.mean_n,
        sa.mean_n
    );
}

#[test]
fn issue_43_2_a_bad_table_is_refused_by_its_field() {
    let case = common::short_en50318(8, 250.0);
    for (h, f, says) in [
        (vec![0.0], vec![117.0], "at least two points"),
        (vec![-1.0, 1.0], vec![117.0], "as many forces"),
        (vec![1.0, -1.0], vec![117.0, 117.0], "increase"),
        (vec![-1.0, f64::NAN], vec![117.0, 117.0], "height_m[1]"),
        (vec![-1.0, 1.0], vec![100.0, 100.0], "make them agree"),
    ] {
        let c = with_table(
            case.clone(),
            UpliftByHeight {
                height_m: h,
                uplift_n: f,
            },
        );
        let e = c.validate().unwrap_err().to_string();
        assert!(
            e.contains("pantographs[0].uplift_by_height") && e.contains(says),
            "{e}"
        );
    }
}

/// Issue 51, item 2: a table too steep for the chain to rest on the wire is refused by its own
/// field, `uplift_by_height`, naming its slope (it was refused under `stiffness_n_per_m`).
#[test]
fn issue_51_a_table_too_steep_to_rest_on_is_refused_by_its_field() {
    let steep = with_table(
        common::short_en50318(8, 250.0),
        UpliftByHeight {
            height_m: vec![-0.001, 0.0, 0.001],
            uplift_n: vec![5000.0, 117.0, 0.0],
        },
    );
    let e = pcsim_core::compile::Setup::from_case(&steep)
        .and_then(|s| s.integrator())
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("pantographs[0].uplift_by_height") && e.contains("4.8830e6 N/m"),
        "{e}"
    );
}
