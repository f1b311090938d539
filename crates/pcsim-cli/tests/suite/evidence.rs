//! Issue 42: numbers with their evidence through the CLI (`pcsim run --verify`).

use crate::common::{ok, pcsim, refused, scratch, stdout};

fn json(p: &std::path::Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(p).unwrap()).unwrap()
}

/// `pcsim run --verify`: summary.json's `verification` holds every statistic of the run beside
/// its refined and stiff-contact values (the run's own value as in `stats`), the terminal lists
/// exactly the statistics it does not find converged, the report carries the section, `assess`
/// shows the refined verdicts; with `--seeds` it is refused.
#[test]
fn issue_42_1_run_verify_writes_shows_and_assesses_the_verification() {
    let d = scratch("evidence", "verify");
    let o = pcsim()
        .args([
            "run",
            "--preset",
            "en50318-2002",
            "--verify",
            "--report",
            "--out",
        ])
        .arg(d.join("v"))
        .output()
        .unwrap();
    ok(&o);
    let text = stdout(&o);
    let s = json(&d.join("v/summary.json"));
    let v = &s["verification"];
    let stats = &s["pantographs"][0]["stats"];
    let checks = v["pantographs"][0]["statistics"].as_array().unwrap();
    assert_eq!(checks.len(), 9);
    for c in checks {
        let name = c["statistic"].as_str().unwrap();
        assert_eq!(c["value"], stats[name], "{name}");
        let change = c["change_percent"].as_f64().unwrap();
        let tol = c["tolerance_percent"].as_f64().unwrap();
        assert_eq!(
            c["converged"].as_bool().unwrap(),
            change.abs() <= tol,
            "{name}"
        );
    }
    assert_eq!(
        v["refined"]["dt_s"].as_f64().unwrap(),
        0.5 * s["dt_s"].as_f64().unwrap()
    );
    let not = v["not_converged"].as_array().unwrap().len();
    assert_eq!(text.matches("NOT CONVERGED").count(), not, "{text}");
    // Issue 53, item 2: each statistic with its numerical error on the terminal, the change
    // to the refined run (σ: its value and |refined − value| to 0.01 N).
    let sigma = checks.iter().find(|c| c["statistic"] == "std_n").unwrap();
    let (val, refined) = (
        sigma["value"].as_f64().unwrap(),
        sigma["refined"].as_f64().unwrap(),
    );
    let shown = format!("std {val:.2} ± {:.2} N", (refined - val).abs());
    assert!(
        text.contains("numerical (the change refined):") && text.contains(&shown),
        "{shown} in {text}"
    );
    let html = std::fs::read_to_string(d.join("v/report.html")).unwrap();
    assert!(html.contains("Verification: the numbers against a refined run"));
    let a = pcsim()
        .arg("assess")
        .arg(d.join("v"))
        .args(["--system", "ac"])
        .output()
        .unwrap();
    ok(&a);
    assert!(stdout(&a).contains("verdict refined"), "{}", stdout(&a));
    let o = pcsim()
        .args([
            "run",
            "--preset",
            "en50318-2002",
            "--verify",
            "--seeds",
            "2",
            "--out",
        ])
        .arg(d.join("s"))
        .output()
        .unwrap();
    refused(&o, &["--verify", "--seeds"]);
}

