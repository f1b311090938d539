//! The unit tests of `input::criteria` (moved out of the library so that the core compiles once
//! for `cargo run --release` and `cargo test --release`: issue 53, item 3).

#![allow(unused_imports)]

use pcsim_core::error::CaseError;
use pcsim_core::input::criteria::*;
use serde::Deserialize;

#[test]
fn the_embedded_criteria_parse_and_each_limit_names_a_source() {
    let c = parse(CRITERIA_TOML, false).expect("the embedded criteria parse");
    assert!(c.len() >= 8);
    for x in &c {
        assert!(!x.source.is_empty() && !x.clause.is_empty(), "{}", x.id);
        // A limit only where it was quoted; never one from the user's status here.
        assert_eq!(
            x.limit != Limit::None,
            x.status == Status::Quoted,
            "{}",
            x.id
        );
        assert_ne!(x.status, Status::User);
    }
}

#[test]
fn a_users_file_is_refused_naming_the_criterion_and_field() {
    let ok = "[[criterion]]\nid = \"s\"\nquantity = \"std_n\"\nkind = \"max\"\nfactor_of = { quantity = \"mean_force_n\", factor = 0.25 }\nclause = \"c\"\nsource = \"s\"\nstatus = \"user\"\n";
    let c = user_file(ok).unwrap();
    assert_eq!(
        c[0].limit,
        Limit::FactorOf {
            quantity: Quantity::MeanForce,
            factor: 0.25
        }
    );
    for (from, to, field) in [
        ("std_n", "sigma", "criterion[0].quantity"),
        ("\"user\"", "\"quoted\"", "criterion[0].status"),
        ("\"max\"", "\"below\"", "criterion[0].kind"),
        ("source = \"s\"", "source = \" \"", "criterion[0].source"),
        (
            "factor = 0.25",
            "factor = nan",
            "criterion[0].factor_of.factor",
        ),
    ] {
        let e = user_file(&ok.replace(from, to)).unwrap_err().to_string();
        assert!(e.contains(field), "{from} -> {to}: {e}");
    }
    // A limit-free kind with a limit, and a bound kind without one.
    let e = user_file(&ok.replace("\"max\"", "\"report\""))
        .unwrap_err()
        .to_string();
    assert!(e.contains("criterion[0].kind"), "{e}");
    let no_limit = ok.replace(
        "factor_of = { quantity = \"mean_force_n\", factor = 0.25 }\n",
        "",
    );
    let e = user_file(&no_limit).unwrap_err().to_string();
    assert!(e.contains("criterion[0].limit"), "{e}");
    // An unknown key is named.
    let e = user_file(&ok.replace("kind", "kinds"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("kinds"), "{e}");
}

#[test]
fn a_users_criterion_replaces_the_builtin_one_of_the_same_id() {
    let user = user_file("[[criterion]]\nid = \"std-max\"\nquantity = \"std_n\"\nkind = \"max\"\nlimit = 40.0\nclause = \"c\"\nsource = \"my copy\"\nstatus = \"user\"\n").unwrap();
    let all = merged(builtin(), user);
    assert_eq!(all.len(), builtin().len());
    let s = all.iter().find(|c| c.id == "std-max").unwrap();
    assert_eq!((s.limit, s.status), (Limit::Constant(40.0), Status::User));
}
