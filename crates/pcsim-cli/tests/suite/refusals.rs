//! Regression tests of issue 10 ("hardening and a new user's first hour"), one per numbered item,
//! each named after what it guards. Every crash, hang or silent wrong answer found by a new user
//! must stay a clear error (exit status 2, the field or flag and its value named) or a warning.

use std::path::{Path, PathBuf};
use std::process::Output;
use std::time::Duration;

use crate::common;
use common::{pcsim, refused, run_within, stderr, stdout};

fn scratch(name: &str) -> PathBuf {
    common::scratch("hardening", name)
}

/// A preset's text with one edit.
fn edited(preset: &str, from: &str, to: &str) -> String {
    let text = pcsim_core::presets::find(preset).unwrap().toml;
    assert!(text.contains(from), "edit `{from}` not found");
    text.replacen(from, to, 1)
}

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

/// A short plain case (6 spans of the simple catenary).
fn short_case(dir: &Path) -> PathBuf {
    let (mut c, _) = pcsim_core::presets::load("en50318-2002").unwrap();
    c.catenary.spans = 6;
    c.run.start_m = 60.0;
    c.run.end_m = 300.0;
    c.run.analysis_m = [120.0, 240.0];
    write(dir, "short.toml", &c.to_toml_string())
}

// Item 1: tiny speeds and time steps.

#[test]
fn issue_10_1_tiny_speed_is_refused_with_the_step_estimate() {
    let o = pcsim()
        .args([
            "run",
            "--preset",
            "en50318-2002",
            "--speed",
            "1e-6",
            "--quiet",
        ])
        .arg("--out")
        .arg(crate::common::own_out())
        .output()
        .unwrap();
    refused(
        &o,
        &["run.speed_kmh", "steps", "--max-steps", "--speed 1e-6"],
    );
}

#[test]
fn issue_10_1_tiny_dt_in_a_case_file_is_refused() {
    let d = scratch("dt");
    let p = write(
        &d,
        "dt.toml",
        &edited(
            "en50318-2002",
            "dt_s = { value = 0.001",
            "dt_s = { value = 1e-12",
        ),
    );
    let o = pcsim()
        .arg("run")
        .arg(&p)
        .arg("--quiet")
        .arg("--out")
        .arg(crate::common::own_out())
        .output()
        .unwrap();
    refused(&o, &["run.dt_s", "steps"]);
}

#[test]
fn issue_10_1_realtime_and_bench_refuse_tiny_speeds_and_steps() {
    for args in [
        vec![
            "realtime",
            "--preset",
            "syt-7.0-9.8",
            "--window",
            "215",
            "--speed",
            "1e-6",
        ],
        vec!["bench", "--speed", "1e-9"],
        vec!["bench", "--dt", "1e-12"],
    ] {
        let o = run_within(
            {
                let mut c = pcsim();
                c.args(&args).arg("--quiet");
                c
            },
            Duration::from_secs(30),
        );
        refused(&o, &["steps"]);
    }
}

#[test]
fn issue_10_1_eva_tiny_step_is_refused_before_allocating() {
    let d = scratch("eva-step");
    let o = run_within(
        {
            let mut c = pcsim();
            c.args([
                "eva",
                "--preset",
                "syt-7.0-9.8",
                "--step",
                "1e-6",
                "--quiet",
                "--out",
            ])
            .arg(&d);
            c
        },
        Duration::from_secs(30),
    );
    refused(&o, &["--step", "GiB"]);
}

#[test]
fn issue_10_1_a_raised_limit_lets_a_long_run_through() {
    // The same check with the limit lowered: a normal run refused, then allowed when raised.
    let d = scratch("limit");
    let case = short_case(&d);
    let o = pcsim()
        .arg("run")
        .arg(&case)
        .args(["--max-steps", "100", "--quiet", "--out"])
        .arg(d.join("o"))
        .output()
        .unwrap();
    refused(&o, &["--max-steps"]);
    let o = pcsim()
        .arg("run")
        .arg(&case)
        .args(["--max-steps", "100000", "--quiet", "--out"])
        .arg(d.join("o"))
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
}

