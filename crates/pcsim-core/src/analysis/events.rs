//! A run's error-level events (a dewirement, contact lost over a tenth of the section) and
//! which of them a user accepted by flag: the one rule every front end and every study applies
//! (`report.rs` lists them in the summary; `sensitivity.rs` and Monte Carlo count them over their
//! runs). Its own file so that neither of those imports the other.

use serde::{Deserialize, Serialize};

use crate::analysis::record::RunOutput;

/// Share of the analysis section with contact lost above which a run's contact force statistics
/// are an error-level event, %: beyond it they describe a pantograph more often in the air than a
/// contact that was measured (for scale, the TSI Energy's limit on the share of arcing is 0.2 %).
pub const LOSS_OF_CONTACT_ERROR_PERCENT: f64 = 10.0;

/// What kind of error-level event a run met (each front end may accept a kind on request);
/// written as its [`RunErrorKind::name`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum RunErrorKind {
    /// The contact wire left a pantograph's head.
    Dewirement,
    /// Contact lost over more than [`LOSS_OF_CONTACT_ERROR_PERCENT`] of the analysis section.
    ContactLoss,
}

impl RunErrorKind {
    /// Every kind, in the order they are reported.
    pub const ALL: [RunErrorKind; 2] = [RunErrorKind::Dewirement, RunErrorKind::ContactLoss];

    /// Its name in the outputs (`montecarlo.json`, Python's `allow=`): `dewirement`,
    /// `contact_loss`.
    pub fn name(self) -> &'static str {
        match self {
            RunErrorKind::Dewirement => "dewirement",
            RunErrorKind::ContactLoss => "contact_loss",
        }
    }

    /// The command line's flag that accepts it (Python's keyword is the same without the
    /// dashes, `allow_contact_loss=True`).
    pub fn flag(self) -> &'static str {
        match self {
            RunErrorKind::Dewirement => "--allow-dewirement",
            RunErrorKind::ContactLoss => "--allow-contact-loss",
        }
    }
}

/// The error-level events a user accepted on request (the CLI's `--allow-dewirement` and
/// `--allow-contact-loss`, Python's `allow_dewirement=` and `allow_contact_loss=`): the one rule
/// that decides whether a run's events refuse it, for every front end and for a Monte Carlo study.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct AllowedErrors {
    /// A dewirement is accepted.
    pub dewirement: bool,
    /// Contact loss over [`LOSS_OF_CONTACT_ERROR_PERCENT`] is accepted.
    pub contact_loss: bool,
}

impl AllowedErrors {
    /// Whether events of `kind` are accepted.
    pub fn allows(&self, kind: RunErrorKind) -> bool {
        match kind {
            RunErrorKind::Dewirement => self.dewirement,
            RunErrorKind::ContactLoss => self.contact_loss,
        }
    }

    /// The first of `errors` that is not accepted (the one a front end refuses the run with).
    pub fn first_refused<'a>(&self, errors: &'a [RunError]) -> Option<&'a RunError> {
        errors.iter().find(|e| !self.allows(e.kind))
    }
}

/// How often each kind of error-level event occurred over several runs (a Monte Carlo study's
/// realisations): per kind, the indices of the runs that had it and the first run's message.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct EventCount {
    /// The kind (written as its name, [`RunErrorKind::name`]).
    pub kind: RunErrorKind,
    /// The runs (realisation indices) that had it.
    pub runs: Vec<usize>,
    /// The first such run's message.
    pub first_message: String,
    /// Whether the user accepted it by flag.
    pub allowed: bool,
}

/// The events of several runs, counted per kind (kinds that did not occur are left out).
pub fn count_events(per_run: &[Vec<RunError>], allowed: AllowedErrors) -> Vec<EventCount> {
    RunErrorKind::ALL
        .iter()
        .filter_map(|&k| {
            let runs: Vec<usize> = per_run
                .iter()
                .enumerate()
                .filter(|(_, es)| es.iter().any(|e| e.kind == k))
                .map(|(i, _)| i)
                .collect();
            let first = runs.first()?;
            let first_message = per_run[*first]
                .iter()
                .find(|e| e.kind == k)
                .map(|e| e.message.clone())
                .unwrap_or_default();
            Some(EventCount {
                kind: k,
                runs,
                first_message,
                allowed: allowed.allows(k),
            })
        })
        .collect()
}

/// One error-level event of a run.
#[derive(Debug, Clone, PartialEq)]
pub struct RunError {
    /// Its kind.
    pub kind: RunErrorKind,
    /// What happened, for `summary.json`'s `errors` and the terminal.
    pub message: String,
}

/// The run's error-level events, built here once for every front end: a dewirement (the contact
/// wire left a pantograph's head in the analysis section; beyond the head there is no contact,
/// so the EN 50318 statistics include those samples as loss of contact), and otherwise contact
/// lost over more than [`LOSS_OF_CONTACT_ERROR_PERCENT`] of the section.
pub fn run_errors(out: &RunOutput) -> Vec<RunError> {
    let mut v = Vec::new();
    for p in &out.pantographs {
        let dewired = p.lateral.as_ref().filter(|l| l.samples_off_head > 0);
        if let Some(l) = dewired {
            v.push(RunError {
                kind: RunErrorKind::Dewirement,
                message: format!(
                    "pantograph {}: dewirement: the contact wire left the head in {} samples of the analysis section (closest margin {:.0} mm); there the contact force is zero, and the statistics include those samples as loss of contact",
                    p.name,
                    l.samples_off_head,
                    l.min_head_margin_mm.unwrap_or(f64::NAN)
                ),
            });
        }
        // A dewirement already explains (and reports) the contact it loses.
        if let Some(s) = p.stats.as_ref().filter(|s| {
            dewired.is_none() && s.loss_of_contact_percent > LOSS_OF_CONTACT_ERROR_PERCENT
        }) {
            v.push(RunError {
                kind: RunErrorKind::ContactLoss,
                message: format!(
                    "pantograph {}: contact lost over {:.1} % of the analysis section (more than {LOSS_OF_CONTACT_ERROR_PERCENT} %): its force statistics mix contact with flight",
                    p.name, s.loss_of_contact_percent
                ),
            });
        }
    }
    v
}
