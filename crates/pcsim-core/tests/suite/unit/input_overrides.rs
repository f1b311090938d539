//! The unit tests of `input::overrides` (moved out of the library so that the core compiles once
//! for `cargo run --release` and `cargo test --release`: issue 53, item 3).

#![allow(unused_imports)]

use pcsim_core::error::CaseError;
use pcsim_core::input::case::Case;
use pcsim_core::input::overrides::*;
use pcsim_core::input::presets;

#[test]
fn overrides_set_values_and_name_bad_paths() {
    let (c, _) = presets::load("stitched-2018-like").unwrap();
    let o = with_overrides(
        &c,
        &[
            ("run.speed_kmh".into(), OverrideValue::Integer(300)),
            (
                "catenary.contact_wire.tension_n".into(),
                OverrideValue::Number(21_500.0),
            ),
            (
                "pantographs[1].offset_m".into(),
                OverrideValue::Number(150.0),
            ),
        ],
    )
    .unwrap();
    assert_eq!(o.run.speed_kmh, 300.0);
    assert_eq!(o.catenary.contact_wire.tension_n, 21_500.0);
    assert_eq!(o.pantographs[1].offset_m(), 150.0);
    assert_eq!(
        value_at(&o, "pantographs[1].offset_m").unwrap(),
        toml::Value::Float(150.0)
    );
    let e = value_at(&o, "pantographs[2].offset_m").unwrap_err();
    assert!(e.to_string().contains("index 2"), "{e}");
    let e = with_overrides(&c, &[("run.sped_kmh".into(), 3.0.into())]).unwrap_err();
    assert!(e.to_string().contains("sped_kmh"), "{e}");
    let e = with_overrides(&c, &[("pantographs[7].offset_m".into(), 3.0.into())]).unwrap_err();
    assert!(e.to_string().contains("pantographs[7]"), "{e}");
    let e = with_overrides(
        &c,
        &[("catenary.contact_wire.tension_n".into(), (-1.0).into())],
    )
    .unwrap_err();
    assert!(
        e.to_string().contains("catenary.contact_wire.tension_n"),
        "{e}"
    );
}