#[test]
fn issue_10_1_plain_progress_lines_when_stderr_is_not_a_terminal() {
    let d = scratch("progress");
    let case = short_case(&d);
    let o = pcsim()
        .env("PCSIM_PROGRESS_EVERY_S", "0")
        .arg("run")
        .arg(&case)
        .args(["--progress", "plain", "--out"])
        .arg(d.join("o"))
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let e = stderr(&o);
    assert!(
        e.lines()
            .filter(|l| l.starts_with("run: ") && l.contains('%'))
            .count()
            >= 2,
        "{e}"
    );
}

// Item 2: a huge model.

#[test]
fn issue_10_2_huge_models_are_refused_before_they_are_built() {
    let d = scratch("huge");
    // The new user's case: 10000 spans with 200 modes.
    let p = write(
        &d,
        "a.toml",
        &edited(
            "en50318-2002",
            "spans = { value = 20,",
            "spans = { value = 10000,",
        )
        .replace("modes_per_m = { value = 1.0,", "modes = { value = 200,"),
    );
    let o = run_within(
        {
            let mut c = pcsim();
            // Its own output directory: another test's run in the crate's `out` holds its lock.
            c.arg("run")
                .arg(&p)
                .arg("--quiet")
                .arg("--out")
                .arg(d.join("o"));
            c
        },
        Duration::from_secs(20),
    );
    refused(&o, &["catenary.spans", "10000"]);
    // A legal but huge model is refused by its memory estimate.
    let p = write(
        &d,
        "b.toml",
        &edited(
            "en50318-2002",
            "spans = { value = 20,",
            "spans = { value = 5000,",
        )
        .replace("modes_per_m = { value = 1.0,", "modes = { value = 10000,"),
    );
    let o = run_within(
        {
            let mut c = pcsim();
            // Its own output directory: another test's run in the crate's `out` holds its lock.
            c.arg("run")
                .arg(&p)
                .arg("--quiet")
                .arg("--out")
                .arg(d.join("o"));
            c
        },
        Duration::from_secs(20),
    );
    refused(&o, &["catenary.spans", "GiB", "--max-memory-gb"]);
}

// Item 3.

#[test]
fn issue_10_3_bench_realtime_with_zero_steps_is_an_error() {
    let o = pcsim()
        .args(["bench", "--realtime", "--steps", "0"])
        .output()
        .unwrap();
    refused(&o, &["--steps"]);
}

// Item 4.

#[test]
fn issue_10_4_plot_of_an_empty_timeseries_is_an_error_not_a_hang() {
    let d = scratch("empty-plot");
    let case = short_case(&d);
    let out = d.join("o");
    let o = pcsim()
        .arg("run")
        .arg(&case)
        .arg("--quiet")
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success());
    let ts = std::fs::read_to_string(out.join("timeseries.csv")).unwrap();
    std::fs::write(out.join("timeseries.csv"), ts.lines().next().unwrap()).unwrap();
    let o = run_within(
        {
            let mut c = pcsim();
            c.arg("plot").arg(&out);
            c
        },
        Duration::from_secs(30),
    );
    refused(&o, &["no rows"]);
}

// Item 5.

#[test]
fn issue_10_5_a_toml_error_always_says_what_is_wrong() {
    let d = scratch("toml");
    let p = write(&d, "t.toml", "[run]\nspeed_kmh =");
    let o = pcsim()
        .arg("run")
        .arg(&p)
        .arg("--out")
        .arg(crate::common::own_out())
        .output()
        .unwrap();
    refused(&o, &["line 2", "missing", "speed_kmh ="]);
    // Item 17: the file is named once.
    assert_eq!(stderr(&o).matches("t.toml").count(), 1, "{}", stderr(&o));
}

// Item 6: merging shards.

fn eva_shard(dir: &Path, case: &Path, extra: &[&str], shard: &str) -> (PathBuf, Output) {
    let out = dir.join(format!(
        "shard-{}-{}-{}",
        case.file_stem().unwrap().to_string_lossy(),
        shard.replace('/', "of"),
        extra.join("_")
    ));
    let o = pcsim()
        .arg("eva")
        .arg(case)
        .args([
            "--speed",
            "150,200",
            "--quiet",
            "--no-plot",
            "--shard",
            shard,
        ])
        .args(extra)
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    (out, o)
}

