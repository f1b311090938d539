//! The unit tests of `input::units` (moved out of the library so that the core compiles once
//! for `cargo run --release` and `cargo test --release`: issue 53, item 3).

#![allow(unused_imports)]

use pcsim_core::input::units::*;

#[test]
fn quantities_with_and_without_units() {
    let f = |t: &str| parse_quantity(t, Dimension::Force, 1e3).unwrap().value;
    assert_eq!(f("20kN"), 20_000.0);
    assert_eq!(f("20000N"), 20_000.0);
    assert_eq!(f("20000 n"), 20_000.0);
    assert_eq!(f("9.8"), 9_800.0); // bare: the flag's unit, kN
    assert_eq!(f("1.5e1kN"), 15_000.0);
    let v = |t: &str| parse_quantity(t, Dimension::Speed, 1.0).unwrap().value;
    assert_eq!(v("250"), 250.0);
    assert_eq!(v("250km/h"), 250.0);
    assert!((v("50m/s") - 180.0).abs() < 1e-12);
    assert!(parse_quantity("20kg", Dimension::Force, 1.0)
        .unwrap_err()
        .contains("unknown unit"));
    assert!(parse_quantity("abc", Dimension::Force, 1.0)
        .unwrap_err()
        .contains("not a number"));
    assert!(parse_quantity("nan", Dimension::Force, 1.0).is_err());
    assert_eq!(
        parse_quantity("215", Dimension::Length, 1.0).unwrap().value,
        215.0
    );
    assert_eq!(
        parse_quantity("1ms", Dimension::Time, 1.0).unwrap().value,
        1e-3
    );
}
