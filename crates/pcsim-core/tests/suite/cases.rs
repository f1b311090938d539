//! Case files: presets carry a source on every field, unknown keys are errors, and bad values
//! give an error naming the field and the value.

use pcsim_core::error::CaseError;
use pcsim_core::input::case::{unsourced_fields, Case};
use pcsim_core::presets::{self, PRESETS};
use pcsim_core::Setup;

#[test]
fn every_preset_field_has_a_source_and_the_preset_validates() {
    for p in PRESETS {
        let missing = unsourced_fields(p.toml).unwrap();
        assert!(
            missing.is_empty(),
            "{}: fields without a source: {missing:?}",
            p.name
        );
        let (case, prov) = Case::from_toml_str(p.toml).unwrap();
        assert!(
            prov.len() > 30,
            "{}: only {} sourced fields",
            p.name,
            prov.len()
        );
        assert!(prov.values().all(|s| !s.trim().is_empty()));
        Setup::from_case(&case).unwrap();
    }
}

#[test]
fn plain_values_parse_like_sourced_ones() {
    let (case, _) = presets::load("en50318-2002").unwrap();
    let plain = case.to_toml_string();
    let (again, prov) = Case::from_toml_str(&plain).unwrap();
    assert!(prov.is_empty());
    assert_eq!(case, again);
}

fn err_of(edit: impl Fn(&mut String)) -> String {
    let mut text = presets::find("en50318-2002").unwrap().toml.to_string();
    edit(&mut text);
    match Case::from_toml_str(&text) {
        Err(e) => e.to_string(),
        // Refused by the set-up, or by the coupled stability check when the integrator is built
        // (before any step).
        Ok((case, _)) => match Setup::from_case(&case).and_then(|s| s.integrator()) {
            Err(e) => e.to_string(),
            Ok(_) => panic!("expected an error"),
        },
    }
}

fn replace(from: &'static str, to: &'static str) -> impl Fn(&mut String) {
    move |t: &mut String| {
        assert!(t.contains(from), "test edit `{from}` not found");
        *t = t.replacen(from, to, 1);
    }
}

#[test]
fn unknown_key_is_an_error_naming_it() {
    let e = err_of(replace(
        "[catenary.contact_wire]\n",
        "[catenary.contact_wire]\ncolour = 3\n",
    ));
    assert!(
        e.contains("colour") && e.contains("catenary.contact_wire"),
        "{e}"
    );
}

#[test]
fn negative_tension_names_field_and_value() {
    let e = err_of(replace(
        "tension_n = { value = 20000.0",
        "tension_n = { value = -20000.0",
    ));
    assert!(
        e.contains("catenary.contact_wire.tension_n") && e.contains("-20000"),
        "{e}"
    );
}

#[test]
fn zero_mass_names_field_and_value() {
    let e = err_of(replace(
        "mass_per_m_kg = { value = 1.07",
        "mass_per_m_kg = { value = 0.0",
    ));
    assert!(
        e.contains("catenary.messenger.mass_per_m_kg") && e.contains("= 0"),
        "{e}"
    );
}

#[test]
fn pantograph_mass_must_be_positive() {
    let e = err_of(replace("value = [7.2, 15.0]", "value = [7.2, -15.0]"));
    assert!(
        e.contains("pantographs[0].masses_kg[1]") && e.contains("-15"),
        "{e}"
    );
}

#[test]
fn dropper_outside_its_span() {
    let e = err_of(replace("[5.0, 10.5,", "[5.0, 70.5,"));
    assert!(
        e.contains("catenary.droppers.positions_m[1]")
            && e.contains("70.5")
            && e.contains("outside"),
        "{e}"
    );
}

#[test]
fn speed_at_or_above_wave_speed() {
    let e = err_of(replace(
        "speed_kmh = { value = 250.0",
        "speed_kmh = { value = 450.0",
    ));
    assert!(
        e.contains("run.speed_kmh") && e.contains("450") && e.contains("wave speed"),
        "{e}"
    );
}

#[test]
fn high_speed_ratio_warns() {
    let (mut case, _) = presets::load("en50318-2002").unwrap();
    case.run.speed_kmh = 320.0;
    let w = Setup::from_case(&case).unwrap().warnings;
    assert!(w.iter().any(|w| w.0.contains("0.7")), "{w:?}");
    case.run.speed_kmh = 200.0;
    assert!(Setup::from_case(&case).unwrap().warnings.is_empty());
}

#[test]
fn analysis_section_outside_the_model() {
    let e = err_of(replace("value = [300.0, 900.0]", "value = [300.0, 1900.0]"));
    assert!(e.contains("run.analysis_m") && e.contains("1900"), "{e}");
}

#[test]
fn nan_names_the_field() {
    let e = err_of(replace(
        "ei_nm2 = { value = 195.0",
        "ei_nm2 = { value = nan",
    ));
    assert!(
        e.contains("catenary.contact_wire.ei_nm2") && e.to_lowercase().contains("nan"),
        "{e}"
    );
}