fn short_syt(dir: &Path, speed: f64) -> PathBuf {
    let (mut c, _) = pcsim_core::presets::load("syt-7.0-9.8").unwrap();
    c.catenary.spans = 6;
    c.run.modes = Some(360);
    c.run.speed_kmh = speed;
    c.run.start_m = 60.0;
    c.run.end_m = 280.0;
    c.run.analysis_m = [120.0, 240.0];
    write(dir, &format!("syt-{speed}.toml"), &c.to_toml_string())
}

#[test]
fn issue_10_6_merge_refuses_shards_of_different_sweeps_and_never_writes_into_them() {
    let d = scratch("merge");
    let case = short_syt(&d, 150.0);
    let other_case = {
        let (mut c, _) = pcsim_core::presets::load("syt-7.0-9.8").unwrap();
        c.catenary.spans = 6;
        c.run.modes = Some(360);
        c.run.start_m = 60.0;
        c.run.end_m = 280.0;
        c.run.analysis_m = [120.0, 240.0];
        c.catenary.messenger.tension_n = 8000.0;
        write(&d, "other.toml", &c.to_toml_string())
    };
    let (s0, o) = eva_shard(&d, &case, &[], "0/2");
    assert!(o.status.success(), "{}", stderr(&o));
    let (s1, o) = eva_shard(&d, &case, &[], "1/2");
    assert!(o.status.success(), "{}", stderr(&o));
    let merge = |dirs: &[&Path], out: &Path| {
        pcsim()
            .args(["eva", "merge", "--no-plot"])
            .args(dirs)
            .arg("--out")
            .arg(out)
            .output()
            .unwrap()
    };
    // Other speeds, another --tol, another case, another shard count.
    let (o_speed, _) = {
        let out = d.join("speeds");
        let o = pcsim()
            .arg("eva")
            .arg(&case)
            .args([
                "--speed",
                "150,210",
                "--quiet",
                "--no-plot",
                "--shard",
                "1/2",
                "--out",
            ])
            .arg(&out)
            .output()
            .unwrap();
        assert!(o.status.success());
        (out, o)
    };
    let (o_tol, o) = eva_shard(&d, &case, &["--tol", "0.02"], "1/2");
    assert!(o.status.success());
    let (o_case, o) = eva_shard(&d, &other_case, &[], "1/2");
    assert!(o.status.success());
    let (o_n, o) = eva_shard(&d, &case, &[], "1/3");
    assert!(o.status.success());
    for (bad, needle) in [
        (&o_speed, "different sweeps"),
        (&o_tol, "different sweeps"),
        (&o_case, "different sweeps"),
        (&o_n, "cannot be merged"),
    ] {
        let out = d.join("merged-bad");
        let o = merge(&[&s0, bad], &out);
        refused(&o, &[needle]);
        assert!(!out.exists(), "a failed merge left {}", out.display());
        let partial = std::fs::read_dir(&d)
            .unwrap()
            .filter_map(|e| e.ok())
            .any(|e| e.file_name().to_string_lossy().contains(".partial-"));
        assert!(!partial, "a failed merge left a partial directory");
    }
    // A missing shard, a shard twice, and --out naming a shard.
    refused(&merge(&[&s0], &d.join("m1")), &["missing"]);
    refused(&merge(&[&s0, &s0], &d.join("m2")), &["twice"]);
    let before = std::fs::read(s0.join("eva.csv")).unwrap();
    refused(&merge(&[&s0, &s1], &s0), &["would write into the shard"]);
    assert_eq!(std::fs::read(s0.join("eva.csv")).unwrap(), before);
    // The good merge works.
    let o = merge(&[&s0, &s1], &d.join("merged"));
    assert!(o.status.success(), "{}", stderr(&o));
}

#[test]
fn issue_10_6_an_empty_shard_does_not_claim_files() {
    let d = scratch("empty-shard");
    let case = short_syt(&d, 150.0);
    let (out, o) = eva_shard(&d, &case, &[], "3/4");
    assert!(o.status.success(), "{}", stderr(&o));
    let s = stdout(&o);
    assert!(s.contains("holds none of the 2 cases"), "{s}");
    assert!(!s.contains("cases/"), "{s}");
    assert!(!out.join("cases").exists());
    assert_eq!(
        std::fs::read_to_string(out.join("eva.csv"))
            .unwrap()
            .lines()
            .count(),
        1
    );
}

