//! The compile step (MuJoCo's rule: no engine file reads the file format): the one place that
//! reads a [`Case`] and turns it into what the engine takes — the [`Model`] (`model.rs`), the
//! [`Plan`] of the run and the integrator's [`Options`], checked once: the case validated, the
//! resources estimated against the [`Budget`], the speed and the time step checked for stability.
//!
//! Layers: `model/` and `solve/` import nothing from `input/`; `input/` reuses the model's
//! vocabulary (damping, pre-sag, sections); this module imports them all (`tests/suite/layers.rs`).

pub mod budget;
pub mod model;

pub use budget::{Budget, Estimate};
pub use model::{model_from_case, static_balance, StaticBalance, CONTACT, MESSENGER};

use crate::error::{CaseError, Warning};
use crate::input::case::Case;
use crate::model::build::BuilderRun;
use crate::model::Model;
use crate::solve::integrator::Integrator;
use crate::solve::realtime::{Coupling, RealtimeCatenary};
use crate::solve::stability;
use crate::solve::{ContactSample, Options, Plan, State, Workspace};

/// The plan of a validated case: the run lasts until the rearmost pantograph reaches
/// `run.end_m`.
pub fn plan_of(case: &Case) -> Plan {
    let v = case.speed_m_s();
    let max_off = case
        .pantographs
        .iter()
        .map(|p| p.offset_m())
        .fold(0.0, f64::max);
    Plan {
        speed_kmh: case.run.speed_kmh,
        speed_m_s: v,
        start_m: case.run.start_m,
        duration_s: (case.run.end_m - (case.run.start_m - max_off)) / v,
        analysis_m: case.run.analysis_m,
    }
}

/// What a case becomes: the model (the problem), the plan of the run and the integrator's
/// options, with the warnings found on the way.
#[derive(Debug, Clone)]
pub struct Setup {
    /// The model (the problem).
    pub model: Model,
    /// The run's plan (speed, start, duration, analysis section).
    pub plan: Plan,
    /// The integrator's options (Δt, kernels).
    pub options: Options,
    /// Warnings found while building the set-up.
    pub warnings: Vec<Warning>,
}

impl Setup {
    /// Validate a case and build its model, plan and options, within the default [`Budget`].
    pub fn from_case(case: &Case) -> Result<Setup, CaseError> {
        Self::from_case_with(case, &Budget::default())
    }

    /// [`Setup::from_case`] within a given budget: the run's steps and memory are estimated
    /// from the case before anything is built, and refused with an error naming the cause when
    /// they exceed it.
    pub fn from_case_with(case: &Case, budget: &Budget) -> Result<Setup, CaseError> {
        // Validated once, here; the model is built from the validated case.
        let validated = case.validate()?;
        budget.check(case)?;
        let (model, mut warnings) = model::model_from_validated(case, validated)?;
        let plan = plan_of(case);
        warnings.extend(plan.check(&model).map_err(in_case_terms)?);
        let options = Options::new(case.run.dt_s);
        // Δt against the local explicit limits, here, so that a case is refused before anything
        // is compiled; the coupled limit needs the compiled model and is checked when the
        // integrator is built (`solve::stability`).
        stability::check_local(&model, options.dt_s).map_err(in_case_terms)?;
        Ok(Setup {
            model,
            plan,
            options,
            warnings,
        })
    }

    /// A hand-made model and its run (`model::ModelBuilder`).
    pub fn from_builder((model, run): (Model, BuilderRun)) -> Setup {
        let length = model.length_m();
        Setup {
            model,
            plan: Plan {
                speed_kmh: run.speed_m_s * 3.6,
                speed_m_s: run.speed_m_s,
                start_m: run.start_m,
                duration_s: run.duration_s,
                analysis_m: [0.0, length],
            },
            options: Options::new(run.dt_s),
            warnings: Vec::new(),
        }
    }

    /// The integrator of this set-up: the model compiled, the time step checked against the
    /// local and coupled limits ([`crate::solve::stability`]), the Δt operators built.
    pub fn integrator(&self) -> Result<Integrator, CaseError> {
        Integrator::new(self.model.clone(), &self.plan, self.options).map_err(in_case_terms)
    }

    /// Number of steps of the run.
    pub fn n_steps(&self) -> usize {
        self.plan.n_steps(self.options.dt_s)
    }
}

