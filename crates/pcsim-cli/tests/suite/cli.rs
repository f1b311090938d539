//! The command line: names, files and exit codes that users and other tools depend on.

use std::path::PathBuf;
use std::process::Command;

fn pcsim() -> Command {
    Command::new(env!("CARGO_BIN_EXE_pcsim"))
}

fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("pcsim-cli-test-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// A short plain-valued case (6 spans) written from the preset.
fn short_case(dir: &std::path::Path) -> PathBuf {
    let (mut c, _) = pcsim_core::presets::load("en50318-2002").unwrap();
    c.catenary.spans = 6;
    c.run.start_m = 60.0;
    c.run.end_m = 300.0;
    c.run.analysis_m = [120.0, 240.0];
    let p = dir.join("short.toml");
    std::fs::write(&p, c.to_toml_string()).unwrap();
    p
}

#[test]
fn presets_lists_and_shows_an_editable_case() {
    let out = pcsim().arg("presets").output().unwrap();
    assert!(out.status.success());
    let s = String::from_utf8(out.stdout).unwrap();
    assert!(s.contains("en50318-2002") && s.contains("benchmark-55m"));
    let out = pcsim()
        .args(["presets", "show", "benchmark-55m"])
        .output()
        .unwrap();
    assert!(out.status.success());
    let text = String::from_utf8(out.stdout).unwrap();
    let (case, _) = pcsim_core::Case::from_toml_str(&text).unwrap();
    assert_eq!(case, pcsim_core::presets::load("benchmark-55m").unwrap().0);
    let out = pcsim().args(["presets", "show", "nope"]).output().unwrap();
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("nope"));
}

#[test]
fn run_writes_summary_and_timeseries() {
    let dir = scratch("run");
    let case = short_case(&dir);
    let outdir = dir.join("out");
    let out = pcsim()
        .arg("run")
        .arg(&case)
        .arg("--out")
        .arg(&outdir)
        .args(["--speed", "200", "--quiet"])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let js: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(outdir.join("summary.json")).unwrap())
            .unwrap();
    assert_eq!(js["speed_kmh"].as_f64().unwrap(), 200.0);
    for k in ["simulated_time_s", "wall_time_s"] {
        assert!(js[k].as_f64().unwrap() > 0.0, "{k}");
    }
    assert_eq!(js["analysis_section_m"][0].as_f64().unwrap(), 120.0);
    let p = &js["pantographs"][0]["stats"];
    for k in [
        "mean_n",
        "std_n",
        "std_0_5hz_n",
        "std_5_20hz_n",
        "stat_max_n",
        "stat_min_n",
        "actual_max_n",
        "actual_min_n",
        "contact_point_range_mm",
        "max_uplift_at_support_mm",
        "loss_of_contact_percent",
    ] {
        assert!(p[k].as_f64().unwrap().is_finite(), "{k}");
    }
    let csv = std::fs::read_to_string(outdir.join("timeseries.csv")).unwrap();
    let mut lines = csv.lines();
    let header = lines.next().unwrap();
    assert_eq!(
        header,
        "time_s,leading_position_m,leading_force_n,leading_force_filtered_n,leading_height_m"
    );
    let rows: Vec<&str> = lines.collect();
    let sim = js["simulated_time_s"].as_f64().unwrap();
    assert_eq!(rows.len(), (sim / 0.001).round() as usize);
    assert!(!csv.to_lowercase().contains("nan"));
}

#[test]
fn missing_file_is_a_clear_error() {
    let out = pcsim()
        .args(["run", "/no/such/case.toml", "--quiet"])
        .arg("--out")
        .arg(crate::common::own_out())
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    let e = String::from_utf8_lossy(&out.stderr);
    assert!(
        e.contains("/no/such/case.toml") && e.contains("cannot read"),
        "{e}"
    );
}

#[test]
fn bad_value_names_field_and_value_with_nonzero_exit() {
    let dir = scratch("bad");
    let case = short_case(&dir);
    let text = std::fs::read_to_string(&case).unwrap().replacen(
        "tension_n = 20000.0",
        "tension_n = -5.0",
        1,
    );
    std::fs::write(&case, text).unwrap();
    let out = pcsim()
        .arg("run")
        .arg(&case)
        .arg("--out")
        .arg(dir.join("o"))
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    let e = String::from_utf8_lossy(&out.stderr);
    assert!(
        e.contains("catenary.contact_wire.tension_n") && e.contains("-5"),
        "{e}"
    );
    assert!(!e.contains("panicked"));
    assert!(
        !dir.join("o").join("summary.json").exists(),
        "no output for a bad case"
    );
}