// Item 7: `pcsim hil` input.

fn hil_input(dir: &Path, name: &str, rows: &[(f64, f64, f64)]) -> PathBuf {
    let mut s = String::from("time_s,contact_force_n,position_from_start_m\n");
    for (t, f, x) in rows {
        s.push_str(&format!("{t},{f},{x}\n"));
    }
    write(dir, name, &s)
}

#[test]
fn issue_10_7_hil_checks_time_and_position() {
    let d = scratch("hil");
    let good: Vec<(f64, f64, f64)> = (0..50)
        .map(|k| (k as f64 * 1e-3, 85.0, 61.7 * k as f64 * 1e-3))
        .collect();
    let run = |rows: &[(f64, f64, f64)], name: &str| {
        let p = hil_input(&d, name, rows);
        pcsim()
            .args(["hil", "--preset", "syt-7.0-9.8", "--input"])
            .arg(&p)
            .arg("--out")
            .arg(d.join(format!("{name}.out")))
            .output()
            .unwrap()
    };
    assert!(run(&good, "good").status.success());
    let mut gap = good.clone();
    gap[20].0 += 0.004;
    refused(&run(&gap, "gap"), &["line 22", "Δt"]);
    let mut back = good.clone();
    back[30].0 = back[28].0;
    refused(&run(&back, "back"), &["line 32", "Δt"]);
    let mut far = good.clone();
    far[10].2 = 1e7;
    refused(
        &run(&far, "far"),
        &["line 12", "outside the modelled catenary"],
    );
    let mut jump = good.clone();
    jump[10].2 += 5.0;
    refused(&run(&jump, "jump"), &["line 12", "km/h"]);
}

// Item 9.

#[test]
fn issue_10_9_fmu_build_refuses_a_file_that_is_not_the_library() {
    let d = scratch("fmu-lib");
    let o = pcsim()
        .args(["fmu", "build", "--lib", "/etc/passwd", "--out"])
        .arg(&d)
        .output()
        .unwrap();
    refused(&o, &["/etc/passwd", "not an ELF shared library"]);
    // An ELF shared library that is not the FMU: the C library of the system.
    let libc = [
        "/lib/x86_64-linux-gnu/libm.so.6",
        "/usr/lib/x86_64-linux-gnu/libm.so.6",
    ]
    .into_iter()
    .find(|p| Path::new(p).exists());
    if let Some(lib) = libc {
        let o = pcsim()
            .args(["fmu", "build", "--lib", lib, "--out"])
            .arg(&d)
            .output()
            .unwrap();
        refused(&o, &["does not export the FMI 2.0 and 3.0 entry points"]);
    }
    assert!(!d.join("pcsim_fmu.fmu").exists());
}

// Item 11 and 16.

#[test]
fn issue_10_11_validate_says_its_exit_status_and_strict_fails_on_a_failed_row() {
    let o = pcsim().args(["validate", "--quiet"]).output().unwrap();
    assert_eq!(o.status.code(), Some(0));
    assert!(stdout(&o).contains("--strict"), "{}", stdout(&o));
    let o = pcsim()
        .args(["validate", "--quiet", "--strict"])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(1), "rows fail with the public data");
}

#[test]
fn issue_10_16_flags_of_the_other_bench_mode_and_zero_jobs_are_refused() {
    refused(
        &pcsim()
            .args(["bench", "--realtime", "--modes", "10"])
            .output()
            .unwrap(),
        &["--modes", "full model"],
    );
    refused(
        &pcsim().args(["bench", "--window", "215"]).output().unwrap(),
        &["--window", "--realtime"],
    );
    refused(
        &pcsim()
            .args(["bench", "--preset", "syt-7.0-9.8", "--spans", "10"])
            .output()
            .unwrap(),
        &["--spans", "en50318-2002"],
    );
    refused(
        &pcsim()
            .args(["eva", "--preset", "syt-7.0-9.8", "--jobs", "0"])
            .arg("--out")
            .arg(crate::common::own_out())
            .output()
            .unwrap(),
        &["--jobs 0"],
    );
    let readme =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../../README.md")).unwrap();
    for cmd in ["pcsim hil", "pcsim fmu xml", "--strict", "--progress"] {
        assert!(readme.contains(cmd), "the README does not mention `{cmd}`");
    }
}

