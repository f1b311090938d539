//! The unit tests of `input::measured` (moved out of the library so that the core compiles once
//! for `cargo run --release` and `cargo test --release`: issue 53, item 3).

#![allow(unused_imports)]

use pcsim_core::error::CaseError;
use pcsim_core::input::bounds::inv;
use pcsim_core::input::measured::*;

fn rows(n: usize, dx: f64) -> String {
    let mut s = String::from("position_m,force_n\n");
    for k in 0..n {
        s += &format!("{},{}\n", 100.0 + dx * k as f64, 120.0 + (k % 7) as f64);
    }
    s
}

#[test]
fn a_good_record_reads_and_bad_ones_name_what_is_wrong() {
    let m = MeasuredForce::from_csv(&rows(100, 0.25), "m.csv").unwrap();
    assert_eq!(m.position_m.len(), 100);
    assert!((m.spacing_m - 0.25).abs() < 1e-12);
    let err = |t: &str| MeasuredForce::from_csv(t, "m.csv").unwrap_err().to_string();
    let e = err(&rows(100, 0.25).replace("position_m", "position_km"));
    assert!(e.contains("position_km") && e.contains("metres"), "{e}");
    let e = err(&rows(100, 0.25).replace("force_n", "force_kn"));
    assert!(e.contains("force_kn") && e.contains("newtons"), "{e}");
    let e = err(&rows(100, 0.25).replacen("position_m,force_n\n", "", 1));
    assert!(e.contains("header"), "{e}");
    let e = err(&rows(10, 0.25));
    assert!(e.contains("10 rows") && e.contains("64"), "{e}");
    let e = err(&rows(100, 0.25).replace("112.5,", "112.6,"));
    assert!(e.contains("uniform spacing") && e.contains("112.6"), "{e}");
    // Issue 39, item 7: the error names the file's lines (the header is line 1), not the
    // rows counted from 1 after it.
    assert!(e.contains("lines 51 and 52"), "{e}");
    // Forces a sum of squares cannot hold are refused by value, never read into NaN
    // statistics.
    let e = err(&rows(100, 0.25).replace("101,124", "101,1e308"));
    assert!(e.contains("line 6") && e.contains("1e308"), "{e}");
    let e = err(&rows(100, 0.25).replace("101,", "101,abc,"));
    assert!(
        e.contains("line") && e.contains("two finite numbers"),
        "{e}"
    );
    let e = err(&rows(100, 0.25).replace("101,", "101,nan\n#"));
    assert!(e.contains("two finite numbers"), "{e}");
    assert!(err("").contains("empty"));
}