/// `pcsim run --sensitivity`: summary.json's `sensitivity` holds the preset's ranged values with
/// their reasons, each statistic's band around the run's own value, the movers of each, the
/// runs with the seed; the terminal and the report show them, the figure is drawn; the same
/// seed gives the same bytes; a case with no range, a flag with --seeds and a sample too large are
/// refused by name.
#[test]
fn issue_42_2_run_sensitivity_writes_and_shows_the_bands() {
    let d = scratch("evidence", "sensitivity");
    let go = |dir: &str, extra: &[&str]| {
        let o = pcsim()
            .args([
                "run",
                "--preset",
                "en50318-2002",
                "--sensitivity",
                "--sensitivity-samples",
                "3",
            ])
            .args(extra)
            .arg("--out")
            .arg(d.join(dir))
            .output()
            .unwrap();
        ok(&o);
        o
    };
    let o = go("s", &["--report", "--jobs", "2"]);
    let text = stdout(&o);
    let s = json(&d.join("s/summary.json"));
    let sens = &s["sensitivity"];
    let params = sens["parameters"].as_array().unwrap();
    assert_eq!(params.len(), 7, "{sens}");
    assert!(params.iter().all(|p| p["range_source"].is_string()));
    assert_eq!(sens["spec"]["samples"], 3);
    assert_eq!(sens["runs"].as_array().unwrap().len(), 2 * 7 + 3);
    let stats = &s["pantographs"][0]["stats"];
    for b in sens["pantographs"][0]["statistics"].as_array().unwrap() {
        let name = b["statistic"].as_str().unwrap();
        assert_eq!(b["value"], stats[name], "{name}");
        let (lo, x, hi) = (
            b["low"].as_f64().unwrap(),
            b["value"].as_f64().unwrap(),
            b["high"].as_f64().unwrap(),
        );
        assert!(lo <= x && x <= hi, "{name}");
        assert_eq!(b["movers"].as_array().unwrap().len(), 7, "{name}");
    }
    assert!(text.contains("sensitivity: 7 ranged values"), "{text}");
    assert!(text.contains("pantographs[0].uplift_n"), "{text}");
    let html = std::fs::read_to_string(d.join("s/report.html")).unwrap();
    assert!(html.contains("Sensitivity: the statistics over the case"));
    assert!(html.contains("why this range"));
    assert!(d.join("s/sensitivity_leading.svg").exists());
    // The same seed, one thread: the same sensitivity.
    go("t", &["--jobs", "1"]);
    assert_eq!(json(&d.join("t/summary.json"))["sensitivity"], *sens);
    // Refusals by name.
    let o = pcsim()
        .args([
            "run",
            "--preset",
            "en50318-2002",
            "--sensitivity",
            "--seeds",
            "2",
            "--out",
        ])
        .arg(d.join("x"))
        .output()
        .unwrap();
    refused(&o, &["--sensitivity with --seeds"]);
    let o = pcsim()
        .args([
            "run",
            "--preset",
            "en50318-2002",
            "--sensitivity",
            "--sensitivity-samples",
            "5000",
            "--out",
        ])
        .arg(d.join("y"))
        .output()
        .unwrap();
    refused(&o, &["--sensitivity-samples", "at most 1000"]);
    let o = pcsim()
        .args(["run", "--preset", "benchmark-55m", "--sensitivity", "--out"])
        .arg(d.join("z"))
        .output()
        .unwrap();
    refused(&o, &["--sensitivity", "no value a range"]);
}

