//! The core's layers import downward only: `model` ← `solve` ← `input` ← `compile` ← `analysis`
//! (and the bottom helpers `error`, `fingerprint` and `linalg` from anywhere; `session.rs` on top).
//! `model/` and `solve/` import nothing from `input/` (issue 18: the engine never reads the file
//! format; `input/` reuses the model's vocabulary, and `compile/` turns a case into a model). A
//! `use crate::input` inside `solve/`, say, fails here.

use std::path::Path;

const LAYERS: &[&str] = &[
    "model", "solve", "input", "compile", "analysis", "session", "study",
];

fn sources(dir: &Path, out: &mut Vec<std::path::PathBuf>) {
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            sources(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

#[test]
fn imports_point_downward_only() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut checked = 0;
    for (rank, layer) in LAYERS.iter().enumerate() {
        let mut files = Vec::new();
        let file = src.join(format!("{layer}.rs"));
        if file.exists() {
            files.push(file);
        } else {
            sources(&src.join(layer), &mut files);
        }
        assert!(!files.is_empty(), "{layer}/ has no sources");
        for f in files {
            let text = std::fs::read_to_string(&f).unwrap();
            for upper in &LAYERS[rank + 1..] {
                for pat in [format!("crate::{upper}"), format!("super::super::{upper}")] {
                    assert!(
                        !text.contains(&pat),
                        "{} (layer `{layer}`) refers to the layer above it: `{pat}`",
                        f.display()
                    );
                }
            }
            checked += 1;
        }
    }
    assert!(checked > 20, "only {checked} files checked");
}

/// The engine (`model/`, `solve/`) names nothing of the case format: no `input::` path and no
/// case type, by any route.
#[test]
fn the_engine_never_reads_the_file_format() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    sources(&src.join("model"), &mut files);
    sources(&src.join("solve"), &mut files);
    assert!(files.len() > 20);
    for f in files {
        let text = std::fs::read_to_string(&f).unwrap();
        for pat in [
            "input::",
            "Case {",
            "Case,",
            "&Case",
            "CatenaryCase",
            "PantographCase",
        ] {
            assert!(!text.contains(pat), "{} names `{pat}`", f.display());
        }
    }
}

/// The engine's errors speak the model's terms (issue 40, item 4): no case-file path
/// (`run.dt_s`, `pantographs[0].masses_kg`, `catenary.ice`, …) is written in the code of
/// `model/` or `solve/` (comments aside); `compile::in_case_terms` maps the engine's
/// `CaseError::Model` to the case field.
#[test]
fn the_engines_errors_name_no_case_path() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    sources(&src.join("model"), &mut files);
    sources(&src.join("solve"), &mut files);
    let sections = [
        "run.",
        "catenary.",
        "pantographs[",
        "line.",
        "contact.",
        "wind.",
        "irregularity[",
    ];
    for f in files {
        let text = std::fs::read_to_string(&f).unwrap();
        for (i, line) in text.lines().enumerate() {
            let code = line.split("//").next().unwrap_or("");
            // Inside string literals only (a field access such as `model.pantographs[p]` is code).
            for lit in code.split('"').skip(1).step_by(2) {
                for sec in sections {
                    let starts = lit.starts_with(sec)
                        || lit.contains(&format!(" {sec}"))
                        || lit.contains(&format!("`{sec}"));
                    assert!(
                        !starts,
                        "{}:{}: a case path in the engine's text: \"{lit}\"",
                        f.display(),
                        i + 1
                    );
                }
            }
        }
    }
}

/// The Python bindings stay out of the workspace's default members, so that the README's
/// `cargo test --release` and `cargo run --release` need no Python and build nothing twice
/// (they had slipped in once, by an edit of the list).
#[test]
fn python_bindings_stay_out_of_the_default_members() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../Cargo.toml");
    let text = std::fs::read_to_string(root).unwrap();
    let doc: toml::Table = text.parse().unwrap();
    let ws = doc["workspace"].as_table().unwrap();
    let names = |k: &str| -> Vec<String> {
        ws[k]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_str().unwrap().to_string())
            .collect()
    };
    let (members, defaults) = (names("members"), names("default-members"));
    assert!(members.iter().any(|m| m.ends_with("pcsim-py")));
    assert!(
        !defaults.iter().any(|m| m.ends_with("pcsim-py")),
        "{defaults:?}"
    );
    for m in ["pcsim-core", "pcsim-cli", "pcsim-fmu", "pcsim-capi"] {
        assert!(
            defaults.iter().any(|d| d.ends_with(m)),
            "{m} not in {defaults:?}"
        );
    }
}

