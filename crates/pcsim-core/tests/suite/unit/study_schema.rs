//! The unit tests of `study::schema` (moved out of the library so that the core compiles once
//! for `cargo run --release` and `cargo test --release`: issue 53, item 3).

#![allow(unused_imports)]

use pcsim_core::study::schema::*;
use serde_json::{json, Map, Value};

#[test]
fn every_schema_is_an_object_schema_and_unknown_names_are_none() {
    for (name, _) in names() {
        let s = schema(&name).expect(&name);
        if name == "figures" {
            // A list of figures.
            assert_eq!(s["type"], "array", "{name}");
            continue;
        }
        assert_eq!(s["type"], "object", "{name}");
        assert!(s["properties"].as_object().is_some_and(|p| !p.is_empty()));
    }
    assert!(SCHEMAS
        .iter()
        .all(|(n, _)| names().iter().any(|(m, _)| m == n)));
    assert!(schema("nope").is_none() && schema("nope-spec").is_none());
}

#[test]
fn the_case_schema_refuses_unknown_keys_and_allows_sourced_values() {
    let s = case_schema();
    // deny_unknown_fields reaches the schema: the case's top level closes its keys.
    assert_eq!(s["additionalProperties"], false);
    // A property is plain or sourced.
    let run = &s["properties"]["run"]["anyOf"];
    assert!(run.as_array().is_some_and(|a| a.len() == 2), "{run}");
    assert_eq!(run[1]["required"], serde_json::json!(["value"]));
}
