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

/// The inputs of the study goldens, written into `dir`: a short en50318-2002 (8 spans), the same
/// with 2 mm of irregularity (Monte Carlo), the design test spec on 6 spans.
fn study_inputs(dir: &Path) {
    use pcsim_core::zoo::geometries::{geometries, short_en50318};
    std::fs::write(
        dir.join("case.toml"),
        short_en50318(8, 250.0).to_toml_string(),
    )
    .unwrap();
    let rough = geometries()
        .into_iter()
        .find(|(g, _)| *g == "catenary, irregularity")
        .unwrap()
        .1;
    std::fs::write(dir.join("rough.toml"), rough.to_toml_string()).unwrap();
    std::fs::copy(
        root().join("tests/design/swarm.toml"),
        dir.join("spec.toml"),
    )
    .unwrap();
}

/// Each study's command and the files it writes (issue 52's proof: the outputs of every study,
/// written by the build before the study contract, one driver and typed outputs). `OUT` is the
/// study's output directory; `RUN` the `run` study's, `B55` a run of benchmark-55m.
const STUDIES: &[(&str, &[&str], &[&str])] = &[
    (
        "run",
        &["run", "case.toml", "--dropper-forces", "--out", "OUT"],
        &["summary.json", "timeseries.csv", "droppers.csv"],
    ),
    (
        "b55",
        &["run", "--preset", "benchmark-55m", "--out", "OUT"],
        &["summary.json"],
    ),
    (
        "verify",
        &["run", "case.toml", "--verify", "--out", "OUT"],
        &["summary.json"],
    ),
    (
        "sensitivity",
        &[
            "run",
            "--preset",
            "en50318-2002",
            "--sensitivity",
            "--sensitivity-samples",
            "2",
            "--out",
            "OUT",
        ],
        &["summary.json"],
    ),
    (
        "montecarlo",
        &["run", "rough.toml", "--seeds", "3", "--out", "OUT"],
        &["montecarlo.csv", "montecarlo.json"],
    ),
    (
        "eva",
        &[
            "eva",
            "case.toml",
            "--speed",
            "200,250",
            "--out",
            "OUT",
            "--no-plot",
        ],
        &["eva.csv"],
    ),
    (
        "window",
        &[
            "window",
            "case.toml",
            "--speed",
            "250",
            "--max-window",
            "240",
            "--coarse",
            "60",
            "--resolution",
            "30",
            "--out",
            "OUT",
            "--no-plot",
        ],
        &["window.csv", "fit.csv"],
    ),
    (
        "realtime",
        &[
            "realtime",
            "case.toml",
            "--window",
            "180,240",
            "--out",
            "OUT",
            "--no-plot",
        ],
        &["realtime.csv", "timeseries.csv"],
    ),
    (
        "validate",
        &["validate", "case.toml", "--json"],
        &["stdout"],
    ),
    (
        "design",
        &["design", "spec.toml", "--out", "OUT", "--no-plot"],
        &["design.json", "design.csv", "traces.csv", "best-case.toml"],
    ),
    (
        "frf",
        &[
            "pantograph",
            "frf",
            "case.toml",
            "--points",
            "40",
            "--out",
            "OUT",
        ],
        &["frf.csv"],
    ),
    (
        "fit",
        &["pantograph", "fit", "FITDATA", "FITSTART", "--out", "OUT"],
        &["fit.json", "fitted-pantograph.toml"],
    ),
    (
        "compare",
        &[
            "compare",
            "B55",
            "MEASURED",
            "--search",
            "30m",
            "--out",
            "OUT",
            "--no-plot",
        ],
        &[
            "compare.csv",
            "compare_stats.csv",
            "compare_spectrum.csv",
            "compare_profile.csv",
        ],
    ),
    (
        "assess",
        &["assess", "RUN", "--system", "ac"],
        &["assessment.json", "assessment.csv"],
    ),
    // The reports, last (each writes into the study it reports on): a run with its droppers
    // and assessment, --verify, --sensitivity, a design, a fit (written before the report read
    // them back through their types).
    ("report-run", &["report", "RUN"], &["report.html"]),
    ("report-verify", &["report", "REPORT"], &["report.html"]),
    (
        "report-sensitivity",
        &["report", "REPORT"],
        &["report.html"],
    ),
    ("report-design", &["report", "REPORT"], &["report.html"]),
    ("report-fit", &["report", "REPORT"], &["report.html"]),
];

