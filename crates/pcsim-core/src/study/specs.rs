//! The studies' specs (issue 40, item 1): what a front end asks of a study, as typed values with
//! their defaults, their checks, their fingerprint and their job list, in one place. The CLI
//! translates its flags and Python its keyword arguments into a spec; neither holds a default, a
//! check or a fingerprint of its own (OpenFAST's typed input per module, which drivers fill and
//! never re-derive).
//!
//! - [`EvaSweepSpec`]: the EVA over speeds × tensions × dampings ([`crate::study::sweeps::eva_sweep`]);
//! - [`WindowSweepSpec`]: the accuracy-based window length over speeds × tensions
//!   ([`crate::study::sweeps::window_sweep`]);
//! - [`MonteCarloSpec`]: realisations of one case ([`crate::study::montecarlo`]);
//! - the design search's spec is [`crate::input::design::DesignSpec`] (a file of its own).
//!
//! Errors name the spec's field (`step_m`, `sigma_tol_pct`, …); a front end maps the name to its
//! own (the CLI's flag: [`EvaSweepSpec::FLAGS`], [`WindowSweepSpec::FLAGS`]).

use std::fmt::Write as _;

use crate::analysis::eva::EvaSettings;
use crate::analysis::events::AllowedErrors;
use crate::analysis::sweep::{damping_label, Grid, Job, Shard};
use crate::compile::Budget;
use crate::error::{CaseError, SimError};
use crate::fingerprint::fnv1a64_hex;
use crate::input::case::Case;
use crate::model::wire::Damping;
use crate::study::sweeps::{eva_sweep, window_sweep, EvaCase, WindowCase};
use crate::study::window_search::{SearchSettings, Tolerances};

/// The most positions across a span at which an EVA sweep takes the EVA (each is one more
/// evaluation of the energy density).
pub const MAX_SPAN_POSITIONS: usize = 64;

fn bad(field: &str, value: impl std::fmt::Display, reason: &str) -> CaseError {
    CaseError::Invalid {
        field: field.into(),
        value: value.to_string(),
        reason: reason.into(),
    }
}

/// The sweep's grid: speeds, tensions (empty: the case's), dampings (empty: the case's), the
/// realisations of the case's random inputs and the shard this process runs.
#[derive(Debug, Clone, PartialEq)]
pub struct GridSpec {
    /// Train speeds, km/h.
    pub speeds_kmh: Vec<f64>,
    /// Contact-wire tensions, N.
    pub tensions_n: Vec<f64>,
    /// Dampings of the catenary.
    pub dampings: Vec<Damping>,
    /// Realisations of the case's random inputs per grid point (1: the case as it is).
    pub seeds: usize,
    /// The part of the grid run here.
    pub shard: Shard,
}

impl Default for GridSpec {
    fn default() -> Self {
        GridSpec {
            speeds_kmh: Vec::new(),
            tensions_n: Vec::new(),
            dampings: Vec::new(),
            seeds: 1,
            shard: Shard::ALL,
        }
    }
}

impl GridSpec {
    /// The grid over `base`.
    pub fn grid(&self, base: &Case) -> Grid {
        Grid::new(
            base.clone(),
            self.speeds_kmh.clone(),
            self.tensions_n.clone(),
            self.dampings.clone(),
        )
        .with_seeds(self.seeds)
    }

    /// Every job of the grid over `base` (checked: an error names the grid point), and those of
    /// this shard.
    pub fn jobs(&self, base: &Case) -> Result<(Vec<Job>, Vec<Job>), CaseError> {
        let all = self.grid(base).jobs()?;
        let mine = all
            .iter()
            .filter(|j| self.shard.contains(j.index))
            .cloned()
            .collect();
        Ok((all, mine))
    }
}

/// An EVA sweep: the grid and the EVA's settings (Δd = 1 m, 0.01 J, 0.99 by default: the
/// paper's criterion and the fraction criterion).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct EvaSweepSpec {
    /// The grid.
    pub grid: GridSpec,
    /// The EVA's settings (the budget in them is the run's).
    pub settings: EvaSettings,
}

impl EvaSweepSpec {
    /// The CLI's flag of each field (for its messages).
    pub const FLAGS: [(&'static str, &'static str); 6] = [
        ("step_m", "--step"),
        ("tolerance_j", "--tol"),
        ("fraction", "--fraction"),
        ("max_window_m", "--max-window"),
        ("snapshot_at_m", "--snapshot-at"),
        ("span_positions", "--span-positions"),
    ];

