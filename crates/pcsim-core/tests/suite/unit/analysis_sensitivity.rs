//! The unit tests of `analysis::sensitivity` (moved out of the library so that the core compiles once
//! for `cargo run --release` and `cargo test --release`: issue 53, item 3).

#![allow(unused_imports)]

use pcsim_core::analysis::events::{run_errors, AllowedErrors};
use pcsim_core::analysis::record::{simulate, RunOutput};
use pcsim_core::analysis::sensitivity::*;
use pcsim_core::analysis::verify::{statistic, VERDICT_STATISTICS};
use pcsim_core::compile::budget::Budget;
use pcsim_core::compile::Setup;
use pcsim_core::error::CaseError;
use pcsim_core::input::case::{Case, RangedValue};
use pcsim_core::input::overrides::{with_overrides, OverrideValue};
use pcsim_core::model::wind_field::SplitMix64;
use serde::{Deserialize, Serialize};

/// Issue 51, item 3: a run not made makes the study a failure unless the spec accepts it, and
/// a value whose one end ran keeps its place among the movers (ranked by how far that end
/// moved the statistic), never dropped.
#[test]
fn a_run_not_made_fails_the_study_and_keeps_its_value_ranked() {
    let case = pcsim_core::input::presets::load("en50318-2002").unwrap().0;
    let case = pcsim_core::input::overrides::with_overrides(
        &case,
        &[
            (
                "catenary.spans".into(),
                pcsim_core::input::overrides::OverrideValue::Integer(6),
            ),
            ("run.end_m".into(), 300.0.into()),
            (
                "run.analysis_m".into(),
                pcsim_core::input::overrides::OverrideValue::Numbers(vec![120.0, 240.0]),
            ),
        ],
    )
    .unwrap();
    let go = |c: &Case| simulate(&Setup::from_case(c).unwrap(), &mut |_| true).unwrap();
    let out = go(&case);
    let set = |p: &str, x: f64| {
        go(&pcsim_core::input::overrides::with_overrides(&case, &[(p.into(), x.into())]).unwrap())
    };
    let ranged = |path: &str, low: f64, high: f64, value: f64| RangedValue {
        path: path.into(),
        value,
        low,
        high,
        source: None,
        range_source: None,
        integer: false,
    };
    let params = vec![
        ranged("pantographs[0].uplift_n", 100.0, 160.0, 120.0),
        ranged("catenary.steady_arm.mass_kg", 0.5, 1.5, 0.91),
    ];
    let spec = SensitivitySpec {
        samples: 0,
        ..SensitivitySpec::default()
    };
    let runs = study_runs(&params, &spec);
    // The uplift's high end "failed"; its low end moved the mean by about 20 N.
    let outputs = vec![
        Ok(set("pantographs[0].uplift_n", 100.0)),
        Err("the run could not be made".to_string()),
        Ok(set("catenary.steady_arm.mass_kg", 0.5)),
        Ok(set("catenary.steady_arm.mass_kg", 1.5)),
    ];
    let s = assemble(
        &out,
        params.clone(),
        Vec::new(),
        runs.clone(),
        &outputs,
        &spec,
        AllowedErrors::default(),
    );
    assert_eq!(s.failed.len(), 1);
    let e = s.check().unwrap_err().to_string();
    assert!(
        e.contains("1 of 4 runs") && e.contains("pantographs[0].uplift_n high"),
        "{e}"
    );
    let mean = s.band("leading", "mean_n").unwrap();
    let m = &mean.movers[0];
    assert_eq!(m.path, "pantographs[0].uplift_n", "{:?}", mean.movers);
    assert_eq!((m.at_high, m.swing), (None, None));
    assert!(m.moved > 10.0, "{m:?}");
    // Accepted by the spec: the study passes, the run still listed as not made.
    let allow = SensitivitySpec {
        allow_failed_runs: true,
        ..spec
    };
    let s = assemble(
        &out,
        params,
        Vec::new(),
        runs,
        &outputs,
        &allow,
        AllowedErrors::default(),
    );
    assert!(s.check().is_ok() && s.failed.len() == 1);
}