/// An integrator with its state and workspace: the convenient way to step a set-up by hand.
#[derive(Debug, Clone)]
pub struct Stepper {
    /// The stepper.
    pub integ: Integrator,
    /// The state it steps.
    pub state: State,
    /// Its scratch and samples.
    pub ws: Workspace,
}

impl Stepper {
    /// A stepper at the initial (static) state of the set-up.
    pub fn new(setup: &Setup) -> Result<Stepper, CaseError> {
        let integ = setup.integrator()?;
        let state = integ.initial_state(setup.plan.start_m);
        let ws = integ.workspace();
        Ok(Stepper { integ, state, ws })
    }

    /// One step.
    pub fn step(&mut self) {
        self.integ.step(&mut self.state, &mut self.ws);
    }

    /// The model.
    pub fn model(&self) -> &Model {
        self.integ.model()
    }

    /// Contact samples of the last step.
    pub fn samples(&self) -> &[ContactSample] {
        self.ws.samples()
    }
}

/// The leading pantograph's static push on the contact wire at the run's speed, N: a lumped
/// pantograph's uplift plus its aerodynamic force (Eq. 17 as a polynomial), or a moving force.
pub fn static_contact_force_n(case: &Case) -> f64 {
    use crate::input::case::PantographCase;
    match case.pantographs.first() {
        Some(PantographCase::Lumped {
            uplift_n,
            aero_coeffs_kmh,
            ..
        }) => {
            uplift_n + crate::model::pantograph::aero_force_n(aero_coeffs_kmh, case.run.speed_kmh)
        }
        Some(PantographCase::MovingForce { force_n, .. }) => *force_n,
        None => 0.0,
    }
}

/// Refuse a `study` (the window search, the real-time study, the EVA) of a case whose leading
/// pantograph never touches the wire: its static push is not upward, so the contact force is
/// zero throughout, the window's relative errors divide by zero and the EVA measures a catenary
/// nobody disturbs.
pub fn require_contact(case: &Case, study: &str) -> Result<(), CaseError> {
    let f = static_contact_force_n(case);
    if f > 0.0 {
        return Ok(());
    }
    let field = match case.pantographs.first() {
        Some(crate::input::case::PantographCase::MovingForce { .. }) => "pantographs[0].force_n",
        _ => "pantographs[0].uplift_n",
    };
    Err(CaseError::Invalid {
        field: field.into(),
        value: format!("a static push of {f} N at {} km/h", case.run.speed_kmh),
        reason: format!(
            "the leading pantograph never presses on the contact wire (its uplift plus aerodynamic force is not upward), so {study} has nothing to measure: its errors relative to a zero contact force are undefined"
        ),
    })
}

/// The case of a real-time window, and of the full-model run it is compared with: `case` with the
/// pantograph the window follows only (`run.window_pantograph`: the leading one by default, the
/// trailing one, a name or an index; its offset kept, so the window's input is that
/// pantograph's own track position). The window carries one pantograph (the rig's): another
/// pantograph's waves reach it only through a catenary the window does not hold, so the window
/// and its reference both leave the others out. This is the one place that says so, and
/// [`realtime_window`] applies it. An unknown selection is refused, naming the pantographs; a
/// crosswind is refused, naming `wind` (the window cannot carry it), before any run.
pub fn window_case(case: &Case) -> Result<Case, CaseError> {
    // Refused here, before any run (a window study runs the full model first): every window
    // path passes through this function.
    if case.wind.is_some() {
        return Err(CaseError::Invalid {
            field: "wind".into(),
            value: "given".into(),
            reason: "the real-time window does not carry a crosswind: the turbulent field is generated before a run, along the whole line, for the run's known duration, and a window session runs as long and as fast as the rig drives it, past any field made in advance (a field generated ahead of the window while it runs is not built); remove [wind] for the window".into(),
        });
    }
    let p = window_pantograph(case)?;
    let mut single = case.clone();
    let keep = single.pantographs.swap_remove(p);
    single.pantographs = vec![keep];
    single.run.window_pantograph = None;
    Ok(single)
}

/// The index of the pantograph a real-time window follows (`run.window_pantograph`).
pub fn window_pantograph(case: &Case) -> Result<usize, CaseError> {
    pantograph_index(
        case,
        case.run.window_pantograph.as_deref(),
        "run.window_pantograph",
        "the real-time window follows",
    )
}

