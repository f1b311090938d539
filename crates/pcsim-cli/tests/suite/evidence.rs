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
