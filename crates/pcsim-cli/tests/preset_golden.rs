//! Five preset runs against `data/golden/preset_runs.json`, made by
//! `scripts/gen_preset_golden.py` with the build before the core restructure (issue 9): every
//! EN 50318 statistic and the run statistics must be identical, and `timeseries.csv`
//! byte-identical (its FNV-1a hash and size).

use std::process::Command;

fn fnv1a64(data: &[u8]) -> String {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for &b in data {
        h ^= b as u64;
        h = h.wrapping_mul(0x0100_0000_01b3);
    }
    format!("{h:016x}")
}

#[test]
fn five_preset_runs_are_unchanged() {
    let golden: serde_json::Value =
        serde_json::from_str(include_str!("../../../data/golden/preset_runs.json")).unwrap();
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
                for (a, b) in gp.iter().zip(sp) {
                    assert_eq!(a["name"], b["name"]);
                    for (k, v) in a["stats"].as_object().unwrap() {
                        assert_eq!(
                            v.as_f64().unwrap().to_bits(),
                            b["stats"][k].as_f64().unwrap().to_bits(),
                            "{preset} at {speed} km/h, {}: {k} = {} vs golden {v}",
                            a["name"],
                            b["stats"][k]
                        );
                    }
                }
                assert_eq!(
                    g["run_statistics"], summary["run_statistics"],
                    "{preset} at {speed} km/h: run statistics"
                );
                let ts = std::fs::read(out.join("timeseries.csv")).unwrap();
                assert_eq!(ts.len() as u64, g["timeseries_bytes"].as_u64().unwrap());
                assert_eq!(
                    fnv1a64(&ts),
                    g["timeseries_fnv1a64"].as_str().unwrap(),
                    "{preset} at {speed} km/h: timeseries.csv differs"
                );
            });
        }
    });
    let _ = std::fs::remove_dir_all(&dir);
}