/// A study's output text with what changes from run to run taken out: the lines with a
/// wall-clock time, the scratch folder's path, the executable's and the clone's (a report shows
/// the command line, whose first word is where the clone was built, and a fit's report names
/// the measured file under the clone's examples/).
fn normalised(text: &str, dir: &Path) -> Vec<u8> {
    text.split_inclusive('\n')
        .filter(|l| !l.contains("\"wall_time_s\"") && !l.contains("wall time"))
        .collect::<String>()
        .replace(env!("CARGO_BIN_EXE_pcsim"), "PCSIM")
        .replace(&dir.display().to_string(), "DIR")
        .replace(&root().display().to_string(), "ROOT")
        .into_bytes()
}

/// Issue 52's proof: every study's outputs (a run with its droppers, `--verify`,
/// `--sensitivity`, Monte Carlo, the EVA and window sweeps, the real-time comparison, validate,
/// design, the pantograph's response and fit, compare, assess) hash to the values the build
/// before the study contract wrote (`data/golden/study_bytes.json`, portable kernels; made by
/// this test with `PCSIM_BLESS=1` on that build and committed before the restructure).
#[test]
fn every_studys_outputs_are_the_bytes_they_were() {
    let dir = std::env::temp_dir().join(format!("pcsim-study-bytes-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    study_inputs(&dir);
    let ex = root().join("examples");
    let subst = |a: &str, out: &Path, name: &str| -> String {
        match a {
            "OUT" => out.display().to_string(),
            "REPORT" => dir
                .join(format!("out-{}", name.trim_start_matches("report-")))
                .display()
                .to_string(),
            "RUN" => dir.join("out-run").display().to_string(),
            "B55" => dir.join("out-b55").display().to_string(),
            "FITDATA" => ex
                .join("pantograph/measured-apparent-mass.csv")
                .display()
                .to_string(),
            "FITSTART" => ex
                .join("pantograph/start-25-percent-off.toml")
                .display()
                .to_string(),
            "MEASURED" => ex.join("compare/measured.csv").display().to_string(),
            a => a.to_string(),
        }
    };
    let mut found = serde_json::Map::new();
    for (name, args, files) in STUDIES {
        let out = dir.join(format!("out-{name}"));
        let argv: Vec<String> = args.iter().map(|a| subst(a, &out, name)).collect();
        let mut c = Command::new(env!("CARGO_BIN_EXE_pcsim"));
        c.args(&argv).current_dir(&dir).env("PCSIM_PORTABLE", "1");
        if !matches!(args[0], "validate" | "assess" | "report") {
            c.arg("--quiet");
        }
        let o = c.output().unwrap();
        assert!(
            o.status.success(),
            "{name}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        let mut hashes = serde_json::Map::new();
        for f in *files {
            let text = if *f == "stdout" {
                String::from_utf8(o.stdout.clone()).unwrap()
            } else {
                // assess and the report write into the study they read.
                let from = if *name == "assess" {
                    dir.join("out-run")
                } else if let Some(study) = name.strip_prefix("report-") {
                    dir.join(format!("out-{study}"))
                } else {
                    out.clone()
                };
                std::fs::read_to_string(from.join(f)).unwrap_or_else(|e| panic!("{name}: {f}: {e}"))
            };
            hashes.insert(f.to_string(), fnv1a64(&normalised(&text, &dir)).into());
        }
        found.insert(name.to_string(), hashes.into());
    }
    let _ = std::fs::remove_dir_all(&dir);
    let path = root().join("data/golden/study_bytes.json");
    let found = serde_json::Value::Object(found);
    if std::env::var_os("PCSIM_BLESS").is_some() {
        std::fs::write(&path, serde_json::to_string_pretty(&found).unwrap() + "\n").unwrap();
    }
    let golden: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    for (name, _, files) in STUDIES {
        for f in *files {
            assert_eq!(
                found[name][f], golden[name][f],
                "{name}'s {f} is not the bytes it was"
            );
        }
    }
}
