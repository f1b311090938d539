//! Issue 41, item 6: the capability × geometry matrix as a test. Every capability of the core
//! (a run, the EVA, the real-time window in SIL and in HIL, Monte Carlo, dropper fatigue, the
//! assessment) runs on every geometry (the catenary and the line, each vertical, in 3D, with a
//! crosswind, a curve, ice, irregularity) on a tiny case. Each cell is either a result that
//! passes its check (finite, plausible numbers; the HIL window fed with the full run's force
//! accepts every step) or a refusal by name (`CaseError::Invalid`, its field and reason); a
//! blow-up, a panic or any other error fails the test. The table and every refusal's reason are
//! written to `docs/matrix.md`, which must equal what the test finds (`PCSIM_BLESS=1` rewrites
//! it): the docs' matrix is generated from this test, never typed.

use crate::common;

use pcsim_core::analysis::assess::{assess, AssessInput};
use pcsim_core::analysis::compare::compare;
use pcsim_core::analysis::design::{search, Design, Local};
use pcsim_core::analysis::eva::{run_eva, EvaSettings};
use pcsim_core::analysis::montecarlo::monte_carlo;
use pcsim_core::analysis::record::{simulate_with, DropperOptions};
use pcsim_core::analysis::report::RunSummary;
use pcsim_core::analysis::studies::run_window_sil;
use pcsim_core::analysis::sweep::check_seeds;
use pcsim_core::compile::Budget;
use pcsim_core::input::case::{Case, IrregularityCase};
use pcsim_core::input::criteria::{self, System};
use pcsim_core::input::design::DesignSpec;
use pcsim_core::input::lateral::IceCase;
use pcsim_core::input::measured::MeasuredForce;
use pcsim_core::session::RealtimeSession;
use pcsim_core::solve::realtime::Coupling;
use pcsim_core::{presets, run_case, CaseError, Setup, SimError};

/// The window of the real-time cells, m (shorter than every tiny case).
const WINDOW_M: f64 = 180.0;

/// What a cell found: the capability ran and passed its check, or it was refused by name.
#[derive(Debug, Clone, PartialEq)]
enum Cell {
    Runs,
    Refused { field: String, reason: String },
}

fn sections_and_lateral(mut c: Case) -> Case {
    let d = presets::load("stitched-2018-like-3d").unwrap().0;
    c.catenary.messenger.section = d.catenary.messenger.section.clone();
    c.catenary.contact_wire.section = d.catenary.contact_wire.section.clone();
    c.catenary.lateral = d.catenary.lateral.clone();
    c.run.dofs = d.run.dofs.clone();
    c
}

fn sections(mut c: Case) -> Case {
    let d = presets::load("stitched-2018-like-3d").unwrap().0;
    c.catenary.messenger.section = d.catenary.messenger.section;
    c.catenary.contact_wire.section = d.catenary.contact_wire.section;
    c
}

fn iced(mut c: Case) -> Case {
    c.catenary.ice = Some(IceCase {
        density_kg_m3: 900.0,
        contact_wire_m: 0.005,
        messenger_m: 0.005,
    });
    c
}

fn rough(mut c: Case) -> Case {
    c.irregularity = vec![IrregularityCase::Psd {
        rms_m: 0.002,
        min_wavelength_m: 2.0,
        max_wavelength_m: 60.0,
        exponent: 2.0,
        table: None,
        seed: 7,
    }];
    c
}

/// The crosswind preset's wind, with its wires' coefficients (sections with `aero`).
fn windy(mut c: Case) -> Case {
    let w = presets::load("stitched-2018-like-3d-crosswind").unwrap().0;
    c.wind = w.wind;
    c.catenary.messenger.section = w.catenary.messenger.section;
    c.catenary.contact_wire.section = w.catenary.contact_wire.section;
    c
}

fn curved_line(mut c: Case) -> Case {
    for t in &mut c.line.as_mut().unwrap().tension_lengths {
        for r in &mut t.span_runs {
            r.track_radius_m = Some(2000.0);
        }
    }
    c
}

