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
    refused(&o, &["--sensitivity-samples", "sensitivity.samples"]);
    let o = pcsim()
        .args(["run", "--preset", "benchmark-55m", "--sensitivity", "--out"])
        .arg(d.join("z"))
        .output()
        .unwrap();
    refused(&o, &["--sensitivity", "no value a range"]);
}