#[test]
fn unknown_preset() {
    match presets::load("nope") {
        Err(CaseError::UnknownPreset(n)) => assert_eq!(n, "nope"),
        other => panic!("{other:?}"),
    }
}

#[test]
fn invalid_toml_reports_a_line() {
    let e = err_of(replace("[run]\n", "[run\n"));
    assert!(e.contains("line"), "{e}");
}

#[test]
fn time_step_too_large_for_the_modes() {
    let e = err_of(replace(
        "modes_per_m = { value = 1.0",
        "modes_per_m = { value = 6.0",
    ));
    assert!(
        e.contains("run.dt_s")
            && e.contains("0.001")
            && e.contains("contact_wire wire's own vertical stiffness"),
        "{e}"
    );
}

#[test]
fn encumbrance_too_small_for_the_messenger_sag() {
    let e = err_of(replace(
        "encumbrance_m = { value = 1.2",
        "encumbrance_m = { value = 0.3",
    ));
    assert!(
        e.contains("catenary.encumbrance_m") && e.contains("0.3"),
        "{e}"
    );
}

#[test]
fn droppers_too_stiff_for_the_step_are_refused_before_the_run() {
    // Stable wire modes but droppers far too stiff for the explicit step: refused by the
    // coupled stability check (issue 20) before a step is taken, naming Δt and the droppers
    // (this case used to run until it blew up).
    let (mut case, _) = presets::load("en50318-2002").unwrap();
    case.catenary.droppers.stiffness_n_per_m = Some(1.0e9);
    let msg = pcsim_core::run_case(&case, &mut |_| true)
        .unwrap_err()
        .to_string();
    assert!(
        msg.contains("run.dt_s") && msg.contains("coupled system") && msg.contains("dropper"),
        "{msg}"
    );
}

#[test]
fn blow_up_stops_with_time_and_place() {
    // A load no catenary can hold (9 kN of uplift): the contact wire passes the messenger's
    // height (the system height, 1.2 m here) and the run stops with the time and the position
    // instead of writing numbers.
    let (mut case, _) = presets::load("en50318-2002").unwrap();
    match &mut case.pantographs[0] {
        pcsim_core::input::case::PantographCase::Lumped { uplift_n, .. } => *uplift_n = 9000.0,
        _ => unreachable!("the preset's pantograph is lumped"),
    }
    let err = pcsim_core::run_case(&case, &mut |_| true).unwrap_err();
    let msg = err.to_string();
    assert!(
        msg.contains("blow-up")
            && msg.contains("t = ")
            && msg.contains("x = ")
            && msg.contains("system height"),
        "{msg}"
    );
}

#[test]
fn contact_spring_too_stiff_for_the_step() {
    let e = err_of(replace(
        "[contact]\nstiffness_n_per_m = { value = 50000.0",
        "[contact]\nstiffness_n_per_m = { value = 5.0e8",
    ));
    assert!(
        e.contains("contact.stiffness_n_per_m") && e.contains("500000000"),
        "{e}"
    );
}

#[test]
fn pathological_values_are_errors_naming_the_field() {
    for (from, to, field) in [
        (
            "encumbrance_m = { value = 1.2",
            "encumbrance_m = { value = 1e300",
            "catenary.encumbrance_m",
        ),
        (
            "value = [7.2, 15.0]",
            "value = [1e300, 15.0]",
            "pantographs[0].masses_kg[0]",
        ),
        (
            "modes_per_m = { value = 1.0",
            "modes_per_m = { value = 1e-9",
            "run.modes_per_m",
        ),
        (
            "mid_span_m = { value = 0.055",
            "mid_span_m = { value = 5.0",
            "catenary.presag.mid_span_m",
        ),
        (
            "tension_n = { value = 20000.0",
            "tension_n = { value = 2e7",
            "catenary.contact_wire.tension_n",
        ),
    ] {
        let e = err_of(replace(from, to));
        assert!(e.contains(field), "{to}: {e}");
    }
    // modes_per_m = 1e-9 no longer becomes one mode per wire without a word.
    let e = err_of(replace(
        "modes_per_m = { value = 1.0",
        "modes_per_m = { value = 1e-9",
    ));
    assert!(e.contains("fewer than 2 modes per span"), "{e}");
}