/// The geometries: a name and its tiny case.
fn geometries() -> Vec<(&'static str, Case)> {
    let cat = || common::short_en50318(8, 250.0);
    let cat3d = || common::short_preset("stitched-2018-like-3d", 8, 250.0);
    let line = common::overlap_line;
    let line3d = || sections_and_lateral(line());
    vec![
        ("catenary", cat()),
        ("catenary, 3D", cat3d()),
        (
            "catenary, 3D, crosswind",
            common::short_preset("stitched-2018-like-3d-crosswind", 8, 250.0),
        ),
        (
            "catenary, 3D, curve",
            common::short_preset("stitched-2018-like-3d-curve", 8, 250.0),
        ),
        ("catenary, ice", iced(sections(cat()))),
        ("catenary, irregularity", rough(cat())),
        ("line", line()),
        ("line, 3D", line3d()),
        ("line, 3D, crosswind", windy(line3d())),
        ("line, 3D, curve", curved_line(line3d())),
        ("line, ice", iced(sections(line()))),
        ("line, irregularity", rough(line())),
        (
            "line, 3D, crosswind, ice, irregularity",
            rough(iced(windy(line3d()))),
        ),
        (
            "line, 3D, curve, ice, irregularity",
            rough(iced(curved_line(line3d()))),
        ),
        (
            "line, 3D, crosswind, curve, ice, irregularity",
            rough(iced(curved_line(windy(line3d())))),
        ),
    ]
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
    let mut c = case.clone();
    if !c.is_random() {
        // A geometry without a random input of its own: the uplift perturbed, seeded.
        c.run.perturb_uplift_rel = 1e-3;
    }
    let n = check_seeds(Some(2), &c).unwrap_or_else(|e| panic!("{what}: {e}"));
    let r = monte_carlo(&c, n, Some(1), &Budget::default(), &|| {})?;
    assert_eq!(r.len(), 2, "{what}");
    let m: Vec<f64> = r
        .iter()
        .map(|x| x.output.pantographs[0].stats.unwrap().mean_n)
        .collect();
    m.iter().for_each(|&v| plausible(what, v, 0.0));
    assert_ne!(m[0], m[1], "{what}: two realisations alike");
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

/// A design search of three evaluations over the leading pantograph's uplift (its mean force
/// towards 120 N): every evaluation finite, the best one confirmed by its own run.
fn design_search(case: &Case, what: &str) -> Result<(), SimError> {
    let spec = DesignSpec::from_toml_str(
        r#"
[base]
file = "case.toml"

[[variable]]
path = "pantographs[0].uplift_n"
min = 100.0
max = 140.0

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
    )
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
];

/// The matrix as Markdown: a table of cells, then every refusal with its reason.
fn render(rows: &[(&str, Vec<Cell>)]) -> String {
    let mut s = String::from(
        "# The capability × geometry matrix\n\n\
         Generated by `cargo test --release -p pcsim-core --test suite matrix::` \
         (`crates/pcsim-core/tests/suite/matrix.rs`; `PCSIM_BLESS=1` rewrites this file, and the \
         test fails while it differs). Each cell ran on a tiny case of its geometry (8 spans of \
         a catenary, or two tension lengths of six spans with a 3-span overlap; 250 km/h): \
         \"runs\" passed its check (finite, plausible forces and energies; the HIL window fed \
         with the full run's force accepted every step); a refusal names the field, and its \
         reason, the physical one, is listed below the table. A blow-up, a panic or an error \
         without a field fails the test.\n\n",
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
    if std::env::var_os("PCSIM_BLESS").is_some() {
        std::fs::write(path, &text).unwrap();
    }
    let committed = std::fs::read_to_string(path).unwrap_or_default();
    assert!(
        committed == text,
        "docs/matrix.md differs from what the matrix finds (PCSIM_BLESS=1 rewrites it):\n{text}"
    );
    // What the line must carry: every capability on a vertical line, a 3D one, and with every
    // load at once; in a crosswind all but the real-time window, which refuses it by name.
    for (g, cells) in &rows {
        for ((name, _), c) in CAPABILITIES.iter().zip(cells) {
            let windowed = name.starts_with("window");
            let wind = g.contains("crosswind");
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