// Item 12: overrides carry units and errors name them.

#[test]
fn issue_10_12_a_tension_override_carries_its_unit_and_errors_name_it() {
    let d = scratch("tension");
    let case = short_case(&d);
    let o = pcsim()
        .arg("run")
        .arg(&case)
        .args(["--tension", "20000", "--quiet", "--out"])
        .arg(d.join("o"))
        .output()
        .unwrap();
    refused(
        &o,
        &[
            "--tension 20000",
            "kN",
            "20000N",
            "catenary.contact_wire.tension_n",
        ],
    );
    assert!(!stderr(&o).contains("dt_s"), "{}", stderr(&o));
    let o = pcsim()
        .arg("run")
        .arg(&case)
        .args(["--tension", "20000N", "--quiet", "--out"])
        .arg(d.join("o"))
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let js: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.join("o/summary.json")).unwrap()).unwrap();
    assert_eq!(js["contact_wire_tension_n"], 20000.0);
    assert_eq!(js["overrides"][0], "--tension 20000N");
    refused(
        &pcsim()
            .arg("run")
            .arg(&case)
            .args(["--speed", "250kg", "--quiet"])
            .arg("--out")
            .arg(crate::common::own_out())
            .output()
            .unwrap(),
        &["--speed", "unknown unit"],
    );
}

// Item 13.

#[test]
fn issue_10_13_a_value_without_a_source_is_accepted() {
    let d = scratch("nosource");
    let text = edited(
        "en50318-2002",
        r#"tension_n = { value = 20000.0, source = "ref §3.1 (c1)" }"#,
        "tension_n = { value = 20000.0 }",
    )
    .replace("spans = { value = 20,", "spans = { value = 6,")
    .replace("end_m = { value = 960.0", "end_m = { value = 300.0")
    .replace("value = [300.0, 900.0]", "value = [120.0, 240.0]");
    let p = write(&d, "c.toml", &text);
    let o = pcsim()
        .arg("run")
        .arg(&p)
        .arg("--quiet")
        .arg("--out")
        .arg(d.join("o"))
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
}

// Items 14 and 18: every output directory redraws, exactly as drawn.

#[test]
fn issue_10_14_plot_redraws_every_output_directory_exactly() {
    let d = scratch("replot");
    let case = short_syt(&d, 150.0);
    let run = d.join("run");
    assert!(pcsim()
        .arg("run")
        .arg(&case)
        .args(["--plot", "--quiet", "--tension", "9.9"])
        .arg("--out")
        .arg(&run)
        .status()
        .unwrap()
        .success());
    let eva = d.join("eva");
    assert!(pcsim()
        .arg("eva")
        .arg(&case)
        .args(["--speed", "150,200", "--quiet", "--out"])
        .arg(&eva)
        .status()
        .unwrap()
        .success());
    let rt = d.join("rt");
    assert!(pcsim()
        .arg("realtime")
        .arg(&case)
        .args(["--window", "120,240", "--quiet", "--out"])
        .arg(&rt)
        .status()
        .unwrap()
        .success());
    let (s0, _) = eva_shard(&d, &case, &[], "0/2");
    let (s1, _) = eva_shard(&d, &case, &[], "1/2");
    let merged = d.join("merged");
    let o = pcsim()
        .args(["eva", "merge"])
        .arg(&s0)
        .arg(&s1)
        .arg("--out")
        .arg(&merged)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    for (dir, figure, must) in [
        (&run, "contact_force_leading.svg", "with --tension 9.9"),
        (
            &run,
            "contact_force_leading.svg",
            "min–max per pixel column",
        ),
        (&eva, "eva_window_energy.svg", "EVA, step criterion"),
        (&eva, "eva_window_energy.svg", "99 % of the total energy"),
        (&eva, "eva_density_speeds_log.svg", "Energy density"),
        (&merged, "eva_window_energy.svg", "EVA, step criterion"),
        (&rt, "realtime_error_vs_window.svg", "relative error"),
        (&rt, "realtime_force_120m.svg", "full model"),
    ] {
        let p = dir.join(figure);
        let before =
            std::fs::read_to_string(&p).unwrap_or_else(|_| panic!("{} was not drawn", p.display()));
        assert!(before.contains(must), "{}: no `{must}`", p.display());
        std::fs::remove_file(&p).unwrap();
        let o = pcsim().arg("plot").arg(dir).output().unwrap();
        assert!(o.status.success(), "{}", stderr(&o));
        assert_eq!(
            std::fs::read_to_string(&p).unwrap(),
            before,
            "`pcsim plot` drew {} differently",
            p.display()
        );
    }
}