/// Every report opens with its answer (issue 42, item 6): the run's statistics, the EVA, the
/// window length, the real-time window against the full model, the Monte Carlo mean with its
/// 95 % interval, the run beside the measurement, the design's answer; each before the first
/// figure and before the first table of a file or of the set-up.
#[test]
fn issue_42_6_every_report_opens_with_its_answer() {
    let d = scratch("evidence", "answer");
    let run = |args: &[&str]| {
        let o = pcsim().args(args).output().unwrap();
        ok(&o);
    };
    let s = |p: &str| d.join(p).to_string_lossy().into_owned();
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let ex = |p: &str| root.join(p).to_string_lossy().into_owned();
    run(&[
        "run",
        "--preset",
        "benchmark-55m",
        "--report",
        "--quiet",
        "--out",
        &s("run"),
    ]);
    run(&[
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
        &s("eva"),
    ]);
    run(&[
        "window",
        "--preset",
        "syt-7.0-9.8",
        "--speed",
        "150",
        "--tension",
        "9.8",
        "--coarse-only",
        "--report",
        "--quiet",
        "--out",
        &s("window"),
    ]);
    run(&[
        "realtime",
        "--preset",
        "syt-7.0-9.8",
        "--window",
        "240",
        "--quiet",
        "--out",
        &s("realtime"),
    ]);
    run(&["report", &s("realtime")]);
    run(&[
        "run",
        &ex("examples/cases/syt-irregular.toml"),
        "--seeds",
        "2",
        "--quiet",
        "--out",
        &s("mc"),
    ]);
    run(&["report", &s("mc")]);
    run(&[
        "compare",
        &s("run"),
        &ex("examples/compare/measured.csv"),
        "--search",
        "30m",
        "--quiet",
        "--out",
        &s("cmp"),
    ]);
    run(&["report", &s("cmp")]);
    for (dir, says) in [
        ("run", "EN 50318 statistics"),
        ("eva", "effective vibration area of each case"),
        ("window", "the shortest window"),
        ("realtime", "against the full model"),
        ("mc", "95 % interval"),
        ("cmp", "beside the measurement"),
    ] {
        let html = std::fs::read_to_string(d.join(dir).join("report.html")).unwrap();
        let answer = html
            .find("id=\"answer\"")
            .unwrap_or_else(|| panic!("{dir}: no answer"));
        assert!(
            html[answer..answer + 200].contains(says),
            "{dir}: {}",
            &html[answer..answer + 200]
        );
        let first = ["<svg", "<h2>The run</h2>", ".csv</h2>"]
            .iter()
            .filter_map(|m| html.find(m))
            .min()
            .unwrap_or(html.len());
        assert!(answer < first, "{dir}: something before the answer");
    }
    // The Monte Carlo answer holds the mean and its interval as montecarlo.json has them.
    let mc: serde_json::Value = json(&d.join("mc/montecarlo.json"));
    let html = std::fs::read_to_string(d.join("mc/report.html")).unwrap();
    let m = mc["statistics"]["leading"]["std_n"]["mean"]
        .as_f64()
        .unwrap();
    assert!(html.contains(&format!("{m:.3}")), "the mean σ {m:.3}");
    // Its table of every statistic with its interval (not only the answer.json every study has).
    assert!(
        html.contains("95 % interval of the mean"),
        "no table of intervals"
    );
}

/// `pcsim validate --verify`: every row carries its refined and stiff-contact value and
/// verdict, the terminal lists exactly the rows not established, and the JSON says the same.
#[test]
fn issue_42_1_validate_verify_shows_which_verdicts_stand() {
    let o = pcsim()
        .args(["validate", "--verify", "--quiet"])
        .output()
        .unwrap();
    ok(&o);
    let text = stdout(&o);
    let j = pcsim()
        .args(["validate", "--verify", "--json", "--quiet"])
        .output()
        .unwrap();
    ok(&j);
    let v: serde_json::Value = serde_json::from_slice(&j.stdout).unwrap();
    let not = v["not_established"].as_array().unwrap();
    assert_eq!(text.matches("NOT ESTABLISHED").count(), not.len(), "{text}");
    let mut unestablished = 0;
    for c in v["cases"].as_array().unwrap() {
        for r in c["rows"].as_array().unwrap() {
            let x = &r["verification"];
            assert!(
                x["refined"].is_number() && x["stiff_contact"].is_number(),
                "{r}"
            );
            unestablished += usize::from(x["established"] == false);
        }
    }
    assert_eq!(unestablished, not.len());
    assert_eq!(v["verification"].as_array().unwrap().len(), 2);
}

