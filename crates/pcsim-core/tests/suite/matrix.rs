//! Issue 41, item 6: the capability × geometry matrix as a test. Every capability of the core
//! (a run, the EVA, the real-time window in SIL and in HIL, Monte Carlo, dropper fatigue, the
//! assessment) runs on every geometry (the catenary and the line, each vertical, in 3D, with a
//! crosswind, a curve, ice, irregularity) on a tiny case. Each cell is either a result that
//! passes its check (finite, plausible numbers; the HIL window fed with the full run's force
//! accepts every step) or a refusal by name (`CaseError::Invalid`, its field and reason); a
//! blow-up, a panic or any other error fails the test. The table and every refusal's reason are
//! written to `docs/matrix.md`, which must equal what the test finds (`PCSIM_BLESS=1` rewrites
//! it): the docs' matrix is generated from this test, never typed.

use pcsim_core::analysis::assess::{assess, AssessInput};
use pcsim_core::analysis::compare::compare;
use pcsim_core::analysis::eva::{run_eva, EvaSettings};
use pcsim_core::analysis::events::AllowedErrors;
use pcsim_core::analysis::record::{simulate_with, DropperOptions};
use pcsim_core::analysis::report::RunSummary;
use pcsim_core::analysis::sensitivity::{sensitivity, SensitivitySpec};
use pcsim_core::analysis::sweep::check_seeds;
use pcsim_core::analysis::verify::verify;
use pcsim_core::compile::Budget;
use pcsim_core::input::case::Case;
use pcsim_core::input::criteria::{self, System};
use pcsim_core::input::design::DesignSpec;
use pcsim_core::input::measured::MeasuredForce;
use pcsim_core::session::RealtimeSession;
use pcsim_core::solve::realtime::Coupling;
use pcsim_core::study::design::{search, Design, Local};
use pcsim_core::study::montecarlo::monte_carlo;
use pcsim_core::study::realtime::run_window_sil;
use pcsim_core::study::sweeps::validation_runs;
use pcsim_core::study::validate::ValidationPlan;
use pcsim_core::zoo::geometries::{matrix_block, with_matrix_block};
use pcsim_core::{run_case, CaseError, Setup, SimError};

/// The window of the real-time cells, m (shorter than every tiny case).
const WINDOW_M: f64 = 180.0;

/// What a cell found: the capability ran and passed its check, or it was refused by name.
#[derive(Debug, Clone, PartialEq)]
enum Cell {
    Runs,
    Refused { field: String, reason: String },
}

/// The geometries: a name and its tiny case (the core's zoo, shared with the front ends' tests).
fn geometries() -> Vec<(&'static str, Case)> {
    pcsim_core::zoo::geometries::geometries()
}

/// A refusal by name is a cell; anything else that fails is the test's failure.
fn cell(what: &str, r: Result<(), SimError>) -> Cell {
    match r {
        Ok(()) => Cell::Runs,
        Err(SimError::Case(CaseError::Invalid { field, reason, .. })) => {
            Cell::Refused { field, reason }
        }
        Err(e) => panic!("{what}: neither a result nor a refusal by name: {e}"),
    }
}

fn plausible(what: &str, mean_n: f64, std_n: f64) {
    assert!(
        mean_n.is_finite() && std_n.is_finite() && mean_n > 20.0 && mean_n < 500.0 && std_n >= 0.0,
        "{what}: mean {mean_n} N, σ {std_n} N"
    );
}