#[test]
fn unusual_values_are_warnings_naming_the_field() {
    let (mut case, _) = presets::load("en50318-2002").unwrap();
    case.run.speed_kmh = 200.0;
    case.catenary.contact_wire.tension_n = 80_000.0;
    case.pantographs[0] = match case.pantographs[0].clone() {
        pcsim_core::input::case::PantographCase::Lumped {
            name,
            offset_m,
            masses_kg,
            stiffness_n_per_m,
            damping_ns_per_m,
            aero_coeffs_kmh,
            head_half_width_m,
            working_half_width_m,
            ..
        } => pcsim_core::input::case::PantographCase::Lumped {
            name,
            offset_m,
            masses_kg,
            stiffness_n_per_m,
            damping_ns_per_m,
            uplift_n: 900.0,
            uplift_by_height: None,
            aero_coeffs_kmh,
            head_half_width_m,
            working_half_width_m,
            strips: Vec::new(),
        },
        other => other,
    };
    let w = Setup::from_case(&case).unwrap().warnings;
    let text: Vec<String> = w.iter().map(|w| w.0.clone()).collect();
    for field in ["catenary.contact_wire.tension_n", "pantographs[0].uplift_n"] {
        assert!(
            text.iter()
                .any(|t| t.contains(field) && t.contains("unusual")),
            "{field}: {text:?}"
        );
    }
}

/// The number of realisations is checked once, in the core, for the CLI and Python alike
/// (`analysis::sweep::check_seeds`): at least one, at most `MAX_SEEDS`, and several only for a
/// case with a seeded random input.
#[test]
fn the_number_of_realisations_is_checked_in_the_core() {
    use pcsim_core::analysis::sweep::{check_seeds, MAX_SEEDS};
    let (plain, _) = presets::load("syt-7.0-9.8").unwrap();
    assert!(!plain.is_random());
    assert_eq!(check_seeds(None, &plain), Ok(1));
    assert!(check_seeds(Some(3), &plain)
        .unwrap_err()
        .contains("no seeded random input"));
    let mut random = plain.clone();
    random
        .irregularity
        .push(pcsim_core::input::case::IrregularityCase::Droppers {
            rms_m: 0.005,
            seed: 7,
        });
    assert!(random.is_random());
    assert_eq!(check_seeds(Some(3), &random), Ok(3));
    assert!(check_seeds(Some(0), &random)
        .unwrap_err()
        .contains("at least 1"));
    assert!(check_seeds(Some(MAX_SEEDS + 1), &random)
        .unwrap_err()
        .contains("at most"));
}

/// Every section a preset cites (`ref §N.M`, `docs/reference.md §N.M`) exists in the
/// repository's copy of the reference notes, `docs/reference.md` (issue 19, item 8: sources cited
/// a "README §3.1" that did not exist, and one read "CALIBRATE"): as a heading `### N.M`, or as
/// item `M.` of section `## N.`.
#[test]
fn every_section_a_preset_cites_exists_and_no_source_is_a_placeholder() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let reference = std::fs::read_to_string(root.join("docs/reference.md")).unwrap();
    let mut sections: Vec<String> = Vec::new();
    let mut current = String::new();
    for line in reference.lines() {
        if let Some(h) = line.strip_prefix("## ") {
            current = h.split('.').next().unwrap_or("").trim().to_string();
            sections.push(current.clone());
        } else if let Some(h) = line.strip_prefix("### ") {
            sections.push(h.split_whitespace().next().unwrap_or("").to_string());
        } else if let Some((n, _)) = line.split_once(". ") {
            if !current.is_empty() && !n.is_empty() && n.chars().all(|c| c.is_ascii_digit()) {
                sections.push(format!("{current}.{n}"));
            }
        }
    }
    let mut cited = 0;
    for p in PRESETS {
        for (i, _) in p.toml.match_indices('§') {
            let n: String = p.toml[i + '§'.len_utf8()..]
                .chars()
                .take_while(|c| c.is_ascii_digit() || *c == '.')
                .collect();
            let n = n.trim_end_matches('.').to_string();
            let before = &p.toml[..i];
            let refers = before.ends_with("ref ") || before.ends_with("docs/reference.md ");
            if refers {
                cited += 1;
                assert!(
                    sections.contains(&n),
                    "{} cites §{n}, which docs/reference.md does not have",
                    p.name
                );
            }
        }
        for bad in ["CALIBRATE", "TODO", "TBD", "README §"] {
            assert!(!p.toml.contains(bad), "{}: a source reads `{bad}`", p.name);
        }
    }
    assert!(cited > 100, "only {cited} citations found");
}

/// Issue 20, item 3: no contact, no numbers — a validation whose pantograph never presses on the
/// wire is refused before any run, naming the field.
#[test]
fn a_validation_of_a_pantograph_that_never_touches_is_refused() {
    use pcsim_core::study::sweeps::{run_quietly, validation_runs};
    use pcsim_core::study::validate::ValidationPlan;
    let mut plan = ValidationPlan::new("en50318-2002").unwrap();
    for c in &mut plan.cases {
        if let pcsim_core::input::case::PantographCase::Lumped { uplift_n, .. } =
            &mut c.pantographs[0]
        {
            *uplift_n = -500.0;
        }
    }
    let budget = pcsim_core::Budget::default();
    let e = validation_runs(&plan, None, &|c| run_quietly(c, &budget))
        .expect_err("refused")
        .to_string();
    assert!(
        e.contains("pantographs[0].uplift_n") && e.contains("validation"),
        "{e}"
    );
}