/// `pcsim pantograph frf` and `pcsim pantograph fit` (issue 43, item 3): the response written
/// with its units and read back as a lab's file; the fit from a start 25 % off returns the
/// preset's chain and writes it as a case block that loads, the measurement named as its
/// source; malformed files, a moving force and an unknown pantograph refused by name.
#[test]
fn issue_43_3_pantograph_frf_and_fit_through_the_cli() {
    let d = scratch("evidence", "frf");
    let s = |p: &str| d.join(p).to_string_lossy().into_owned();
    let o = pcsim()
        .args([
            "pantograph",
            "frf",
            "--preset",
            "en50318-2002",
            "--quantity",
            "receptance",
            "--out",
            &s("frf"),
        ])
        .output()
        .unwrap();
    ok(&o);
    assert!(stdout(&o).contains("receptance peaks at"), "{}", stdout(&o));
    let csv = std::fs::read_to_string(d.join("frf/frf.csv")).unwrap();
    assert!(csv.starts_with("frequency_hz,magnitude_m_per_n,phase_deg\n"));
    assert_eq!(csv.lines().count(), 201);
    assert!(d.join("frf/frf_magnitude.svg").exists() && d.join("frf/frf_phase.svg").exists());
    // Through the study contract (issue 52): frf.json read back beside frf.csv, the figures
    // declared as data and redrawn by `pcsim plot`, the report opening with the answer.
    let frf = json(&d.join("frf/frf.json"));
    assert_eq!(frf["frequency_hz"].as_array().unwrap().len(), 200);
    let peaks = frf["receptance_peaks_hz"].as_array().unwrap();
    assert!(!peaks.is_empty(), "{frf}");
    let o = pcsim().args(["plot", &s("frf")]).output().unwrap();
    ok(&o);
    assert!(stdout(&o).contains("frf_phase.svg"), "{}", stdout(&o));
    ok(&pcsim().args(["report", &s("frf")]).output().unwrap());
    let html = std::fs::read_to_string(d.join("frf/report.html")).unwrap();
    let answer = html.find("id=\"answer\"").expect("an answer");
    assert!(answer < html.find("<svg").unwrap() && html[answer..].contains("receptance peaks at"));
    // A start 25 % off the preset's chain.
    let shown = pcsim()
        .args(["presets", "show", "en50318-2002"])
        .output()
        .unwrap();
    let text = String::from_utf8(shown.stdout)
        .unwrap()
        .replace(
            "masses_kg = { value = [7.2, 15.0]",
            "masses_kg = { value = [9.0, 11.25]",
        )
        .replace(
            "stiffness_n_per_m = { value = [4200.0, 50.0]",
            "stiffness_n_per_m = { value = [5250.0, 37.5]",
        );
    std::fs::write(d.join("start.toml"), text).unwrap();
    let o = pcsim()
        .args([
            "pantograph",
            "fit",
            &s("frf/frf.csv"),
            &s("start.toml"),
            "--out",
            &s("fit"),
        ])
        .output()
        .unwrap();
    ok(&o);
    let fit = json(&d.join("fit/fit.json"));
    let truth = [7.2, 15.0, 4200.0, 50.0, 10.0, 90.0];
    for (p, t) in fit["parameters"].as_array().unwrap().iter().zip(truth) {
        let v = p["value"].as_f64().unwrap();
        // The file's 10 significant digits and 4 decimals of phase bound the agreement.
        assert!((v - t).abs() <= 2e-3 * t, "{p}");
    }
    let block = std::fs::read_to_string(d.join("fit/fitted-pantograph.toml")).unwrap();
    assert!(block.contains("source = \"fitted by pcsim pantograph fit to frf.csv"));
    // The block in a case runs.
    let case = std::fs::read_to_string(d.join("start.toml")).unwrap();
    let cut = case.find("[[pantographs]]").unwrap();
    let end = case[cut..].find("\n[contact]").map(|i| cut + i).unwrap();
    std::fs::write(
        d.join("fitted.toml"),
        format!("{}{}{}", &case[..cut], block, &case[end..]),
    )
    .unwrap();
    let o = pcsim()
        .args(["validate", &s("fitted.toml"), "--json", "--quiet"])
        .output()
        .unwrap();
    ok(&o);
    // The report opens with the fit's answer.
    let o = pcsim().args(["report", &s("fit")]).output().unwrap();
    ok(&o);
    let html = std::fs::read_to_string(d.join("fit/report.html")).unwrap();
    let answer = html.find("id=\"answer\"").expect("an answer");
    assert!(answer < html.find("<svg").unwrap() && html[answer..].contains("masses_kg[0]"));
    // Refusals by name.
    std::fs::write(
        d.join("bad.csv"),
        "frequency_hz,magnitude_m_per_n,phase_deg\n1,1e-3,0\n0.5,1e-3,0\n2,1,0\n3,1,0\n",
    )
    .unwrap();
    let o = pcsim()
        .args([
            "pantograph",
            "fit",
            &s("bad.csv"),
            "--preset",
            "en50318-2002",
            "--out",
            &s("x"),
        ])
        .output()
        .unwrap();
    refused(&o, &["bad.csv: line 3", "increase"]);
    let o = pcsim()
        .args([
            "pantograph",
            "frf",
            "--preset",
            "en50318-2002",
            "--pantograph",
            "rear",
            "--out",
            &s("y"),
        ])
        .output()
        .unwrap();
    refused(&o, &["pantograph", "rear"]);
    let o = pcsim()
        .args([
            "pantograph",
            "frf",
            "--preset",
            "en50318-2002",
            "--from-hz",
            "0",
            "--out",
            &s("z"),
        ])
        .output()
        .unwrap();
    refused(&o, &["--from-hz"]);
}

