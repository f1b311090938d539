//! Issue 18: `pcsim hil` only translates the core's real-time session. The scripted input of
//! `data/golden/realtime/` gives the statuses and, bit for bit, the outputs of `expected.csv`
//! (made by the core), and exit status 2 (an error) because five of its rows are refused.

use std::process::Command;

#[test]
fn hil_replays_the_script_as_the_core_session_does() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let g = root.join("data/golden/realtime");
    let out = std::env::temp_dir().join(format!("pcsim-hil-golden-{}.csv", std::process::id()));
    let r = Command::new(env!("CARGO_BIN_EXE_pcsim"))
        .args([
            "hil",
            "--preset",
            "syt-7.0-9.8",
            "--window",
            "215",
            "--input",
        ])
        .arg(g.join("script.csv"))
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    assert_eq!(
        r.status.code(),
        Some(2),
        "{}",
        String::from_utf8_lossy(&r.stderr)
    );
    let err = String::from_utf8_lossy(&r.stderr);
    assert!(err.contains("5 of 4000 rows were not stepped"), "{err}");
    assert!(err.contains("outside_model"), "{err}");
    let got = std::fs::read_to_string(&out).unwrap();
    let want = std::fs::read_to_string(g.join("expected.csv")).unwrap();
    let got: Vec<&str> = got.lines().skip(1).collect();
    let want: Vec<&str> = want.lines().skip(1).collect();
    assert_eq!(got.len(), want.len());
    for (a, b) in got.iter().zip(&want) {
        let a: Vec<&str> = a.split(',').collect();
        let b: Vec<&str> = b.split(',').collect();
        // hil: time, height, velocity, force, status; golden: row, status, time, height, velocity.
        assert_eq!(a[4], b[1], "row {}", b[0]);
        if b[1] == "ok" {
            for (x, y) in [(a[1], b[3]), (a[2], b[4])] {
                let (x, y): (f64, f64) = (x.parse().unwrap(), y.parse().unwrap());
                assert_eq!(x.to_bits(), y.to_bits(), "row {}", b[0]);
            }
        }
    }
    let _ = std::fs::remove_file(&out);
}