#[test]
fn validate_json_reports_every_row() {
    let out = pcsim()
        .args(["validate", "--json", "--quiet"])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let js: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert!(js["all_pass"].is_boolean());
    let cases = js["cases"].as_array().unwrap();
    let speeds: Vec<f64> = cases
        .iter()
        .map(|c| c["speed_kmh"].as_f64().unwrap())
        .collect();
    assert_eq!(speeds, vec![250.0, 300.0]);
    for c in cases {
        let rows = c["rows"].as_array().unwrap();
        assert_eq!(rows.len(), 8);
        for r in rows {
            assert!(
                r["quantity"].is_string()
                    && r["value"].as_f64().unwrap().is_finite()
                    && r["pass"].is_boolean()
            );
            assert_eq!(r["range"].as_array().unwrap().len(), 2);
        }
    }
    // Not a terminal: no progress bar, and --quiet anyway.
    assert!(
        out.stderr.is_empty(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn seed_table1_json_names_the_pantograph_and_the_paper_value() {
    let out = pcsim()
        .args(["validate", "seed-table1", "--json", "--quiet"])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let js: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert!(js["all_pass"].is_boolean());
    let cases = js["cases"].as_array().unwrap();
    let keys: Vec<(f64, String)> = cases
        .iter()
        .map(|c| {
            (
                c["speed_kmh"].as_f64().unwrap(),
                c["pantograph"].as_str().unwrap().to_string(),
            )
        })
        .collect();
    assert_eq!(
        keys,
        vec![
            (275.0, "leading".into()),
            (275.0, "trailing".into()),
            (320.0, "leading".into()),
            (320.0, "trailing".into())
        ]
    );
    for c in cases {
        let rows = c["rows"].as_array().unwrap();
        assert_eq!(rows.len(), 9);
        for r in rows {
            assert!(r["value"].as_f64().unwrap().is_finite());
            assert!(
                r["paper_value"].as_f64().is_some()
                    && r["pass"].is_boolean()
                    && r["paper_pass"].is_boolean()
            );
        }
    }
}

#[test]
fn run_plot_and_replot_write_readable_figures() {
    let dir = scratch("plot");
    let case = short_case(&dir);
    let outdir = dir.join("out");
    let out = pcsim()
        .arg("run")
        .arg(&case)
        .arg("--out")
        .arg(&outdir)
        .args(["--plot", "--quiet", "--tension", "18"])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let js: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(outdir.join("summary.json")).unwrap())
            .unwrap();
    assert_eq!(js["contact_wire_tension_n"].as_f64().unwrap(), 18_000.0);
    assert!(
        std::fs::read_to_string(outdir.join("contact_height.svg"))
            .unwrap()
            .contains("design height at the supports"),
        "contact_height: the height's datum"
    );
    for f in ["contact_force_leading", "contact_height"] {
        let svg = std::fs::read_to_string(outdir.join(format!("{f}.svg"))).unwrap();
        assert!(svg.contains("Position along the track [m]"), "{f}: x label");
        assert!(
            svg.contains("[N]") || svg.contains("[mm]"),
            "{f}: y label with unit"
        );
        assert!(
            svg.contains("supports (every 60 m, dashed)"),
            "{f}: span marks in the legend"
        );
        let png = std::fs::read(outdir.join(format!("{f}.png"))).unwrap();
        assert_eq!(&png[1..4], b"PNG");
        assert!(png.len() > 20_000, "{f}.png looks empty");
    }
    assert!(
        std::fs::read_to_string(outdir.join("contact_force_leading.svg"))
            .unwrap()
            .contains("0–20 Hz")
    );
    // Redraw from the files alone.
    for f in ["contact_force_leading.svg", "contact_height.png"] {
        std::fs::remove_file(outdir.join(f)).unwrap();
    }
    let out = pcsim().arg("plot").arg(&outdir).output().unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(
        outdir.join("contact_force_leading.svg").exists()
            && outdir.join("contact_height.png").exists()
    );
    // A directory that is not a complete output is a clear error (issue 19: readers trust a
    // directory only through its complete manifest).
    let out = pcsim().arg("plot").arg(&dir).output().unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("pcsim.json"));
}

/// A short SYT case (8 spans) for EVA sweeps.
fn short_syt(dir: &std::path::Path) -> PathBuf {
    let (mut c, _) = pcsim_core::presets::load("syt-7.0-9.8").unwrap();
    c.catenary.spans = 8;
    c.run.modes = Some(480);
    c.run.start_m = 60.0;
    c.run.end_m = 400.0;
    c.run.analysis_m = [180.0, 300.0];
    let p = dir.join("syt-short.toml");
    std::fs::write(&p, c.to_toml_string()).unwrap();
    p
}

#[test]
fn eva_shards_merge_to_the_unsharded_result() {
    let dir = scratch("eva");
    let case = short_syt(&dir);
    let grid = [
        "--speed",
        "150,200",
        "--tension",
        "9.8,12",
        "--damping",
        "preset,modal:0.01",
        "--quiet",
    ];
    let full = dir.join("full");
    let out = pcsim()
        .arg("eva")
        .arg(&case)
        .args(grid)
        .arg("--out")
        .arg(&full)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let table = String::from_utf8_lossy(&out.stdout);
    assert!(table.contains("EVA step [m]") && table.contains("EVA 99% [m]"));
    let csv = std::fs::read_to_string(full.join("eva.csv")).unwrap();
    assert_eq!(csv.lines().count(), 1 + 8);
    for f in [
        "eva_density_speeds.svg",
        "eva_density_tensions.png",
        "eva_window_energy.svg",
        "eva_length_vs_speed.png",
        "eva_length_vs_tension.svg",
    ] {
        assert!(full.join(f).exists(), "{f}");
    }
    // Issue 53, item 4: the length figures draw the step criterion's band over a span.
    for f in ["eva_length_vs_speed.svg", "eva_length_vs_tension.svg"] {
        let svg = std::fs::read_to_string(full.join(f)).unwrap();
        assert!(
            svg.contains("step criterion over a span (least, largest)"),
            "{f}"
        );
    }
    assert!(full.join("cases/case0000_v150_t9.8_window.csv").exists());
    let mut shards = Vec::new();
    for i in 0..3 {
        let d = dir.join(format!("shard{i}"));
        let out = pcsim()
            .arg("eva")
            .arg(&case)
            .args(grid)
            .arg("--out")
            .arg(&d)
            .arg("--shard")
            .arg(format!("{i}/3"))
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        shards.push(d);
    }
    let merged = dir.join("merged");
    let out = pcsim()
        .args(["eva", "merge"])
        .args(&shards)
        .arg("--out")
        .arg(&merged)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(
        std::fs::read(merged.join("eva.csv")).unwrap(),
        csv.as_bytes(),
        "merged eva.csv differs from the unsharded one"
    );
    // Every per-case file is there too, byte-identical.
    for e in std::fs::read_dir(full.join("cases")).unwrap() {
        let e = e.unwrap();
        assert_eq!(
            std::fs::read(e.path()).unwrap(),
            std::fs::read(merged.join("cases").join(e.file_name())).unwrap()
        );
    }
    // A missing shard is an error, not a silently short table.
    let out = pcsim()
        .args(["eva", "merge"])
        .args(&shards[..2])
        .arg("--out")
        .arg(dir.join("bad"))
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("missing"));
}

