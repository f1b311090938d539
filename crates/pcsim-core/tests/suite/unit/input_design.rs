//! The unit tests of `input::design` (moved out of the library so that the core compiles once
//! for `cargo run --release` and `cargo test --release`: issue 53, item 3).

#![allow(unused_imports)]

use pcsim_core::error::CaseError;
use pcsim_core::input::design::*;
use serde::Deserialize;

const SPEC: &str = r#"
[base]
preset = "en50318-2002"
[[variable]]
path = "pantographs[0].uplift_n"
min = 60.0
max = 160.0
[[speed]]
kmh = 250.0
[[objective]]
statistic = "mean_n"
target = 100.0
[budget]
evaluations = 10
"#;

#[test]
fn a_spec_parses_with_its_defaults() {
    let s = DesignSpec::from_toml_str(SPEC).unwrap();
    assert_eq!(s.objective[0].statistic, Statistic::MeanN);
    assert_eq!(s.objective[0].pantograph, Which::Worst);
    assert_eq!(s.speeds[0].weight, 1.0);
    assert_eq!(s.budget.method, Method::ParticleSwarm);
    assert_eq!(s.variables[0].sensitivity_step(), 5.0);
}

#[test]
fn a_bad_spec_names_the_field_and_the_value() {
    let e = DesignSpec::from_toml_str(&SPEC.replace("\"mean_n\"", "\"mean_force\""))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("objective[0].statistic") && e.contains("mean_force"),
        "{e}"
    );
    let e = DesignSpec::from_toml_str(&SPEC.replace("max = 160.0", "max = 50.0"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("variable[0].max") && e.contains("50"), "{e}");
    let e = DesignSpec::from_toml_str(&SPEC.replace("evaluations = 10", "evaluations = 0"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("budget.evaluations"), "{e}");
    let nm = SPEC.replace(
        "evaluations = 10",
        "evaluations = 1\nmethod = \"nelder-mead\"",
    );
    let e = DesignSpec::from_toml_str(&nm).unwrap_err().to_string();
    assert!(
        e.contains("budget.evaluations") && e.contains("at least the 2"),
        "{e}"
    );
    assert!(DesignSpec::from_toml_str(&nm.replace("evaluations = 1", "evaluations = 2")).is_ok());
    let e = DesignSpec::from_toml_str(&SPEC.replace("[budget]", "[budget]\ncolour = 1"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("budget") && e.contains("colour"), "{e}");
    let e = DesignSpec::from_toml_str(&SPEC.replace("target = 100.0", "pantograph = \"middle\""))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("objective[0].pantograph") && e.contains("middle"),
        "{e}"
    );
}
