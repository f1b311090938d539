//! The stitched presets: two pantographs on `stitched-2018-like` and the SYT calibration.

use pcsim_core::study::validate::{compare, target_cases};
use pcsim_core::{presets, run_case};

/// Table 1 rows that pass today and must keep passing: (speed, pantograph, quantity).
const MUST_PASS: &[(f64, &str, &str)] = &[
    (275.0, "leading", "mean"),
    (275.0, "leading", "actual_min"),
    (275.0, "leading", "contact_point_range_mm"),
    (275.0, "leading", "loss_of_contact_percent"),
    (275.0, "trailing", "mean"),
    (275.0, "trailing", "max_uplift_at_support_mm"),
    (275.0, "trailing", "loss_of_contact_percent"),
    (320.0, "leading", "mean"),
    (320.0, "leading", "std"),
    (320.0, "leading", "std_5_20hz"),
    (320.0, "leading", "actual_max"),
    (320.0, "leading", "actual_min"),
    (320.0, "leading", "contact_point_range_mm"),
    (320.0, "leading", "loss_of_contact_percent"),
    (320.0, "trailing", "mean"),
    (320.0, "trailing", "std_0_5hz"),
    (320.0, "trailing", "loss_of_contact_percent"),
];

#[test]
fn seed_table1_rows_and_the_trailing_pantograph_at_320() {
    let (base, _) = presets::load("stitched-2018-like").unwrap();
    let targets = target_cases("seed_table1").unwrap();
    assert_eq!(targets.len(), 4);
    let outs: Vec<_> = std::thread::scope(|s| {
        let hs: Vec<_> = [275.0, 320.0]
            .iter()
            .map(|&v| {
                let mut c = base.clone();
                c.run.speed_kmh = v;
                s.spawn(move || run_case(&c, &mut |_| true).unwrap())
            })
            .collect();
        hs.into_iter().map(|h| h.join().unwrap()).collect()
    });
    for t in &targets {
        let out = &outs[if t.speed_kmh == 275.0 { 0 } else { 1 }];
        let name = t.pantograph.as_deref().unwrap();
        let p = out.pantographs.iter().find(|p| p.name == name).unwrap();
        let rows = compare(&p.stats.unwrap(), t);
        assert_eq!(rows.rows.len(), 9);
        for r in &rows.rows {
            assert!(r.paper_value.is_some());
            if MUST_PASS.contains(&(t.speed_kmh, name, r.quantity.as_str())) {
                assert!(
                    r.pass,
                    "{} km/h {name} {} = {} left {:?}",
                    t.speed_kmh, r.quantity, r.value, r.range
                );
            }
        }
    }
    // The trailing pantograph runs on a wire the leading one has set swaying: at 320 km/h its σ
    // exceeds the leading one's, as in every published result.
    let s320 = |n: &str| {
        outs[1]
            .pantographs
            .iter()
            .find(|p| p.name == n)
            .unwrap()
            .stats
            .unwrap()
    };
    assert!(
        s320("trailing").std_n > 1.1 * s320("leading").std_n,
        "trailing {} vs leading {}",
        s320("trailing").std_n,
        s320("leading").std_n
    );
    // The means follow the EN 50367 target 0.00097 v² + 70 N they were calibrated to.
    for (out, v) in outs.iter().zip([275.0f64, 320.0]) {
        for p in &out.pantographs {
            let target = 0.00097 * v * v + 70.0;
            assert!(
                (p.stats.unwrap().mean_n - target).abs() < 0.6,
                "{} at {v}: {}",
                p.name,
                p.stats.unwrap().mean_n
            );
        }
    }
}

#[test]
fn syt_mean_matches_the_measured_85_1_n_at_222_kmh() {
    // The aerodynamic coefficient (and only it) is calibrated to the measured mean (paper §4.2).
    let (case, _) = presets::load("syt-7.0-9.8").unwrap();
    assert_eq!(case.run.speed_kmh, 222.0);
    let out = run_case(&case, &mut |_| true).unwrap();
    let s = out.pantographs[0].stats.unwrap();
    assert!((s.mean_n - 85.1).abs() < 0.3, "mean {}", s.mean_n);
    // σ is not calibrated; it is reported against the measured 18.2 N (docs/validation.md) and
    // guarded here against drifting far from it.
    assert!((s.std_n - 18.2).abs() < 0.15 * 18.2, "σ {}", s.std_n);
}
