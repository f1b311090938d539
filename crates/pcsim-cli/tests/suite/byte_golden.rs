//! The proof of issue 18's refactor: byte goldens made by the build before it
//! (`scripts/gen_byte_golden.py`, `scripts/gen_study_golden.sh`).
//!
//! - Eight preset runs (the eighth a [line], issue 21): `timeseries.csv` and `summary.json` (less its wall-clock line) hash to
//!   the same FNV-1a value, on the portable kernels always and on the AVX2 kernels where this
//!   machine has them; the 3D presets' warnings are the same.
//! - The rows of `pcsim eva`, `pcsim window` (and its `fit.csv`) and `pcsim validate --json` for a
//!   small grid are the same bytes (portable kernels).

use std::path::Path;
use std::process::Command;

fn root() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
}

fn fnv1a64(data: &[u8]) -> String {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for &b in data {
        h ^= b as u64;
        h = h.wrapping_mul(0x0100_0000_01b3);
    }
    format!("{h:016x}")
}

/// `summary.json` as written, less its line with the wall-clock time.
fn summary_without_wall(text: &str) -> Vec<u8> {
    text.split_inclusive('\n')
        .filter(|l| !l.contains("\"wall_time_s\""))
        .collect::<String>()
        .into_bytes()
}

fn pcsim(args: &[&str], dir: &Path, portable: bool) -> std::process::Output {
    let mut c = Command::new(env!("CARGO_BIN_EXE_pcsim"));
    c.args(args).current_dir(dir);
    if portable {
        c.env("PCSIM_PORTABLE", "1");
    } else {
        c.env_remove("PCSIM_PORTABLE");
    }
    let r = c.output().unwrap();
    assert!(
        r.status.success(),
        "pcsim {args:?}: {}",
        String::from_utf8_lossy(&r.stderr)
    );
    r
}

#[test]
fn preset_runs_are_byte_identical_on_both_kernel_paths() {
    let golden: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(root().join("data/golden/preset_bytes.json")).unwrap(),
    )
    .unwrap();
    let runs = golden.as_array().unwrap();
    assert_eq!(runs.len(), 8);
    let dir = std::env::temp_dir().join(format!("pcsim-byte-golden-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mut checked = 0;
    for (i, g) in runs.iter().enumerate() {
        let preset = g["preset"].as_str().unwrap();
        for path in ["portable", "avx2"] {
            let out = dir.join(format!("run{i}-{path}"));
            let mut args = vec!["run", "--preset", preset, "--quiet", "--out"];
            let o = out.display().to_string();
            args.push(&o);
            let speed = g["speed_kmh"].to_string();
            if !g["speed_kmh"].is_null() {
                args.extend(["--speed", &speed]);
            }
            pcsim(&args, &dir, path == "portable");
            let text = std::fs::read_to_string(out.join("summary.json")).unwrap();
            let s: serde_json::Value = serde_json::from_str(&text).unwrap();
            let want = &g[path];
            if s["kernels"] != want["kernels"] {
                // This machine has no AVX2 with FMA: only the portable path can be checked.
                assert_eq!(path, "avx2", "{preset}: kernels {}", s["kernels"]);
                continue;
            }
            let ts = std::fs::read(out.join("timeseries.csv")).unwrap();
            assert_eq!(
                fnv1a64(&ts),
                want["timeseries_fnv1a64"].as_str().unwrap(),
                "{preset} ({path}): timeseries.csv changed"
            );
            assert_eq!(
                fnv1a64(&summary_without_wall(&text)),
                want["summary_fnv1a64"].as_str().unwrap(),
                "{preset} ({path}): summary.json changed"
            );
            if let Some(w) = g.get("warnings") {
                assert_eq!(&s["warnings"], w, "{preset}: warnings");
            }
            checked += 1;
        }
    }
    assert!(checked >= 7, "only {checked} runs checked");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn study_rows_are_byte_identical() {
    let dir = std::env::temp_dir().join(format!("pcsim-study-golden-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let g = root().join("data/golden/studies");
    let read = |p: &Path| std::fs::read_to_string(p).unwrap();
    pcsim(
        &[
            "eva",
            "--preset",
            "syt-7.0-9.8",
            "--speed",
            "150,222",
            "--tension",
            "9.8",
            "--out",
            "eva",
            "--no-plot",
            "--quiet",
        ],
        &dir,
        true,
    );
    assert_eq!(read(&dir.join("eva/eva.csv")), read(&g.join("eva.csv")));
    pcsim(
        &[
            "window",
            "--preset",
            "syt-7.0-9.8",
            "--speed",
            "150",
            "--tension",
            "9.8",
            "--max-window",
            "240",
            "--coarse",
            "40",
            "--resolution",
            "10",
            // The search the golden was made with (the default before issue 39, item 8).
            "--coarse-only",
            "--out",
            "win",
            "--no-plot",
            "--quiet",
        ],
        &dir,
        true,
    );
    assert_eq!(
        read(&dir.join("win/window.csv")),
        read(&g.join("window.csv"))
    );
    assert_eq!(read(&dir.join("win/fit.csv")), read(&g.join("fit.csv")));
    let v = pcsim(&["validate", "--json"], &dir, true);
    assert_eq!(
        String::from_utf8(v.stdout).unwrap(),
        read(&g.join("validate.json"))
    );
    let _ = std::fs::remove_dir_all(&dir);
}
