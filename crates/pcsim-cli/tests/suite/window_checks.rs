//! The window sweep's tolerances and search are checked once, in the core (`window_sweep`,
//! `Tolerances::check`, `SearchSettings::check_for`): `pcsim window` refuses a tolerance out of
//! (0, 1000) % and a longest window not shorter than the model, naming the flag, before any run.

use crate::common::{ok, pcsim, scratch, stdout};

fn window(extra: &[&str]) -> (Option<i32>, String) {
    let o = pcsim()
        .args([
            "window",
            "--preset",
            "syt-7.0-9.8",
            "--no-plot",
            "--quiet",
            "--out",
        ])
        .arg(std::env::temp_dir().join(format!("pcsim-window-checks-{}", std::process::id())))
        .args(extra)
        .output()
        .unwrap();
    (
        o.status.code(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

#[test]
fn bad_tolerances_and_windows_are_refused_naming_the_flag() {
    for (args, flag, why) in [
        (
            &["--sigma-tol", "0"][..],
            "--sigma-tol",
            "percentage in (0, 1000)",
        ),
        (
            &["--mean-tol", "1000%"][..],
            "--mean-tol",
            "percentage in (0, 1000)",
        ),
        (
            &["--max-window", "5000"][..],
            "--max-window",
            "shorter than the model",
        ),
    ] {
        let (code, err) = window(args);
        assert_eq!(code, Some(2), "{args:?}: {err}");
        assert!(err.contains(flag) && err.contains(why), "{args:?}: {err}");
    }
}

/// A CSV file as rows of `column → text`.
fn csv_rows(path: &std::path::Path) -> Vec<std::collections::HashMap<String, String>> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let head: Vec<String> = lines
        .next()
        .unwrap()
        .split(',')
        .map(str::to_string)
        .collect();
    lines
        .map(|l| {
            head.iter()
                .cloned()
                .zip(l.split(',').map(str::to_string))
                .collect()
        })
        .collect()
}

/// Issue 53, item 5: the window length is monotone in the scan — every window scanned at or
/// above the length found meets every criterion, the one just below it does not — and
/// `pcsim realtime` at that length gives the same errors as the window study (the same SIL
/// run against the same full model).
#[test]
fn the_window_length_is_monotone_in_the_scan_and_realtime_agrees() {
    let root = scratch("window-checks", "monotone");
    let (win, rt) = (root.join("window"), root.join("realtime"));
    let run = |args: &[&str]| {
        let o = pcsim().args(args).output().unwrap();
        ok(&o);
        stdout(&o)
    };
    let out = run(&[
        "window",
        "--preset",
        "syt-7.0-9.8",
        "--speed",
        "150",
        "--tension",
        "9.8",
        "--min-window",
        "151",
        "--max-window",
        "189",
        "--resolution",
        "2",
        "--no-plot",
        "--quiet",
        "--out",
        win.to_str().unwrap(),
    ]);
    let row = &csv_rows(&win.join("window.csv"))[0];
    let length: f64 = row["length_m"].parse().expect("a length within 151–189 m");
    let num =
        |r: &std::collections::HashMap<String, String>, k: &str| -> f64 { r[k].parse().unwrap() };
    // The terminal shows each criterion's error at the length found.
    assert!(out.contains(&format!("at {length} m: mean")), "{out}");
    // Default tolerances: mean 1 %, σ 3 %, max 5 %.
    let passes = |r: &std::collections::HashMap<String, String>| {
        num(r, "mean_err_pct").abs() <= 1.0
            && num(r, "sigma_err_pct").abs() <= 3.0
            && num(r, "max_err_pct").abs() <= 5.0
    };
    let scanned = csv_rows(&win.join("cases").join("case0000_v150_t9.8_errors.csv"));
    let above: Vec<_> = scanned
        .iter()
        .filter(|r| num(r, "window_m") >= length)
        .collect();
    // The full scan: every lattice window from the length found to the longest was run.
    assert_eq!(above.len(), ((189.0 - length) / 2.0) as usize + 1);
    assert!(
        above.iter().all(|r| passes(r)),
        "a window above {length} m fails"
    );
    if length > 151.0 {
        let below = scanned
            .iter()
            .find(|r| (num(r, "window_m") - (length - 2.0)).abs() < 1e-9)
            .expect("the window just below was run");
        assert!(!passes(below), "{} m passes too", length - 2.0);
    }
    run(&[
        "realtime",
        "--preset",
        "syt-7.0-9.8",
        "--speed",
        "150",
        "--window",
        &length.to_string(),
        "--no-plot",
        "--quiet",
        "--out",
        rt.to_str().unwrap(),
    ]);
    let r = &csv_rows(&rt.join("realtime.csv"))[0];
    for (w, t) in [
        ("mean_err_pct", "mean_error_percent"),
        ("sigma_err_pct", "std_error_percent"),
        ("max_err_pct", "max_error_percent"),
    ] {
        assert!(
            (num(row, w) - num(r, t)).abs() <= 1.5e-3,
            "{w}: window {} against realtime {}",
            row[w],
            r[t]
        );
    }
    // 167 m fails σ on this case (3.08 %): the scan must find the length above it.
    assert!(length > 151.0, "{length} m");
    let _ = std::fs::remove_dir_all(&root);
}
