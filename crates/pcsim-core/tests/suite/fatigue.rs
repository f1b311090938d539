//! Dropper fatigue (issue 22, item 5): the rainflow count against the golden of an independent
//! tool (the Python `rainflow` package, ASTM E1049-85 §5.4.4; `scripts/gen_rainflow_golden.py`),
//! exactly; the droppers' tensions through a run over a line with an overlap, their cycles and
//! Miner's damage.

use crate::common;

use pcsim_core::analysis::fatigue::{rainflow, Cycle};

fn root() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn csv(name: &str) -> Vec<Vec<String>> {
    std::fs::read_to_string(root().join("data/golden/rainflow").join(name))
        .unwrap()
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(str::to_owned).collect())
        .collect()
}

/// Every cycle of five series (sines, a dropper-like record with a slack plateau, integer values
/// full of ties, a random walk, a short record): range, mean, count and both indices, in the
/// golden's order, bit for bit.
#[test]
fn rainflow_matches_the_golden_exactly() {
    let series = csv("series.csv");
    let cycles = csv("cycles.csv");
    let n = series
        .iter()
        .map(|r| r[0].parse::<usize>().unwrap())
        .max()
        .unwrap()
        + 1;
    let mut total = 0;
    for k in 0..n {
        let x: Vec<f64> = series
            .iter()
            .filter(|r| r[0].parse::<usize>().unwrap() == k)
            .map(|r| r[1].parse().unwrap())
            .collect();
        let want: Vec<Cycle> = cycles
            .iter()
            .filter(|r| r[0].parse::<usize>().unwrap() == k)
            .map(|r| Cycle {
                range: r[1].parse().unwrap(),
                mean: r[2].parse().unwrap(),
                count: r[3].parse().unwrap(),
                start: r[4].parse().unwrap(),
                end: r[5].parse().unwrap(),
            })
            .collect();
        let got = rainflow(&x);
        assert_eq!(got.len(), want.len(), "series {k}: number of cycles");
        for (i, (g, w)) in got.iter().zip(&want).enumerate() {
            assert_eq!(g, w, "series {k}, cycle {i}");
        }
        total += got.len();
    }
    assert!(total > 1000, "{total} cycles");
}

/// Over a line with an overlap (two tension lengths of six 60 m spans, a 3-span overlap,
/// 250 km/h), every dropper's tension is followed through the run: the kept history gives the
/// same extremes, slack steps and cycles as the streamed count, every dropper starts at its
/// preload, the droppers of both tension lengths inside the overlap are among them, and Miner's
/// damage is each dropper's cycles on the S–N curve.
#[test]
fn dropper_tensions_cycles_and_damage_over_a_line_with_an_overlap() {
    use pcsim_core::analysis::fatigue::SnCurve;
    use pcsim_core::analysis::record::{simulate_with, DropperOptions};
    let case = common::overlap_line();
    let setup = pcsim_core::Setup::from_case(&case).unwrap();
    let curve = SnCurve {
        m: 5.0,
        stress_range_pa: 100e6,
        cycles: 2e6,
        area_m2: 10e-6,
    };
    let opts = DropperOptions {
        history: true,
        history_limit: 50_000_000,
        curve: Some(curve),
    };
    let out = simulate_with(&setup, Some(opts), &mut |_| true).unwrap();
    let d = out.droppers.as_ref().unwrap();
    let h = d.history.as_ref().unwrap();
    let n = d.droppers.len();
    let steps = out.time_s.len();
    assert_eq!(h.len(), n * steps);
    let mut in_overlap = std::collections::BTreeSet::new();
    for (i, f) in d.droppers.iter().enumerate() {
        let x: Vec<f64> = (0..steps).map(|k| h[k * n + i]).collect();
        let (lo, hi) = x
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
                (a.min(v), b.max(v))
            });
        assert_eq!((lo, hi), (f.min_n, f.max_n), "dropper {i}");
        assert_eq!(x.iter().filter(|&&v| v == 0.0).count(), f.slack_steps);
        let cycles = rainflow(&x);
        assert_eq!(cycles.iter().map(|c| c.count).sum::<f64>(), f.cycles);
        let dmg = curve.damage(&cycles);
        assert_eq!(Some(dmg), f.damage, "dropper {i}");
        assert!(
            (x[0] - f.preload_n).abs() < 0.05 * f.preload_n,
            "dropper {i} at {} m starts at {} N, preload {} N",
            f.x_m,
            x[0],
            f.preload_n
        );
        if f.x_m > 180.0 && f.x_m < 360.0 {
            in_overlap.insert(f.wire.clone());
        }
    }
    assert_eq!(
        in_overlap.len(),
        2,
        "droppers of both tension lengths in the overlap"
    );
    // The pantograph excites the droppers it passes: the largest damage is where it ran.
    let worst = d
        .droppers
        .iter()
        .max_by(|a, b| a.damage.partial_cmp(&b.damage).unwrap())
        .unwrap();
    assert!(worst.damage.unwrap() > 0.0 && worst.x_m > 60.0 && worst.x_m < 480.0);
    // A history beyond its limit is not kept; the counts are the same.
    let opts = DropperOptions {
        history_limit: n * steps - 1,
        ..opts
    };
    let again = simulate_with(&setup, Some(opts), &mut |_| true).unwrap();
    let d2 = again.droppers.unwrap();
    assert!(d2.history.is_none());
    assert_eq!(d2.droppers, d.droppers);
}