type Capability = (&'static str, fn(&Case, &str) -> Result<(), SimError>);

fn run(case: &Case, what: &str) -> Result<(), SimError> {
    let out = run_case(case, &mut |_| true)?;
    let s = out.pantographs[0]
        .stats
        .expect("the analysis section is crossed");
    plausible(what, s.mean_n, s.std_n);
    Ok(())
}

fn eva(case: &Case, what: &str) -> Result<(), SimError> {
    let setup = Setup::from_case(case)?;
    let e = run_eva(&setup, &EvaSettings::default(), &mut |_| true)?;
    for v in [&e.snapshot, &e.max, &e.mean] {
        assert!(
            v.total_j.is_finite() && v.total_j >= 0.0,
            "{what}: {}",
            v.total_j
        );
    }
    assert!(e.snapshot.total_j > 0.0, "{what}: no vibration energy");
    Ok(())
}

fn window_sil(case: &Case, what: &str) -> Result<(), SimError> {
    let w = run_window_sil(case, WINDOW_M)?;
    let s = w.stats.expect("the window crosses the analysis section");
    plausible(what, s.mean_n, s.std_n);
    Ok(())
}

fn window_hil(case: &Case, what: &str) -> Result<(), SimError> {
    let mut rt = RealtimeSession::new(case, WINDOW_M, Coupling::Hil)?;
    let full = run_case(&pcsim_core::compile::window_case(case)?, &mut |_| true)?;
    let p = &full.pantographs[0];
    for (f, x) in p.force_n.iter().zip(&p.position_m) {
        let o = rt
            .step(*f, *x)
            .unwrap_or_else(|e| panic!("{what}: the window refused a step at {x} m: {e:?}"));
        assert!(o.wire_height_m.is_finite(), "{what}");
    }
    Ok(())
}

fn montecarlo(case: &Case, what: &str) -> Result<(), SimError> {
    // Nothing injected: a geometry without a random input of its own is refused, saying why.
    let n = check_seeds(Some(2), case).map_err(|reason| {
        SimError::Case(CaseError::Invalid {
            field: "--seeds".into(),
            value: "2".into(),
            reason,
        })
    })?;
    let r = monte_carlo(case, n, Some(1), &Budget::default(), &|| {})?;
    assert_eq!(r.len(), 2, "{what}");
    let m: Vec<f64> = r
        .iter()
        .map(|x| x.output.pantographs[0].stats.unwrap().mean_n)
        .collect();
    m.iter().for_each(|&v| plausible(what, v, 0.0));
    assert_ne!(m[0], m[1], "{what}: two realisations alike");
    Ok(())
}

/// `--verify`: the run refined and with a stiffer contact, each statistic beside both.
fn verification(case: &Case, what: &str) -> Result<(), SimError> {
    let out = run_case(case, &mut |_| true)?;
    let v = verify(case, &out, &Budget::default(), Some(1))?;
    assert!(!v.pantographs.is_empty(), "{what}: nothing verified");
    for p in &v.pantographs {
        for s in &p.statistics {
            assert!(
                s.refined.is_finite() && s.stiff_contact.is_finite(),
                "{what}: {}",
                s.statistic
            );
        }
    }
    Ok(())
}

/// `--sensitivity`: the contact wire's tension ranged ±5 %, one at a time (two runs).
fn sensitivity_study(case: &Case, what: &str) -> Result<(), SimError> {
    let out = run_case(case, &mut |_| true)?;
    let t = case.catenary.contact_wire.tension_n;
    let ranged = pcsim_core::input::RangedValue {
        path: "catenary.contact_wire.tension_n".into(),
        value: t,
        low: 0.95 * t,
        high: 1.05 * t,
        source: None,
        range_source: Some("the matrix: ±5 %".into()),
        integer: false,
    };
    let spec = SensitivitySpec {
        samples: 0,
        ..SensitivitySpec::default()
    };
    let s = sensitivity(
        case,
        &out,
        &[ranged],
        &[],
        &spec,
        AllowedErrors::default(),
        &Budget::default(),
        Some(1),
        &|_, _| {},
    )?;
    s.check()?;
    let b = s
        .band(&out.pantographs[0].name, "std_n")
        .unwrap_or_else(|| panic!("{what}: no band"));
    assert!(b.low <= b.value && b.value <= b.high, "{what}: {b:?}");
    Ok(())
}

/// `pcsim validate CASE`: the case at the EN 50318:2002 speeds against its ranges.
fn validate_case(case: &Case, what: &str) -> Result<(), SimError> {
    let plan = ValidationPlan::new("en50318-2002")?.on_case(case.clone(), "matrix")?;
    let (runs, report) = validation_runs(&plan, Some(1), &|c| run_case(c, &mut |_| true))?;
    assert_eq!(runs.len(), 2, "{what}");
    assert!(
        report.cases.iter().all(|c| !c.rows.is_empty()),
        "{what}: no rows"
    );
    Ok(())
}

fn fatigue(case: &Case, what: &str) -> Result<(), SimError> {
    let setup = Setup::from_case(case)?;
    let opts = DropperOptions {
        history: false,
        history_limit: 0,
        curve: None,
    };
    let out = simulate_with(&setup, Some(opts), &mut |_| true)?;
    let d = out.droppers.expect("the droppers' record was asked for");
    assert!(!d.droppers.is_empty(), "{what}: no dropper");
    assert!(
        d.droppers
            .iter()
            .all(|x| x.min_n.is_finite() && x.max_n.is_finite() && x.max_n >= x.min_n),
        "{what}"
    );
    Ok(())
}

fn assessment(case: &Case, what: &str) -> Result<(), SimError> {
    let out = run_case(case, &mut |_| true)?;
    let summary = RunSummary::new(case, &out, 0.0, Vec::new(), Vec::new());
    let input = AssessInput::from_summary_json(&serde_json::to_string(&summary).unwrap())?;
    let a = assess(&input, &criteria::builtin(), Some(System::Ac));
    assert!(!a.rows.is_empty(), "{what}: no criterion assessed");
    Ok(())
}

/// The run against a measured record: the run's own contact force taken 2 m further on (every
/// fifth sample, as a recording car's CSV), which the alignment must find at a correlation of 1.
fn comparison(case: &Case, what: &str) -> Result<(), SimError> {
    let out = run_case(case, &mut |_| true)?;
    let p = &out.pantographs[0];
    let mut csv = String::from("position_m,force_n\n");
    for (x, f) in p.position_m.iter().zip(&p.force_n).step_by(5) {
        csv.push_str(&format!("{},{f}\n", x - 2.0));
    }
    let meas = MeasuredForce::from_csv(&csv, "measured.csv")?;
    let supports = Setup::from_case(case)?.model.supports_m.clone();
    let c = compare(
        (&p.position_m, &p.force_n),
        &meas,
        case.speed_m_s(),
        case.run.analysis_m,
        10.0,
        &supports,
    )?;
    assert!(
        (c.shift_m - 2.0).abs() <= meas.spacing_m && c.correlation > 0.99,
        "{what}: shift {} m, correlation {}",
        c.shift_m,
        c.correlation
    );
    assert!(c.warnings.is_empty(), "{what}: {:?}", c.warnings);
    Ok(())
}

/// A design search of three evaluations over the contact wire's tension (±10 % of the case's;
/// the mean force towards 120 N): every evaluation finite, the best one confirmed by its own
/// run.
fn design_search(case: &Case, what: &str) -> Result<(), SimError> {
    let t = case.catenary.contact_wire.tension_n;
    let spec = DesignSpec::from_toml_str(&format!(
        r#"
[base]
file = "case.toml"

[[variable]]
path = "catenary.contact_wire.tension_n"
min = {:?}
max = {:?}

[[speed]]
kmh = 250.0

[[objective]]
statistic = "mean_n"
pantograph = "leading"
target = 120.0

[budget]
evaluations = 3
method = "nelder-mead"
"#,
        0.9 * t,
        1.1 * t
    ))
    .unwrap_or_else(|e| panic!("{what}: {e}"));
    let d = Design::new(spec, case.clone())?;
    let r = search(
        &d,
        Vec::new(),
        &Local { jobs: Some(1) },
        Some(1),
        &mut |_| true,
    )?;
    assert!(
        r.evaluations.len() >= 3,
        "{what}: {} evaluations",
        r.evaluations.len()
    );
    for e in &r.evaluations {
        let fm = e.values[0][0].unwrap_or_else(|| panic!("{what}: {e:?}"));
        plausible(what, fm, 0.0);
    }
    let best = r
        .best
        .unwrap_or_else(|| panic!("{what}: no feasible design"));
    assert!(best < r.evaluations.len());
    let (_, same) = r
        .confirmation
        .as_ref()
        .expect("the best design is confirmed");
    assert!(*same, "{what}: the confirmation differs");
    Ok(())
}

/// Issue 54: the current-collection study (the default spec's first train at the case's speed):
/// the wire wears (Archard's term > 0, every bin finite), NQ within the loss of contact, the
/// strips' wear exactly where the case models the contact point's path across the head.
fn current_collection(case: &Case, what: &str) -> Result<(), SimError> {
    use pcsim_core::study::wear::{WearSpec, WearStudy, DEFAULT_SPEC};
    use pcsim_core::study::Study;
    let mut spec = WearSpec::from_toml_str(DEFAULT_SPEC).unwrap();
    spec.trains.truncate(1);
    spec.trains[0].speed_kmh.value = case.run.speed_kmh;
    let study = WearStudy {
        spec,
        case: case.clone(),
    };
    Study::check(&study)?;
    let o = study.run(&|| {})?;
    for p in &o.trains[0].pantographs {
        assert!(
            p.wire_terms_mm3[0] > 0.0 && p.wire_terms_mm3.iter().all(|v| v.is_finite()),
            "{what}: {:?}",
            p.wire_terms_mm3
        );
        assert!(
            p.nq_percent <= p.loss_percent + 1e-12,
            "{what}: NQ {} %, loss {} %",
            p.nq_percent,
            p.loss_percent
        );
        assert_eq!(p.strip.is_some(), o.lateral, "{what}");
    }
    assert!(
        o.wire
            .daily_mm3_per_m
            .iter()
            .all(|v| v.is_finite() && *v >= 0.0),
        "{what}"
    );
    assert!(o.wire.years_to_limit.is_some_and(|y| y > 0.0), "{what}");
    Ok(())
}

const CAPABILITIES: &[Capability] = &[
    ("run", run),
    ("eva", eva),
    ("window (SIL)", window_sil),
    ("window (HIL)", window_hil),
    ("Monte Carlo", montecarlo),
    ("dropper fatigue", fatigue),
    ("assess", assessment),
    ("compare", comparison),
    ("design", design_search),
    ("verify", verification),
    ("sensitivity", sensitivity_study),
    ("validate CASE", validate_case),
    ("current collection", current_collection),
];

/// The matrix as Markdown: a table of cells, then every refusal with its reason.
fn render(rows: &[(&str, Vec<Cell>)]) -> String {
    let mut s = String::from(
        "Generated by `cargo test --release -p pcsim-core --test suite matrix::` \
         (`crates/pcsim-core/tests/suite/matrix.rs`; `PCSIM_BLESS=1` rewrites this file, and the \
         test fails while it differs). Each cell ran on a tiny case of its geometry (8 spans of \
         a catenary, or two tension lengths of six spans with a 3-span overlap; 250 km/h): \
         \"runs\" passed its check (finite, plausible forces and energies; the HIL window fed \
         with the full run's force accepted every step); a refusal names the field, and its \
         reason, the physical one, is listed below the table. A blow-up, a panic or an error \
         without a field fails the test. Nothing is injected to make a cell run: a Monte Carlo \
         study of a case without a random input of its own is refused, saying so. The \
         sensitivity cell ranges the contact wire's tension ±5 %; the design cell searches it \
         ±10 %; validate CASE runs the case at the EN 50318:2002 speeds. The front ends' own \
         tables follow the capabilities'.\n\n",
    );
    s.push_str("| geometry |");
    for (name, _) in CAPABILITIES {
        s.push_str(&format!(" {name} |"));
    }
    s.push_str("\n|---|");
    for _ in CAPABILITIES {
        s.push_str("---|");
    }
    s.push('\n');
    let mut reasons: Vec<(String, String)> = Vec::new();
    for (g, cells) in rows {
        s.push_str(&format!("| {g} |"));
        for c in cells {
            match c {
                Cell::Runs => s.push_str(" runs |"),
                Cell::Refused { field, reason } => {
                    let key = (field.clone(), reason.clone());
                    let i = match reasons.iter().position(|r| *r == key) {
                        Some(i) => i,
                        None => {
                            reasons.push(key);
                            reasons.len() - 1
                        }
                    };
                    s.push_str(&format!(" refused: `{field}` [{}] |", i + 1));
                }
            }
        }
        s.push('\n');
    }
    if !reasons.is_empty() {
        s.push_str("\nThe refusals, each with the reason the tool gives:\n\n");
        for (i, (field, reason)) in reasons.iter().enumerate() {
            s.push_str(&format!("{}. `{field}`: {reason}\n", i + 1));
        }
    }
    s
}

#[test]
fn issue_41_6_every_capability_on_every_geometry_runs_or_is_refused_by_name() {
    let mut rows = Vec::new();
    for (g, case) in geometries() {
        let cells: Vec<Cell> = CAPABILITIES
            .iter()
            .map(|(name, f)| {
                let what = format!("{name} on {g}");
                cell(&what, f(&case, &what))
            })
            .collect();
        rows.push((g, cells));
    }
    let text = render(&rows);
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../docs/matrix.md");
    let doc = std::fs::read_to_string(path).unwrap_or_default();
    if std::env::var_os("PCSIM_BLESS").is_some() {
        std::fs::write(path, with_matrix_block(&doc, "core", &text)).unwrap();
    }
    let committed = std::fs::read_to_string(path).unwrap_or_default();
    assert!(
        matrix_block(&committed, "core") == Some(text.as_str()),
        "docs/matrix.md differs from what the matrix finds (PCSIM_BLESS=1 rewrites it):\n{text}"
    );
    // What the line must carry: every capability on a vertical line, a 3D one, and with every
    // load at once; in a crosswind all but the real-time window, which refuses it by name; a
    // Monte Carlo study wherever the case has a random input of its own (nothing injected:
    // without one it is refused, saying so).
    let random: Vec<bool> = geometries().iter().map(|(_, c)| c.is_random()).collect();
    for ((g, cells), random) in rows.iter().zip(random) {
        for ((name, _), c) in CAPABILITIES.iter().zip(cells) {
            let windowed = name.starts_with("window");
            let wind = g.contains("crosswind");
            if *name == "Monte Carlo" && !random {
                assert!(
                    matches!(c, Cell::Refused { field, .. } if field == "--seeds"),
                    "{name} on {g}: {c:?}"
                );
                continue;
            }
            if g.starts_with("line") && !(wind && windowed) {
                assert_eq!(*c, Cell::Runs, "{name} on {g}");
            }
            if wind && windowed {
                assert!(
                    matches!(c, Cell::Refused { field, .. } if field == "wind"),
                    "{name} on {g}: {c:?}"
                );
            }
        }
    }
}