/// Validation flows one way (issue 18): the case's section types (`lateral.rs`,
/// `irregularity.rs`) import neither `case.rs` nor the validation, and only `validate/mod.rs` holds
/// `Case::validate`; every bound is in `bounds.rs`, in one style.
#[test]
fn validation_has_no_circle_and_one_table_of_bounds() {
    let input = Path::new(env!("CARGO_MANIFEST_DIR")).join("src/input");
    for f in ["lateral.rs", "irregularity.rs"] {
        let text = std::fs::read_to_string(input.join(f)).unwrap();
        for pat in ["super::case", "input::case", "validate"] {
            assert!(!text.contains(pat), "{f} names `{pat}`");
        }
    }
    let mut with_validate = Vec::new();
    let mut files = Vec::new();
    sources(&input, &mut files);
    for f in &files {
        let text = std::fs::read_to_string(f).unwrap();
        if text.contains("pub fn validate(&self)") {
            with_validate.push(
                f.strip_prefix(&input)
                    .unwrap()
                    .to_string_lossy()
                    .into_owned(),
            );
        }
        if !f.ends_with("bounds.rs") {
            assert!(
                !text.contains(": Bound ="),
                "{} defines bounds outside bounds.rs",
                f.display()
            );
        }
    }
    assert_eq!(with_validate, ["validate/mod.rs"]);
}

/// Analysis depends on the compiled model, not on the stepper (issue 18, item 3): the energy view
/// and the observers (the EN 50318 recorder, the energy sampler) take a `CompiledModel`; only
/// the drivers that run a set-up (`simulate`, the EVA run) build an `Integrator`. The compiled
/// model holds no time step.
#[test]
fn analysis_reads_the_compiled_model_not_the_stepper() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let energy = std::fs::read_to_string(src.join("analysis/energy.rs")).unwrap();
    assert!(
        !energy.contains("Integrator"),
        "analysis/energy.rs names the stepper"
    );
    let run = std::fs::read_to_string(src.join("solve/run.rs")).unwrap();
    let observe = &run[run.find("fn observe(").expect("Observer::observe")..];
    let observe = &observe[..observe.find(')').unwrap()];
    assert!(
        observe.contains("&CompiledModel") && !observe.contains("Integrator"),
        "Observer::observe takes the stepper: {observe}"
    );
    for f in ["analysis/record.rs", "analysis/eva.rs"] {
        let text = std::fs::read_to_string(src.join(f)).unwrap();
        for (i, _) in text.match_indices("fn observe(") {
            let sig = &text[i..i + text[i..].find(')').unwrap()];
            assert!(
                !sig.contains("Integrator"),
                "{f}: an observer takes the stepper"
            );
        }
    }
    let compiled = std::fs::read_to_string(src.join("solve/compiled.rs")).unwrap();
    let body = &compiled[compiled.find("pub struct CompiledModel").unwrap()..];
    let body = &body[..body.find("\n}").unwrap()];
    for dt in ["dt:", "dt_s:", "d_inv", "flow:"] {
        assert!(
            !body.contains(dt),
            "CompiledModel holds a Δt operator: `{dt}`"
        );
    }
}