    /// Check the settings, naming the field.
    pub fn check(&self) -> Result<(), CaseError> {
        let s = &self.settings;
        for (name, v) in [
            ("step_m", s.step_m),
            ("tolerance_j", s.tolerance_j),
            ("max_window_m", s.max_window_m.unwrap_or(1.0)),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return Err(bad(name, v, "must be a finite number > 0"));
            }
        }
        if !(s.fraction > 0.0 && s.fraction < 1.0) {
            return Err(bad("fraction", s.fraction, "must lie in (0, 1)"));
        }
        if let Some(x) = s.snapshot_at_m.filter(|x| !x.is_finite()) {
            return Err(bad("snapshot_at_m", x, "must be a finite position, m"));
        }
        if s.span_positions > MAX_SPAN_POSITIONS {
            return Err(bad(
                "span_positions",
                s.span_positions,
                &format!("at most {MAX_SPAN_POSITIONS} positions across a span (each one a snapshot of the energy)"),
            ));
        }
        Ok(())
    }

    /// The sweep's fingerprint over `base`: its case, grid and settings, the number of shards and
    /// the version (what `eva merge` checks: shards of one sweep only).
    pub fn fingerprint(&self, base: &Case) -> String {
        let (g, s) = (&self.grid, &self.settings);
        let grid = g.grid(base);
        let mut desc = base.to_toml_string();
        let _ = write!(
            desc,
            "\n[sweep]\nspeeds = {:?}\ntensions = {:?}\ndampings = {:?}\nstep = {}\ntol = {}\nfraction = {}\nmax_window = {:?}\nsnapshot_at = {:?}\nspan_positions = {}\npoints_per_mode = {}\nsample_every = {}\nshards = {}\nseeds = {}\nversion = {}\n",
            grid.speeds_kmh,
            grid.tensions_n,
            grid.dampings.iter().map(damping_label).collect::<Vec<_>>(),
            s.step_m,
            s.tolerance_j,
            s.fraction,
            s.max_window_m,
            s.snapshot_at_m,
            s.span_positions,
            s.points_per_mode,
            s.sample_every_s,
            g.shard.count,
            g.seeds,
            env!("CARGO_PKG_VERSION")
        );
        fnv1a64_hex(desc.as_bytes())
    }

    /// Run this shard's jobs `mine` (from [`GridSpec::jobs`]) within `budget` on `threads`
    /// workers; `done` after each case.
    pub fn run(
        &self,
        mine: &[Job],
        budget: &Budget,
        threads: Option<usize>,
        done: &(dyn Fn() + Sync),
    ) -> Result<Vec<EvaCase>, SimError> {
        self.check()?;
        let settings = EvaSettings {
            budget: *budget,
            ..self.settings.clone()
        };
        eva_sweep(mine, &settings, budget, threads, done)
    }
}

/// A window sweep: the grid (of the one-pantograph case, [`crate::compile::window_case`]), the
/// tolerances (mean 1 %, σ 3 %, maximum 5 %) and the search (from half a span to 400 m, coarse
/// 20 m, resolution 1 m, the fine search by default).
#[derive(Debug, Clone, PartialEq)]
pub struct WindowSweepSpec {
    /// The grid.
    pub grid: GridSpec,
    /// The tolerances of the windows against the full model, %.
    pub tolerances: Tolerances,
    /// The shortest window searched, m (`None`: half the case's span).
    pub min_window_m: Option<f64>,
    /// The longest window searched, m.
    pub max_window_m: f64,
    /// The coarse scan's step (with `coarse_only`), m.
    pub coarse_m: f64,
    /// The resolution of the search, m.
    pub resolution_m: f64,
    /// The quick lattice answer instead of the fine search.
    pub coarse_only: bool,
}

impl Default for WindowSweepSpec {
    fn default() -> Self {
        WindowSweepSpec {
            grid: GridSpec::default(),
            tolerances: Tolerances::default(),
            min_window_m: None,
            max_window_m: 400.0,
            coarse_m: 20.0,
            resolution_m: 1.0,
            coarse_only: false,
        }
    }
}

impl WindowSweepSpec {
    /// The CLI's flag of each field (for its messages).
    pub const FLAGS: [(&'static str, &'static str); 7] = [
        ("mean_tol_pct", "--mean-tol"),
        ("sigma_tol_pct", "--sigma-tol"),
        ("max_tol_pct", "--max-tol"),
        ("min_window_m", "--min-window"),
        ("max_window_m", "--max-window"),
        ("coarse_m", "--coarse"),
        ("resolution_m", "--resolution"),
    ];