/// The index of the pantograph `sel` names (none: the leading one); an unknown one is refused
/// as `field`, saying what `purpose` needs.
fn pantograph_index(
    case: &Case,
    sel: Option<&str>,
    field: &str,
    purpose: &str,
) -> Result<usize, CaseError> {
    let n = case.pantographs.len();
    let Some(sel) = sel else {
        return Ok(0);
    };
    let names: Vec<String> = (0..n).map(|i| pantograph_name(case, i)).collect();
    let found = match sel {
        "leading" if n > 0 => Some(0),
        "trailing" if n > 0 => Some(n - 1),
        _ => names
            .iter()
            .position(|x| x == sel)
            .or_else(|| sel.parse::<usize>().ok().filter(|&i| i < n)),
    };
    found.ok_or_else(|| CaseError::Invalid {
        field: field.into(),
        value: sel.to_string(),
        reason: format!(
            "{purpose} one of the case's pantographs: \"leading\", \"trailing\", a name ({}) or an index below {n}",
            names.join(", ")
        ),
    })
}

/// The lumped chain of the pantograph `which` selects (`leading`, `trailing`, a name or an
/// index; none: the leading one), with its name, for its frequency response and its fit
/// (`study/frf.rs`). A moving force has no chain: refused by its field.
pub fn lumped_pantograph(
    case: &Case,
    which: Option<&str>,
) -> Result<(String, crate::model::pantograph::Lumped), CaseError> {
    let i = pantograph_index(case, which, "pantograph", "give")?;
    match model::lumped_chain(&case.pantographs[i], 1.0, case.contact.stiffness_n_per_m) {
        Some(chain) => Ok((pantograph_name(case, i), chain)),
        None => Err(CaseError::Invalid {
            field: format!("pantographs[{i}].kind"),
            value: "moving_force".into(),
            reason: "a moving force has no masses, springs or dampers: no frequency response"
                .into(),
        }),
    }
}

/// Pantograph `i`'s name as the outputs give it (its own, or "leading" for the first and
/// "pantograph-k" for the others).
pub fn pantograph_name(case: &Case, i: usize) -> String {
    model::default_name(case.pantographs[i].name(), i)
}

/// The real-time window of `case` (the pantograph it follows only, [`window_case`]), `window_m`
/// long, coupled as `coupling`: the full model is compiled once, and the window is cut from it.
pub fn realtime_window(
    case: &Case,
    window_m: f64,
    coupling: Coupling,
) -> Result<RealtimeCatenary, CaseError> {
    realtime_window_with(case, window_m, coupling, &Budget::default())
}

/// [`realtime_window`] with the full model compiled within `budget`.
pub fn realtime_window_with(
    case: &Case,
    window_m: f64,
    coupling: Coupling,
    budget: &Budget,
) -> Result<RealtimeCatenary, CaseError> {
    let case = &window_case(case)?;
    let full = Setup::from_case_with(case, budget)?;
    let static_force_n = match case.pantographs.first() {
        Some(crate::input::case::PantographCase::Lumped { uplift_n, .. }) => *uplift_n,
        Some(crate::input::case::PantographCase::MovingForce { force_n, .. }) => *force_n,
        None => 0.0,
    };
    RealtimeCatenary::new(
        &full.model,
        &full.plan,
        full.options,
        case.catenary.span_m,
        static_force_n,
        window_m,
        coupling,
    )
    .map_err(in_case_terms)
}

/// An engine's error in the case's terms: a quantity the engine names in the model's terms
/// ([`CaseError::Model`]) becomes the case field that sets it; nested errors are mapped inside.
/// The one place where the engine's vocabulary meets the file format's.
pub fn in_case_terms(e: CaseError) -> CaseError {
    match e {
        CaseError::Model {
            what,
            value,
            reason,
        } => CaseError::Invalid {
            field: what.case_path(),
            value,
            reason,
        },
        CaseError::InCase { case, error } => CaseError::InCase {
            case,
            error: Box::new(in_case_terms(*error)),
        },
        CaseError::InFile { path, error } => CaseError::InFile {
            path,
            error: Box::new(in_case_terms(*error)),
        },
        other => other,
    }
}