/// Issue 52: no production function over 100 lines, in every crate of the workspace: the
/// threshold is clippy.toml's, and each crate root denies the lint outside its tests (CI runs
/// clippy with `-D warnings`; a crate added without the guard fails here).
#[test]
fn every_crate_denies_functions_over_100_lines() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let clippy = std::fs::read_to_string(root.join("clippy.toml")).unwrap();
    assert!(
        clippy
            .lines()
            .any(|l| l.replace(' ', "") == "too-many-lines-threshold=100"),
        "clippy.toml: {clippy}"
    );
    let mut crates = 0;
    for e in std::fs::read_dir(root.join("crates")).unwrap() {
        let dir = e.unwrap().path();
        let lib = dir.join("src/lib.rs");
        let main = dir.join("src/main.rs");
        let root_file = if lib.exists() { lib } else { main };
        let text = std::fs::read_to_string(&root_file).unwrap();
        assert!(
            text.contains("#![cfg_attr(not(test), deny(clippy::too_many_lines))]"),
            "{} does not deny functions over 100 lines",
            root_file.display()
        );
        crates += 1;
    }
    assert!(crates >= 5, "{crates} crates");
}

/// Issue 52: no circle inside `solve/` between the stepper and its stability proof: the
/// integrator knows only the proof's type, the stability check probes through an integrator,
/// and the constructor that needs both lives in `construct.rs`.
#[test]
fn the_integrator_and_its_stability_check_import_one_way() {
    let solve = Path::new(env!("CARGO_MANIFEST_DIR")).join("src/solve");
    let read = |f: &str| std::fs::read_to_string(solve.join(f)).unwrap();
    // A doc link is no import: the `use` lines and the code's calls are what count.
    let uses = |text: &str, pat: &str| {
        text.lines()
            .any(|l| l.trim_start().starts_with("use ") && l.contains(pat))
    };
    let integrator = read("integrator.rs");
    for pat in ["solve::stability", "solve::construct"] {
        assert!(!uses(&integrator, pat), "integrator.rs imports `{pat}`");
    }
    assert!(!integrator.contains("check_stability("));
    let stability = read("stability.rs");
    assert!(!uses(&stability, "solve::construct"));
    assert!(
        !stability.contains("pub fn new("),
        "Integrator::new is in construct.rs"
    );
    assert!(read("construct.rs").contains("pub fn new("));
}

/// Issue 52, item 5: the pantograph is behind one interface, as a point element is. The
/// stepper and the stability check match no pantograph kind and read no part of one (a chain's
/// masses, its strips, its height table): `solve/pantographs.rs` does, beside
/// `model/pantograph.rs`, so a new kind of pantograph adds no code to either.
#[test]
fn the_stepper_and_the_stability_check_match_no_pantograph_kind() {
    let solve = Path::new(env!("CARGO_MANIFEST_DIR")).join("src/solve");
    let read = |f: &str| std::fs::read_to_string(solve.join(f)).unwrap();
    for file in ["integrator.rs", "stability.rs"] {
        let text = read(file);
        for pat in [
            "PantographKind",
            "Lumped",
            "strips",
            "uplift_by_height",
            "masses_kg",
            "stiffness_n_per_m",
        ] {
            assert!(!text.contains(pat), "{file} reads `{pat}` of a pantograph");
        }
    }
    let own = read("pantographs.rs");
    for f in [
        "chains_at_rest",
        "heads_and_loads",
        "half_kick",
        "within_step",
    ] {
        assert!(own.contains(&format!("pub(crate) fn {f}(")), "{f}");
    }
}

/// Issue 53, item 3: the core is compiled once for `cargo run --release` and `cargo test
/// --release`: its library has no test harness (`[lib] test = false`), so no test lives in
/// `src/` (one there would never run); the unit tests are in `tests/suite/unit/`.
#[test]
fn the_core_keeps_no_tests_in_its_library() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let manifest = std::fs::read_to_string(root.join("Cargo.toml")).unwrap();
    let lib = manifest.split("[lib]").nth(1).expect("a [lib] section");
    let lib = lib.split("\n[").next().unwrap();
    assert!(
        lib.lines().any(|l| l.replace(' ', "") == "test=false"),
        "{lib}"
    );
    let mut files = Vec::new();
    sources(&root.join("src"), &mut files);
    for f in files {
        let text = std::fs::read_to_string(&f).unwrap();
        assert!(
            !text.contains("#[cfg(test)]") && !text.contains("#[test]"),
            "{}: a test in the library would never run; put it in tests/suite/unit",
            f.display()
        );
    }
}