    /// The one-pantograph case the windows are measured on (the pantograph the window follows).
    pub fn single(base: &Case) -> Result<Case, CaseError> {
        crate::compile::window_case(base)
    }

    /// The search over `base`'s model.
    pub fn search(&self, base: &Case) -> SearchSettings {
        SearchSettings {
            min_m: self.min_window_m.unwrap_or(0.5 * base.catenary.span_m),
            max_m: self.max_window_m,
            coarse_m: self.coarse_m,
            resolution_m: self.resolution_m,
            full_scan: !self.coarse_only,
        }
    }

    /// Check the tolerances and the search against `base`, naming the field.
    pub fn check(&self, base: &Case) -> Result<(), CaseError> {
        self.tolerances.check()?;
        Self::single(base)?;
        self.search(base).check_for(base.length_m())
    }

    /// The sweep's fingerprint over `base` (what `window merge` checks), after [`Self::check`]
    /// (which refuses a window pantograph the case does not have).
    pub fn fingerprint(&self, base: &Case) -> Result<String, CaseError> {
        let single = Self::single(base)?;
        let grid = self.grid.grid(&single);
        let mut desc = single.to_toml_string();
        let _ = write!(
            desc,
            "\n[window]\nspeeds = {:?}\ntensions = {:?}\ntol = {:?}\nsearch = {:?}\nseeds = {}\nshards = {}\nversion = {}\n",
            grid.speeds_kmh,
            grid.tensions_n,
            self.tolerances,
            self.search(base),
            self.grid.seeds,
            self.grid.shard.count,
            env!("CARGO_PKG_VERSION")
        );
        Ok(fnv1a64_hex(desc.as_bytes()))
    }

    /// Every job and this shard's, over the one-pantograph case of `base`.
    pub fn jobs(&self, base: &Case) -> Result<(Vec<Job>, Vec<Job>), CaseError> {
        self.grid.jobs(&Self::single(base)?)
    }

    /// Run this shard's jobs `mine` ([`WindowSweepSpec::jobs`]) over `base`.
    pub fn run(
        &self,
        base: &Case,
        mine: &[Job],
        budget: &Budget,
        threads: Option<usize>,
        done: &(dyn Fn() + Sync),
    ) -> Result<Vec<WindowCase>, SimError> {
        self.check(base)?;
        window_sweep(
            mine,
            &self.search(base),
            &self.tolerances,
            budget,
            threads,
            done,
        )
    }
}

/// A Monte Carlo study of one case: its realisations and the error-level events its user accepts.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct MonteCarloSpec {
    /// The number of realisations (seed offsets 0..n).
    pub realisations: usize,
    /// The error-level events accepted (a realisation's otherwise refuses the study).
    pub allowed: AllowedErrors,
}

impl MonteCarloSpec {
    /// Check the number of realisations against `case` (at least 1, at most 100 000, and only
    /// for a case with a seeded random input), naming the field.
    pub fn check(&self, case: &Case) -> Result<usize, CaseError> {
        crate::analysis::sweep::check_seeds(Some(self.realisations), case)
            .map_err(|e| bad("realisations", self.realisations, &e))
    }
}

/// A front end's resource limits, checked and converted once: `max_steps` (at least 1) and
/// `max_memory_gb` (GiB in (0, 1e6]), each `None` for the default.
pub fn budget_of(max_steps: Option<u64>, max_memory_gb: Option<f64>) -> Result<Budget, CaseError> {
    let mut b = Budget::default();
    if let Some(n) = max_steps {
        if n == 0 {
            return Err(bad("max_steps", 0, "must be at least 1"));
        }
        b.max_steps = n;
    }
    if let Some(g) = max_memory_gb {
        if !(g.is_finite() && g > 0.0 && g <= 1e6) {
            return Err(bad(
                "max_memory_gb",
                g,
                "must be a number of GiB in (0, 1e6]",
            ));
        }
        b.max_memory_bytes = (g * (1u64 << 30) as f64) as u64;
    }
    Ok(b)
}

/// A spec's field as its CLI flag in an error (`step_m` → `--step`), by `flags`.
pub fn with_flags(e: CaseError, flags: &[(&str, &str)]) -> CaseError {
    match e {
        CaseError::Invalid {
            field,
            value,
            reason,
        } => CaseError::Invalid {
            field: flags
                .iter()
                .find(|(f, _)| *f == field)
                .map_or(field, |(_, flag)| flag.to_string()),
            value,
            reason,
        },
        other => other,
    }
}