/// Issue 43, item 1 through the CLI: a two-strip pantograph's run has each strip's statistics in
/// summary.json, its force column in timeseries.csv (the strips summing to the pantograph's
/// force to the file's 4 decimals), its line on the terminal and its trace in the force figure.
#[test]
fn issue_43_1_a_two_strip_run_shows_each_strip() {
    let d = crate::common::scratch("evidence", "strips");
    let o = crate::common::pcsim()
        .args([
            "run",
            "--preset",
            "benchmark-55m-two-strips",
            "--plot",
            "--out",
        ])
        .arg(&d)
        .output()
        .unwrap();
    crate::common::ok(&o);
    let out = crate::common::stdout(&o);
    assert!(
        out.contains("strip 1 (+0.25 m)") && out.contains("strip 2 (-0.25 m)"),
        "{out}"
    );
    let s: serde_json::Value =
        serde_json::from_slice(&std::fs::read(d.join("summary.json")).unwrap()).unwrap();
    let strips = s["pantographs"][0]["strips"].as_array().unwrap();
    assert_eq!(strips.len(), 2);
    let mean = s["pantographs"][0]["stats"]["mean_n"].as_f64().unwrap();
    let sum: f64 = strips
        .iter()
        .map(|x| x["stats"]["mean_n"].as_f64().unwrap())
        .sum();
    assert!((sum - mean).abs() < 1e-6 * mean, "{sum} vs {mean}");
    let mut rdr = csv::Reader::from_path(d.join("timeseries.csv")).unwrap();
    let h: Vec<String> = rdr.headers().unwrap().iter().map(String::from).collect();
    let at = |n: &str| h.iter().position(|x| x == n).unwrap();
    let (f, a, b) = (
        at("leading_force_n"),
        at("leading_strip1_force_n"),
        at("leading_strip2_force_n"),
    );
    for r in rdr.records() {
        let r = r.unwrap();
        let v = |i: usize| r[i].parse::<f64>().unwrap();
        assert!((v(f) - v(a) - v(b)).abs() <= 1.5e-4, "{:?}", r);
    }
    let svg = std::fs::read_to_string(d.join("contact_force_leading.svg")).unwrap();
    assert!(svg.contains("strip 1 raw") && svg.contains("strip 2 raw"));
}

/// The sensitivity's sample size and seed without `--sensitivity` are refused naming the flag
/// they need (they were ignored: a user asking for 3 samples got a plain run and exit 0).
#[test]
fn issue_42_2_sensitivity_options_without_the_flag_are_refused() {
    for args in [["--sensitivity-samples", "3"], ["--sensitivity-seed", "7"]] {
        let o = pcsim()
            .args(["run", "--preset", "en50318-2002", "--quiet"])
            .args(args)
            .output()
            .unwrap();
        refused(&o, &["--sensitivity"]);
    }
}