#[test]
fn eva_rejects_bad_arguments_by_name() {
    let dir = scratch("eva-bad");
    let case = short_syt(&dir);
    for (args, needle) in [
        (vec!["--shard", "3/3"], "--shard"),
        (vec!["--damping", "viscous:1"], "--damping"),
        (vec!["--speed", "500"], "run.speed_kmh"),
        (vec!["--tension=-3"], "tension_n"),
    ] {
        let out = pcsim()
            .arg("eva")
            .arg(&case)
            .args(&args)
            .arg("--out")
            .arg(dir.join("o"))
            .arg("--quiet")
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        let e = String::from_utf8_lossy(&out.stderr);
        assert!(e.contains(needle), "{args:?}: {e}");
    }
}

#[test]
fn realtime_compares_windows_with_the_full_model() {
    let dir = scratch("realtime");
    let case = short_syt(&dir);
    let out = pcsim()
        .arg("realtime")
        .arg(&case)
        .args(["--window", "60,240", "--quiet"])
        .arg("--out")
        .arg(dir.join("rt"))
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let table = std::fs::read_to_string(dir.join("rt/realtime.csv")).unwrap();
    let lines: Vec<&str> = table.lines().collect();
    assert_eq!(
        lines[0],
        "window_m,modes,moves,mean_n,std_n,mean_error_percent,std_error_percent,full_mean_n,full_std_n,measured_mean_n,measured_std_n,max_error_percent"
    );
    assert_eq!(lines.len(), 3, "one row per window, numbers only");
    assert!(lines[1].starts_with("60,") && lines[2].starts_with("240,"));
    for l in &lines[1..] {
        for cell in l.split(',') {
            assert!(cell.is_empty() || cell.parse::<f64>().is_ok(), "{l}");
        }
    }
    // The 240 m window is close to the full model on this short case; the 60 m one is not.
    let err = |l: &str| -> f64 { l.split(',').nth(6).unwrap().parse::<f64>().unwrap().abs() };
    assert!(err(lines[2]) < 3.0, "{}", lines[2]);
    assert!(err(lines[1]) > 10.0, "{}", lines[1]);
    for f in [
        "realtime_force_60m.svg",
        "realtime_force_240m.png",
        "realtime_error_vs_window.svg",
        "realtime_mean_vs_window.svg",
        "realtime_std_vs_window.png",
        "timeseries.csv",
    ] {
        assert!(dir.join("rt").join(f).exists(), "{f}");
    }
}

#[test]
fn fmu_bundle_holds_the_generated_description_and_the_library() {
    let dir = scratch("fmu");
    let out = pcsim()
        .args(["fmu", "build", "--out"])
        .arg(&dir)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let fmu = std::fs::read(dir.join("pcsim_fmu.fmu")).unwrap();
    assert_eq!(&fmu[..4], b"PK\x03\x04");
    let xml = pcsim_fmu::vars::model_description();
    let text = String::from_utf8_lossy(&fmu);
    assert!(
        text.contains("modelDescription.xml") && text.contains("binaries/linux64/pcsim_fmu.so")
    );
    assert!(
        fmu.windows(xml.len()).any(|w| w == xml.as_bytes()),
        "the stored XML is the generated one"
    );
    let printed = pcsim().args(["fmu", "xml"]).output().unwrap();
    assert_eq!(String::from_utf8_lossy(&printed.stdout), xml);
}

