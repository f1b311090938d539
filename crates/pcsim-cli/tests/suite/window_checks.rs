//! The window sweep's tolerances and search are checked once, in the core (`window_sweep`,
//! `Tolerances::check`, `SearchSettings::check_for`): `pcsim window` refuses a tolerance out of
//! (0, 1000) % and a longest window not shorter than the model, naming the flag, before any run.

use std::process::Command;

fn window(extra: &[&str]) -> (Option<i32>, String) {
    let o = Command::new(env!("CARGO_BIN_EXE_pcsim"))
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
