//! Zero-phase Butterworth filters against SciPy's `sosfiltfilt(butter(...))` output, committed in
//! `data/golden/filter_golden.csv` by `scripts/gen_filter_golden.py`.

use pcsim_core::analysis::filter::{butter, Band};

fn golden() -> (Vec<String>, Vec<Vec<Option<f64>>>) {
    let text = include_str!("../../../../data/golden/filter_golden.csv");
    let mut lines = text.lines();
    let names: Vec<String> = lines.next().unwrap().split(',').map(String::from).collect();
    let mut cols = vec![Vec::new(); names.len()];
    for l in lines {
        for (c, v) in l.split(',').enumerate() {
            cols[c].push(if v.is_empty() {
                None
            } else {
                Some(v.parse::<f64>().unwrap())
            });
        }
    }
    (names, cols)
}

fn check(name: &str, order: usize, band: Band, fs: f64, step: usize) {
    let (names, cols) = golden();
    let x: Vec<f64> = cols[0].iter().step_by(step).map(|v| v.unwrap()).collect();
    let c = names.iter().position(|n| n == name).unwrap();
    let expect: Vec<f64> = cols[c].iter().flatten().copied().collect();
    let y = butter(order, band, fs).filtfilt(&x);
    assert_eq!(y.len(), expect.len());
    let scale = expect.iter().map(|v| v.abs()).fold(0.0, f64::max);
    let err = y
        .iter()
        .zip(&expect)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    assert!(
        err < 1e-9 * scale.max(1.0),
        "{name}: max abs error {err} vs SciPy"
    );
}

#[test]
fn lowpass_20hz_matches_scipy() {
    check("lp20", 4, Band::Lowpass(20.0), 1000.0, 1);
}

#[test]
fn lowpass_5hz_matches_scipy() {
    check("lp5", 4, Band::Lowpass(5.0), 1000.0, 1);
}

#[test]
fn bandpass_5_20hz_matches_scipy() {
    check("bp5_20", 4, Band::Bandpass(5.0, 20.0), 1000.0, 1);
}

#[test]
fn odd_order_at_another_rate_matches_scipy() {
    check("lp20_order3_fs500", 3, Band::Lowpass(20.0), 500.0, 2);
}

#[test]
fn lowpass_has_unit_dc_gain_and_kills_high_tones() {
    let fs = 1000.0;
    let n = 6000;
    let x: Vec<f64> = (0..n)
        .map(|i| 100.0 + 10.0 * (2.0 * std::f64::consts::PI * 60.0 * i as f64 / fs).sin())
        .collect();
    let y = butter(4, Band::Lowpass(20.0), fs).filtfilt(&x);
    for v in &y[500..n - 500] {
        assert!((v - 100.0).abs() < 0.01, "{v}");
    }
}