#[test]
fn portable_flag_names_its_kernels_and_agrees_with_the_default() {
    let d = scratch("portable");
    let case = short_case(&d);
    let mut sums = Vec::new();
    for (flags, dir) in [(vec![], "best"), (vec!["--portable"], "portable")] {
        let out = d.join(dir);
        let r = pcsim()
            .args(&flags)
            .arg("run")
            .arg(&case)
            .args(["--quiet", "--out"])
            .arg(&out)
            .output()
            .unwrap();
        assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
        let s: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap())
                .unwrap();
        sums.push(s);
    }
    assert_eq!(sums[1]["kernels"], "portable");
    assert!(sums[0]["kernels"].is_string());
    let (a, b) = (
        &sums[0]["pantographs"][0]["stats"],
        &sums[1]["pantographs"][0]["stats"],
    );
    for (k, v) in a.as_object().unwrap() {
        let (x, y) = (v.as_f64().unwrap(), b[k].as_f64().unwrap());
        assert!((x - y).abs() <= 1e-6 * x.abs().max(1e-9), "{k}: {x} vs {y}");
    }
}

#[test]
fn bench_repeats_and_reports_median_min_max() {
    let r = pcsim()
        .args([
            "bench",
            "--preset",
            "en50318-2002",
            "--spans",
            "16",
            "--modes",
            "200",
            "--repeat",
            "3",
            "--quiet",
        ])
        .output()
        .unwrap();
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let out = String::from_utf8_lossy(&r.stdout);
    assert!(
        out.contains("bench `en50318-2002`") && out.contains("3 run(s)"),
        "{out}"
    );
    assert!(
        out.contains("median (min") && out.contains("kernels"),
        "{out}"
    );
    let r = pcsim().args(["bench", "--repeat", "0"]).output().unwrap();
    assert!(!r.status.success());
    assert!(String::from_utf8_lossy(&r.stderr).contains("--repeat 0"));
    let r = pcsim()
        .args([
            "bench",
            "--realtime",
            "--steps",
            "3000",
            "--repeat",
            "2",
            "--quiet",
        ])
        .output()
        .unwrap();
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let out = String::from_utf8_lossy(&r.stdout);
    for want in [
        "window 215 m",
        "Hil coupling",
        "step, p99.99",
        "noise floor",
        "2 run(s)",
    ] {
        assert!(out.contains(want), "missing `{want}` in {out}");
    }
}

/// A real-time benchmark longer than the catenary drives it again from the start state (the
/// default million steps at the preset's 222 km/h cover 62 km of an 1 800 m catenary): 60 000
/// steps are three passes, every step under the contract, and none refused.
#[test]
fn realtime_bench_longer_than_the_catenary_drives_it_again() {
    let r = pcsim()
        .args([
            "bench",
            "--realtime",
            "--steps",
            "60000",
            "--repeat",
            "1",
            "--quiet",
        ])
        .output()
        .unwrap();
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let out = String::from_utf8_lossy(&r.stdout);
    assert!(out.contains("3 pass(es) over the 1800 m catenary"), "{out}");
    let moves: usize = out
        .split("window moves")
        .next()
        .and_then(|h| h.rsplit('(').next())
        .and_then(|n| n.trim().parse().ok())
        .unwrap_or_else(|| panic!("no move count in {out}"));
    // About 28 moves per 1 800 m pass (the 215 m window moves by one 60 m span): two whole
    // passes and a part.
    assert!(moves > 40, "{moves} moves in {out}");
}

/// A short SYT case with a random irregularity (6 spans would be too short for the window: the
/// preset over its first 900 m).
fn short_irregular(dir: &std::path::Path) -> PathBuf {
    let (mut c, _) = pcsim_core::presets::load("syt-7.0-9.8").unwrap();
    c.run.end_m = 700.0;
    c.run.analysis_m = [420.0, 700.0];
    c.irregularity = vec![pcsim_core::input::case::IrregularityCase::Psd {
        rms_m: 0.004,
        min_wavelength_m: 2.0,
        max_wavelength_m: 60.0,
        exponent: 2.0,
        table: None,
        seed: 5,
    }];
    let p = dir.join("irregular.toml");
    std::fs::write(&p, c.to_toml_string()).unwrap();
    p
}

#[test]
fn monte_carlo_run_gives_the_same_bytes_with_one_or_two_jobs() {
    let d = scratch("mc");
    let case = short_irregular(&d);
    let mut outs = Vec::new();
    for jobs in ["1", "2"] {
        let out = d.join(format!("mc{jobs}"));
        let r = pcsim()
            .arg("run")
            .arg(&case)
            .args(["--seeds", "3", "--jobs", jobs, "--quiet", "--plot", "--out"])
            .arg(&out)
            .output()
            .unwrap();
        assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
        outs.push(std::fs::read(out.join("montecarlo.csv")).unwrap());
        assert!(out.join("montecarlo_std_leading.png").exists());
        let js: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(out.join("montecarlo.json")).unwrap())
                .unwrap();
        let s = &js["statistics"]["leading"]["std_n"];
        assert_eq!(s["n"], 3);
        assert!(s["ci95_low"].as_f64().unwrap() <= s["mean"].as_f64().unwrap());
        assert_eq!(js["irregularity"][0]["seed"], 5);
    }
    assert_eq!(outs[0], outs[1]);
    // A case without a random input has nothing to vary.
    let r = pcsim()
        .args([
            "run",
            "--preset",
            "syt-7.0-9.8",
            "--seeds",
            "3",
            "--quiet",
            "--out",
        ])
        .arg(d.join("none"))
        .output()
        .unwrap();
    assert!(!r.status.success());
    assert!(String::from_utf8_lossy(&r.stderr).contains("no seeded random input"));
}

