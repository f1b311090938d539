//! Five preset runs against `data/golden/preset_runs.json`, made by
//! `scripts/gen_preset_golden.py` with the build before the core restructure (issue 9).
//!
//! Through the restructure every statistic and `timeseries.csv` (its FNV-1a hash) stayed
//! identical. The speed work (issue 11) changed the arithmetic on purpose (FFT transforms,
//! fused multiply-adds), so the statistics are compared within [`TOL`] relative, and the run
//! statistics (counts) exactly where the run is not chaotic. `benchmark-55m` at 275 km/h is
//! chaotic: perturbing its uplift by 1e-11 relative moves the old build's statistics by up to
//! 1e-2 (docs/validation.md), so no change of rounding can keep them within 1e-6; it is held to
//! [`TOL_CHAOTIC`], the spread that perturbation showed.

use std::process::Command;

/// Relative tolerance of the statistics.
const TOL: f64 = 1e-6;
/// The same for the chaotic run.
const TOL_CHAOTIC: f64 = 3e-2;

#[test]
fn five_preset_runs_are_unchanged() {
    let golden: serde_json::Value =
        serde_json::from_str(include_str!("../../../../data/golden/preset_runs.json")).unwrap();
    let runs = golden.as_array().unwrap();
    assert_eq!(runs.len(), 5);
    let dir = std::env::temp_dir().join(format!("pcsim-preset-golden-{}", std::process::id()));
    std::thread::scope(|s| {
        for (i, g) in runs.iter().enumerate() {
            let out = dir.join(format!("run{i}"));
            s.spawn(move || {
                let preset = g["preset"].as_str().unwrap();
                let speed = g["speed_kmh"].to_string();
                let r = Command::new(env!("CARGO_BIN_EXE_pcsim"))
                    .args([
                        "run", "--preset", preset, "--speed", &speed, "--quiet", "--out",
                    ])
                    .arg(&out)
                    .output()
                    .unwrap();
                assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
                let summary: serde_json::Value = serde_json::from_str(
                    &std::fs::read_to_string(out.join("summary.json")).unwrap(),
                )
                .unwrap();
                let gp = g["pantographs"].as_array().unwrap();
                let sp = summary["pantographs"].as_array().unwrap();
                assert_eq!(gp.len(), sp.len());
                let chaotic = preset == "benchmark-55m";
                let tol = if chaotic { TOL_CHAOTIC } else { TOL };
                for (a, b) in gp.iter().zip(sp) {
                    assert_eq!(a["name"], b["name"]);
                    for (k, v) in a["stats"].as_object().unwrap() {
                        let (want, got) = (v.as_f64().unwrap(), b["stats"][k].as_f64().unwrap());
                        assert!(
                            (got - want).abs() <= tol * want.abs().max(1e-9),
                            "{preset} at {speed} km/h, {}: {k} = {got} vs golden {want}",
                            a["name"]
                        );
                    }
                }
                if !chaotic {
                    assert_eq!(
                        g["run_statistics"], summary["run_statistics"],
                        "{preset} at {speed} km/h: run statistics"
                    );
                }
            });
        }
    });
    let _ = std::fs::remove_dir_all(&dir);
}
