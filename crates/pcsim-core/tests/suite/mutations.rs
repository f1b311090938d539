//! Property test: mutate the embedded presets at random (numbers set to negative, zero, tiny,
//! huge, NaN or infinite values; lines deleted; tables duplicated; text truncated) and check that
//! loading and validating never panic and never accept a NaN or an infinity into a run.
//!
//! CI runs a bounded number of cases; the documented longer run is
//! `PCSIM_MUTATION_CASES=20000 cargo test --release -p pcsim-core --test suite mutations::`.

use pcsim_core::presets::PRESETS;
use pcsim_core::zoo::number_spans as numbers;
use pcsim_core::{Case, Setup};
use proptest::prelude::*;

const REPLACEMENTS: &[&str] = &[
    "-1.0", "0", "0.0", "-0.0", "1e-300", "1e300", "nan", "inf", "-inf", "1e-12", "1e12", "3",
    "-5", "1e9", "\"text\"", "true",
];

#[derive(Debug, Clone)]
enum Op {
    /// Replace the i-th number of the text.
    Number(usize, usize),
    /// Delete the i-th line.
    DeleteLine(usize),
    /// Duplicate the i-th table (its header and body).
    DuplicateTable(usize),
    /// Keep only this fraction of the text.
    Truncate(f64),
}

fn apply(text: &str, op: &Op) -> String {
    match *op {
        Op::Number(i, r) => {
            let n = numbers(text);
            if n.is_empty() {
                return text.to_string();
            }
            let (s, e) = n[i % n.len()];
            format!(
                "{}{}{}",
                &text[..s],
                REPLACEMENTS[r % REPLACEMENTS.len()],
                &text[e..]
            )
        }
        Op::DeleteLine(i) => {
            let lines: Vec<&str> = text.lines().collect();
            let k = i % lines.len().max(1);
            lines
                .iter()
                .enumerate()
                .filter(|(j, _)| *j != k)
                .map(|(_, l)| *l)
                .collect::<Vec<_>>()
                .join("\n")
        }
        Op::DuplicateTable(i) => {
            let lines: Vec<&str> = text.lines().collect();
            let heads: Vec<usize> = (0..lines.len())
                .filter(|&j| lines[j].starts_with('['))
                .collect();
            if heads.is_empty() {
                return text.to_string();
            }
            let h = heads[i % heads.len()];
            let end = heads
                .iter()
                .find(|&&j| j > h)
                .copied()
                .unwrap_or(lines.len());
            let mut out: Vec<&str> = lines[..end].to_vec();
            out.extend_from_slice(&lines[h..end]);
            out.extend_from_slice(&lines[end..]);
            out.join("\n")
        }
        Op::Truncate(f) => {
            let mut k = ((text.len() as f64) * f) as usize;
            while k > 0 && !text.is_char_boundary(k) {
                k -= 1;
            }
            text[..k].to_string()
        }
    }
}

fn op() -> impl Strategy<Value = Op> {
    prop_oneof![
        6 => (any::<usize>(), any::<usize>()).prop_map(|(i, r)| Op::Number(i, r)),
        2 => any::<usize>().prop_map(Op::DeleteLine),
        1 => any::<usize>().prop_map(Op::DuplicateTable),
        1 => (0.0f64..1.0).prop_map(Op::Truncate),
    ]
}

fn all_finite(case: &Case) -> bool {
    fn walk(v: &toml::Value) -> bool {
        match v {
            toml::Value::Float(f) => f.is_finite(),
            toml::Value::Table(t) => t.values().all(walk),
            toml::Value::Array(a) => a.iter().all(walk),
            _ => true,
        }
    }
    walk(&toml::Value::try_from(case).unwrap())
}

fn cases() -> u32 {
    std::env::var("PCSIM_MUTATION_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(160)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(cases()))]

    #[test]
    fn mutated_presets_never_panic_and_never_run_a_nan(
        preset in 0..PRESETS.len(),
        ops in proptest::collection::vec(op(), 1..4),
    ) {
        let mut text = PRESETS[preset].toml.to_string();
        for o in &ops {
            text = apply(&text, o);
        }
        if let Ok((case, _)) = Case::from_toml_str(&text) {
            if let Ok(setup) = Setup::from_case(&case) {
                prop_assert!(all_finite(&case), "a non-finite value was accepted: {ops:?}");
                prop_assert!(setup.plan.duration_s.is_finite() && setup.plan.duration_s > 0.0);
                prop_assert!(setup.options.dt_s.is_finite() && setup.options.dt_s > 0.0);
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(cases()))]

    /// A design search's spec mutated the same way (issue 24): refused with an error or checked
    /// into a design whose every corner of the box gives a case, never a panic.
    #[test]
    fn mutated_design_specs_never_panic(ops in proptest::collection::vec(op(), 1..4)) {
        use pcsim_core::study::design::Design;
        let mut text = include_str!("../../../../tests/design/swarm.toml").to_string();
        for o in &ops {
            text = apply(&text, o);
        }
        let read = |_: &str| -> std::io::Result<String> { Err(std::io::Error::other("no files here")) };
        if let Ok(d) = Design::from_spec_text(&text, &read) {
            for corner in [0.0, 1.0] {
                let u = vec![corner; d.spec.variables.len()];
                let x = d.x_of(&u);
                prop_assert!(x.iter().all(|v| v.is_finite()));
                for s in &d.spec.speeds {
                    // A corner may be refused in combination with a speed; never a panic.
                    let _ = d.case_at(&x, s.kmh);
                }
            }
            prop_assert!(d.base_x().iter().all(|v| v.is_finite()));
        }
    }
}

#[test]
fn the_mutator_does_mutate() {
    let t = PRESETS[0].toml;
    assert_ne!(apply(t, &Op::Number(3, 6)), t);
    assert!(apply(t, &Op::Number(3, 6)).contains("nan"));
    assert!(apply(t, &Op::DeleteLine(5)).lines().count() < t.lines().count());
    assert!(apply(t, &Op::DuplicateTable(2)).lines().count() > t.lines().count());
    assert!(apply(t, &Op::Truncate(0.5)).len() < t.len());
}