#[test]
fn run_reads_an_irregularity_file_and_reports_it() {
    let d = scratch("irrfile");
    let case = short_case(&d);
    let f = d.join("profile.csv");
    let mut text = String::from("position_m,deviation_m\n");
    for i in 0..=360 {
        let x = i as f64;
        text += &format!("{x},{}\n", 0.005 * (x / 10.0).sin());
    }
    std::fs::write(&f, text).unwrap();
    let out = d.join("o");
    let r = pcsim()
        .arg("run")
        .arg(&case)
        .arg("--irregularity")
        .arg(&f)
        .args(["--quiet", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(s["irregularity"][0]["kind"], "table");
    let rms = s["irregularity"][0]["rms_achieved_m"].as_f64().unwrap();
    assert!(rms > 0.003 && rms < 0.0036, "{rms}");
    // A bad row names the file and the line.
    std::fs::write(&f, "position_m,deviation_m\n0,0\n1,abc\n").unwrap();
    let r = pcsim()
        .arg("run")
        .arg(&case)
        .arg("--irregularity")
        .arg(&f)
        .args(["--quiet", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(!r.status.success());
    let e = String::from_utf8_lossy(&r.stderr);
    assert!(e.contains("profile.csv") && e.contains("line 3"), "{e}");
}

#[test]
fn window_shards_merge_to_the_unsharded_result() {
    let d = scratch("window");
    let args = [
        "window",
        "--preset",
        "syt-7.0-9.8",
        "--speed",
        "160,222",
        "--max-window",
        "260",
        "--coarse",
        "40",
        "--resolution",
        "5",
        // The merge is what is tested: the quick search keeps the four runs short.
        "--coarse-only",
        "--quiet",
        "--no-plot",
        "--out",
    ];
    let full = d.join("full");
    let r = pcsim().args(args).arg(&full).output().unwrap();
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let csv = std::fs::read_to_string(full.join("window.csv")).unwrap();
    assert_eq!(csv.lines().count(), 3, "{csv}");
    assert!(
        std::fs::read_to_string(full.join("fit.csv"))
            .unwrap()
            .lines()
            .count()
            > 10
    );
    for i in 0..2 {
        let r = pcsim()
            .args(args)
            .arg(d.join(format!("s{i}")))
            .args(["--shard", &format!("{i}/2")])
            .output()
            .unwrap();
        assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    }
    let merged = d.join("merged");
    let r = pcsim()
        .args(["window", "merge"])
        .arg(d.join("s0"))
        .arg(d.join("s1"))
        .args(["--no-plot", "--out"])
        .arg(&merged)
        .output()
        .unwrap();
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    for f in ["window.csv", "fit.csv"] {
        assert_eq!(
            std::fs::read(full.join(f)).unwrap(),
            std::fs::read(merged.join(f)).unwrap(),
            "{f} of the merge differs"
        );
    }
    // Tolerances are flags with their unit.
    let r = pcsim()
        .args(["window", "--preset", "syt-7.0-9.8", "--sigma-tol=0%"])
        .arg("--out")
        .arg(crate::common::own_out())
        .output()
        .unwrap();
    assert!(!r.status.success());
    assert!(String::from_utf8_lossy(&r.stderr).contains("--sigma-tol"));
}

/// `pcsim run --dropper-forces` (issue 22, item 5) over a line with two overlaps and a (guessed)
/// S–N curve: `droppers.csv` has every dropper with its damage, `dropper_forces.csv` every
/// dropper's tension from its preload on, the figure is drawn, the worst droppers are printed;
/// a bad S–N value is refused naming its field and value.
#[test]
fn dropper_forces_and_damage_over_a_line() {
    let d = scratch("droppers");
    let case = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples/cases/dropper-fatigue/en50318-2018-like-simple-sn-guess.toml");
    let out_dir = d.join("out");
    let out = pcsim()
        .arg("run")
        .arg(&case)
        .args(["--dropper-forces", "--plot", "--quiet", "--out"])
        .arg(&out_dir)
        .output()
        .unwrap();
    let so = String::from_utf8_lossy(&out.stdout);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{so}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(so.contains("by Miner's damage"), "{so}");
    let rows: Vec<Vec<String>> = std::fs::read_to_string(out_dir.join("droppers.csv"))
        .unwrap()
        .lines()
        .map(|l| l.split(',').map(str::to_owned).collect())
        .collect();
    assert_eq!(
        rows[0],
        "dropper,x_m,wire,preload_n,min_n,max_n,slack_steps,cycles,max_range_n,damage"
            .split(',')
            .collect::<Vec<_>>()
    );
    let forces = std::fs::read_to_string(out_dir.join("dropper_forces.csv")).unwrap();
    let mut lines = forces.lines();
    let head: Vec<&str> = lines.next().unwrap().split(',').collect();
    let first: Vec<f64> = lines
        .next()
        .unwrap()
        .split(',')
        .map(|v| v.parse().unwrap())
        .collect();
    assert_eq!(head.len(), rows.len(), "time column + one per dropper");
    let wires: std::collections::BTreeSet<&str> = rows[1..].iter().map(|r| r[2].as_str()).collect();
    assert_eq!(wires.len(), 3, "three tension lengths: {wires:?}");
    for (i, r) in rows[1..].iter().enumerate() {
        let f0: f64 = r[3].parse().unwrap();
        let damage: f64 = r[9].parse().unwrap();
        assert!(damage.is_finite() && damage >= 0.0, "{r:?}");
        assert!(
            (first[i + 1] - f0).abs() < 0.05 * f0,
            "dropper {i}: {} vs {f0}",
            first[i + 1]
        );
    }
    assert!(out_dir.join("droppers.png").is_file() && out_dir.join("droppers.svg").is_file());
    // A bad S–N value names its field.
    let text = std::fs::read_to_string(&case)
        .unwrap()
        .replace("sn_slope = { value = 5.0", "sn_slope = { value = -5.0");
    let bad = d.join("bad.toml");
    std::fs::write(&bad, text).unwrap();
    let out = pcsim()
        .arg("run")
        .arg(&bad)
        .args(["--dropper-forces", "--quiet", "--out"])
        .arg(d.join("bad"))
        .output()
        .unwrap();
    let e = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{e}");
    assert!(
        e.contains("dropper_fatigue.sn_slope") && e.contains("-5"),
        "{e}"
    );
}

/// `pcsim compare RUN MEASURED.csv` (issue 22, item 4): a measurement made from the run (shifted
/// by 4 m, scaled by 1.1, at 0.25 m) is aligned within one sample, the outputs and figures are
/// written; a file in kilometres or with an uneven spacing is refused, naming what is wrong.
#[test]
fn compare_aligns_a_measurement_and_refuses_bad_files() {
    let d = scratch("compare");
    let case = short_case(&d);
    let run_dir = d.join("run");
    let o = pcsim()
        .arg("run")
        .arg(&case)
        .args(["--quiet", "--out"])
        .arg(&run_dir)
        .output()
        .unwrap();
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let ts = std::fs::read_to_string(run_dir.join("timeseries.csv")).unwrap();
    let mut lines = ts.lines();
    let head: Vec<&str> = lines.next().unwrap().split(',').collect();
    let (ix, iff) = (
        head.iter()
            .position(|c| c.ends_with("_position_m"))
            .unwrap(),
        head.iter().position(|c| c.ends_with("_force_n")).unwrap(),
    );
    let (mut x, mut f) = (Vec::new(), Vec::new());
    for l in lines {
        let v: Vec<f64> = l.split(',').map(|s| s.parse().unwrap()).collect();
        x.push(v[ix]);
        f.push(v[iff]);
    }
    let (shift, dx) = (4.0, 0.25);
    let mut text = String::from("position_m,force_n\n");
    let mut y = x[0] + 5.0 - shift;
    while y + shift < x[x.len() - 1] - 5.0 {
        let k = x.partition_point(|&xi| xi <= y + shift) - 1;
        let t = (y + shift - x[k]) / (x[k + 1] - x[k]);
        text += &format!("{y},{}\n", 1.1 * (f[k] * (1.0 - t) + f[k + 1] * t));
        y += dx;
    }
    let meas = d.join("measured.csv");
    std::fs::write(&meas, &text).unwrap();
    let out = d.join("cmp");
    let o = pcsim()
        .arg("compare")
        .arg(&run_dir)
        .arg(&meas)
        .args(["--search", "20m", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let stats = std::fs::read_to_string(out.join("compare_stats.csv")).unwrap();
    let found: f64 = stats
        .lines()
        .find(|l| l.starts_with("shift_m"))
        .and_then(|l| l.split(',').nth(2))
        .unwrap()
        .parse()
        .unwrap();
    assert!((found - shift).abs() <= dx, "shift {found} m");
    for f in [
        "compare.csv",
        "compare_spectrum.csv",
        "compare_profile.csv",
        "compare_force.png",
        "compare_spectrum.png",
        "compare_profile.png",
    ] {
        assert!(out.join(f).is_file(), "{f}");
    }
    for (bad, what) in [
        (text.replacen("position_m", "position_km", 1), "position_km"),
        (
            text.replacen(
                &format!("{},", x[0] + 5.0 - shift + dx),
                &format!("{},", x[0] + 5.0 - shift + 1.3 * dx),
                1,
            ),
            "uniform spacing",
        ),
    ] {
        std::fs::write(&meas, bad).unwrap();
        let o = pcsim()
            .arg("compare")
            .arg(&run_dir)
            .arg(&meas)
            .args(["--out"])
            .arg(d.join("cmp2"))
            .output()
            .unwrap();
        let e = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{e}");
        assert!(e.contains(what) && e.contains("measured.csv"), "{e}");
    }
}

/// A report.html that stands alone: every figure of `dir` inline and captioned, every table
/// with rows, and nothing fetched from outside (no `src`, `href`, `url(`, `@import` or script;
/// the only address is the SVG namespace). Returns the page.
fn check_report(dir: &std::path::Path) -> String {
    let html = std::fs::read_to_string(dir.join("report.html")).unwrap();
    let svgs = std::fs::read_dir(dir)
        .unwrap()
        .filter(|e| {
            e.as_ref()
                .unwrap()
                .path()
                .extension()
                .is_some_and(|x| x == "svg")
        })
        .count();
    assert!(svgs >= 2, "{}: {svgs} figures", dir.display());
    assert_eq!(html.matches("<svg").count(), svgs, "every figure inline");
    assert_eq!(
        html.matches("<figcaption>").count(),
        svgs,
        "every figure captioned"
    );
    for body in html.split("<tbody>").skip(1) {
        let body = body.split("</tbody>").next().unwrap();
        assert!(body.contains("<tr>"), "a table without rows");
    }
    for bad in ["src=", "href=", "url(", "@import", "<script"] {
        assert!(!html.contains(bad), "{bad} in the report");
    }
    let addresses: Vec<&str> = html
        .match_indices("http")
        .map(|(i, _)| &html[i..(i + 26).min(html.len())])
        .filter(|a| !a.starts_with("http-equiv=\"Content-Securi"))
        .collect();
    // Scripts are forbidden by the page's own policy too (issue 39, item 5).
    assert!(
        html.contains("<meta http-equiv=\"Content-Security-Policy\" content=\"default-src 'none'; script-src 'none'"),
        "no Content-Security-Policy"
    );
    assert!(
        addresses
            .iter()
            .all(|a| a.starts_with("http://www.w3.org/2000/svg")),
        "{addresses:?}"
    );
    let manifest = std::fs::read_to_string(dir.join("pcsim.json")).unwrap();
    assert!(manifest.contains("report.html"));
    html
}

/// `pcsim run --report` and `pcsim eva --report` (issue 22, item 1): one self-contained page
/// each ([`check_report`]); the run's holds the case's values with their sources, its statistics
/// and the command line; `pcsim report DIR` writes the same page again.
#[test]
fn run_and_eva_reports_are_self_contained_pages() {
    let d = scratch("report");
    let out = d.join("out");
    let o = pcsim()
        .args([
            "run",
            "--preset",
            "en50318-2002",
            "--report",
            "--quiet",
            "--out",
        ])
        .arg(&out)
        .output()
        .unwrap();
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let html = check_report(&out);
    assert!(html.matches("<table>").count() >= 3);
    assert!(
        html.contains("<td>catenary.contact_wire.tension_n</td>")
            && html.contains("<td>mean_n</td>"),
        "provenance and statistics rows"
    );
    assert!(html.contains("--report"), "the command line");
    assert!(std::fs::read_to_string(out.join("pcsim.json"))
        .unwrap()
        .contains("case.toml"));
    std::fs::remove_file(out.join("report.html")).unwrap();
    let o = pcsim().arg("report").arg(&out).output().unwrap();
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    assert_eq!(
        std::fs::read_to_string(out.join("report.html")).unwrap(),
        html
    );
    let eva = d.join("eva");
    let o = pcsim()
        .args([
            "eva",
            "--preset",
            "syt-7.0-9.8",
            "--speed",
            "150",
            "--tension",
            "9.8",
            "--report",
            "--quiet",
            "--out",
        ])
        .arg(&eva)
        .output()
        .unwrap();
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let html = check_report(&eva);
    assert!(html.contains("<h2>eva.csv</h2>"));
    // Issue 53, item 4: the answer gives the EVA's band over a span, eva.csv's own values, and
    // the length figure draws it.
    let csv = std::fs::read_to_string(eva.join("eva.csv")).unwrap();
    let (head, row) = (csv.lines().next().unwrap(), csv.lines().nth(1).unwrap());
    let cell = |name: &str| {
        let i = head.split(',').position(|h| h == name).unwrap();
        row.split(',').nth(i).unwrap().to_string()
    };
    for (col, label) in [
        ("eva_step_span_min_m", "step, least over a span [m]"),
        ("eva_step_span_max_m", "step, largest over a span [m]"),
    ] {
        let v = cell(col);
        assert!(!v.is_empty(), "{col} empty");
        assert!(html.contains(label), "{label}");
        assert!(html.contains(&format!("<td>{v}</td>")), "{col} = {v}");
    }
    // A study's page has its command line and its base case with the sources.
    assert!(
        html.contains("eva --preset syt-7.0-9.8"),
        "the command line"
    );
    assert!(
        html.contains("<td>catenary.contact_wire.tension_n</td>"),
        "the provenance table"
    );
}

#[test]
fn assess_gives_each_criterion_with_its_source_and_refuses_bad_input() {
    let d = scratch("assess");
    let out = d.join("out");
    let o = pcsim()
        .args([
            "run",
            "--preset",
            "stitched-2018-like",
            "--speed",
            "320",
            "--report",
            "--quiet",
            "--out",
        ])
        .arg(&out)
        .output()
        .unwrap();
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    // The run's summary records its speed ratio against the contact wire's wave speed.
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let (ratio, c) = (
        s["speed_ratio"].as_f64().unwrap(),
        s["contact_wire_wave_speed_kmh"].as_f64().unwrap(),
    );
    assert!((ratio * c - 320.0).abs() < 1e-9, "{ratio} × {c}");
    // Without a system the AC target is left out by name; the report (made by --report before
    // any assessment) holds the built-in criteria.
    assert!(std::fs::read_to_string(out.join("report.html"))
        .unwrap()
        .contains("<td>speed-ratio</td>"));
    let o = pcsim().arg("assess").arg(&out).output().unwrap();
    let text = String::from_utf8_lossy(&o.stdout);
    assert_eq!(o.status.code(), Some(0), "{text}");
    assert!(text.contains("not applied: mean-force-target-ac") && text.contains("--system"));
    // With the system: the target at 320 km/h, 169.328 N, and every row with its source.
    let o = pcsim()
        .args(["assess", "--system", "ac"])
        .arg(&out)
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&o.stdout);
    assert_eq!(o.status.code(), Some(0), "{text}");
    let a: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("assessment.json")).unwrap())
            .unwrap();
    assert_eq!(a["system"], "ac");
    let rows = a["rows"].as_array().unwrap();
    let target = rows
        .iter()
        .find(|r| r["id"] == "mean-force-target-ac")
        .unwrap();
    assert!((target["limit"].as_f64().unwrap() - 169.328).abs() < 1e-9);
    assert!(rows
        .iter()
        .all(|r| !r["source"].as_str().unwrap().is_empty()));
    let csv = std::fs::read_to_string(out.join("assessment.csv")).unwrap();
    assert_eq!(csv.lines().count(), rows.len() + 1);
    let manifest = std::fs::read_to_string(out.join("pcsim.json")).unwrap();
    assert!(manifest.contains("assessment.csv") && manifest.contains("assessment.json"));
    // The report made before is made again with the system.
    assert!(text.contains("report.html"), "{text}");
    let html = std::fs::read_to_string(out.join("report.html")).unwrap();
    assert!(html.contains("Supply system: ac") && html.contains("mean-force-target-ac"));
    // A user's criterion that the run does not meet: exit 0, and 1 with --strict.
    let crit = d.join("mine.toml");
    std::fs::write(
        &crit,
        "[[criterion]]\nid = \"tight\"\nquantity = \"std_n\"\nkind = \"max\"\nlimit = 1.0\nclause = \"a test limit\"\nsource = \"test\"\nstatus = \"user\"\n",
    )
    .unwrap();
    for (strict, code) in [(false, 0), (true, 1)] {
        let mut c = pcsim();
        c.args(["assess", "--criteria"]).arg(&crit).arg(&out);
        if strict {
            c.arg("--strict");
        }
        let o = c.output().unwrap();
        assert_eq!(
            o.status.code(),
            Some(code),
            "{}",
            String::from_utf8_lossy(&o.stdout)
        );
        assert!(String::from_utf8_lossy(&o.stdout).contains("NOT MET"));
    }
    // Bad input: named.
    let bad = d.join("bad.toml");
    std::fs::write(
        &bad,
        std::fs::read_to_string(&crit)
            .unwrap()
            .replace("std_n", "sigma"),
    )
    .unwrap();
    for (args, needle) in [
        (vec!["--system", "ac25"], "--system ac25"),
        (
            vec!["--criteria", bad.to_str().unwrap()],
            "criterion[0].quantity",
        ),
    ] {
        let o = pcsim()
            .arg("assess")
            .args(&args)
            .arg(&out)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{err}");
        assert!(err.contains(needle), "{err}");
    }
}

/// `run --threads 2` on a line of ten tension lengths (cut to four spans of travel) writes the
/// same time series and statistics, byte for byte, as one thread; a bad count names the flag.
#[test]
fn run_on_two_threads_writes_the_same_bytes_as_one() {
    let d = scratch("threads");
    let (mut c, _) = pcsim_core::presets::load("line-10km-2002").unwrap();
    c.run.end_m = c.run.start_m + 4.0 * c.catenary.span_m;
    c.run.analysis_m = [c.run.start_m + 61.0, c.run.end_m];
    let case = d.join("line.toml");
    std::fs::write(&case, c.to_toml_string()).unwrap();
    let mut outs = Vec::new();
    for threads in ["1", "2"] {
        let out = d.join(format!("t{threads}"));
        let r = pcsim()
            .arg("run")
            .arg(&case)
            .args(["--threads", threads, "--quiet", "--out"])
            .arg(&out)
            .output()
            .unwrap();
        assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
        let mut js: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap())
                .unwrap();
        js.as_object_mut().unwrap().remove("wall_time_s");
        outs.push((std::fs::read(out.join("timeseries.csv")).unwrap(), js));
    }
    assert!(outs[0].0.len() > 10_000);
    assert_eq!(outs[0], outs[1]);
    for bad in ["0", "17", "two"] {
        let r = pcsim()
            .arg("run")
            .arg(&case)
            .args(["--threads", bad, "--quiet", "--out"])
            .arg(d.join("bad"))
            .output()
            .unwrap();
        assert!(!r.status.success());
        assert!(String::from_utf8_lossy(&r.stderr).contains("--threads"));
    }
}