// Item 17: outputs that explain themselves.

#[test]
fn issue_10_17_outputs_explain_themselves() {
    let d = scratch("outputs");
    let case = short_case(&d);
    let out = format!("{}/", d.join("o").display());
    let o = pcsim()
        .arg("run")
        .arg(&case)
        .args(["--quiet", "--out", &out])
        .output()
        .unwrap();
    assert!(o.status.success());
    assert!(!stdout(&o).contains("//"), "{}", stdout(&o));
    let js: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.join("o/summary.json")).unwrap()).unwrap();
    let t = js["simulated_time_s"].as_f64().unwrap();
    assert_eq!(t, (t * 1e6).round() / 1e6, "simulated_time_s = {t}");
    // Presets table: the summaries start in one column.
    let o = pcsim().arg("presets").output().unwrap();
    let cols: Vec<usize> = stdout(&o)
        .lines()
        .map(|l| {
            l.find("  ").unwrap() + l[l.find("  ").unwrap()..].find(|c: char| c != ' ').unwrap()
        })
        .collect();
    assert!(cols.windows(2).all(|w| w[0] == w[1]), "{}", stdout(&o));
    // EVA manifest says how a criterion that was not reached is written.
    let eva = d.join("eva");
    let case = short_syt(&d, 150.0);
    assert!(pcsim()
        .arg("eva")
        .arg(&case)
        .args(["--quiet", "--no-plot", "--out"])
        .arg(&eva)
        .status()
        .unwrap()
        .success());
    let m = std::fs::read_to_string(eva.join("pcsim.json")).unwrap();
    assert!(
        m.contains("empty where its criterion was not reached"),
        "{m}"
    );
}

#[test]
fn issue_10_17_validate_json_rows_carry_a_unit() {
    let o = pcsim()
        .args(["validate", "--json", "--quiet"])
        .output()
        .unwrap();
    let js: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    for c in js["cases"].as_array().unwrap() {
        for r in c["rows"].as_array().unwrap() {
            let q = r["quantity"].as_str().unwrap();
            let want = if q.ends_with("_mm") {
                "mm"
            } else if q.ends_with("_percent") {
                "%"
            } else {
                "N"
            };
            assert_eq!(r["unit"], want, "{q}");
        }
    }
}

#[test]
fn issue_21_6_validate_targets_reads_a_users_ranges_and_says_which_are_missing() {
    // One case of the 2018 simple template, one range typed in (wide), one left empty.
    let d = scratch("targets");
    let text = "[mine]\nsource = \"typed in by hand\"\npreset = \"en50318-2018-like-simple\"\n\n\
                [mine.v275_leading]\nspeed_kmh = 275\nmean = [50.0, 400.0]\nstd = []\n";
    let f = write(&d, "targets.toml", text);
    let o = pcsim()
        .args(["validate", "--quiet", "--targets"])
        .arg(&f)
        .output()
        .unwrap();
    let out = stdout(&o);
    assert_eq!(o.status.code(), Some(0), "{out}{}", stderr(&o));
    assert!(out.contains("1 of 1 rows pass"), "{out}");
    assert!(out.contains("1 ranges are missing"), "{out}");
    assert!(out.contains("no range given"), "{out}");
    // --strict: a missing range is not a pass.
    let o = pcsim()
        .args(["validate", "--quiet", "--strict", "--targets"])
        .arg(&f)
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(1));
    // A malformed range: refused, naming its key.
    let f = write(&d, "bad.toml", &text.replace("std = []", "std = [1.0]"));
    let o = pcsim()
        .args(["validate", "--quiet", "--targets"])
        .arg(&f)
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("mine.v275_leading.std"),
        "{}",
        stderr(&o)
    );
}
