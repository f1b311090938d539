//! How long must the real-time window be? (issue 13; the paper's question, answered by accuracy.)
//!
//! For a case, the accuracy-based length is the shortest window whose SIL run matches the full
//! model within stated tolerances on the mean, σ and actual maximum of the 0–20 Hz contact force,
//! such that every longer window checked up to a stated maximum matches too. The search
//! ([`search`]) evaluates a coarse lattice from the longest window down to the first failure,
//! then the fine lattice downward from the shortest passing coarse window until the first
//! failure. Its claim is stated with its lattice ([`SearchResult::fine_checked_to_m`]): every
//! window at the resolution from the length found up to the lowest passing coarse window, and
//! the coarse windows above; windows between coarse points above that were not run, and an
//! error curve that is not monotone can fail there (issue 20: 167 m failed σ above a 150 m
//! answer). With [`SearchSettings::full_scan`] every window of the fine lattice from the longest
//! down to the first failure is run, and the claim holds for every window at the resolution.
//! Both are monotone in the tolerances: a tighter tolerance passes a subset of the windows, so
//! it never gives a shorter one.
//!
//! Beside it, the energy-based lengths (Eq. 21 criteria, `analysis::eva`), and the criterion
//! that, fitted once over a grid of cases, predicts the accuracy-based lengths best
//! ([`fit_criteria`]).

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

use crate::analysis::eva::{eva_by_fraction, eva_by_step, EvaOutput};
use crate::analysis::record::RunOutput;
use crate::analysis::stats::ContactStats;
use crate::error::{CaseError, SimError};
use crate::input::case::Case;
use crate::study::realtime::run_window_sil;

/// Tolerances on the window's 0–20 Hz force statistics against the full model's, %.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct Tolerances {
    /// Tolerance on the mean force, %.
    pub mean_pct: f64,
    /// Tolerance on the standard deviation σ, %.
    pub sigma_pct: f64,
    /// Tolerance on the statistical maximum, %.
    pub max_pct: f64,
}

impl Default for Tolerances {
    fn default() -> Self {
        Tolerances {
            mean_pct: 1.0,
            sigma_pct: 3.0,
            max_pct: 5.0,
        }
    }
}

/// A window's relative errors against the full model, % (signed).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct WindowErrors {
    /// Window length, m.
    pub window_m: f64,
    /// Error of the mean force, %.
    pub mean_pct: f64,
    /// Error of σ, %.
    pub sigma_pct: f64,
    /// Error of the statistical maximum, %.
    pub max_pct: f64,
}

impl WindowErrors {
    /// The errors of `window` against `full`.
    pub fn of(window_m: f64, window: &ContactStats, full: &ContactStats) -> Self {
        let rel = |a: f64, b: f64| 100.0 * (a - b) / b.abs().max(1e-12);
        WindowErrors {
            window_m,
            mean_pct: rel(window.mean_n, full.mean_n),
            sigma_pct: rel(window.std_n, full.std_n),
            max_pct: rel(window.actual_max_n, full.actual_max_n),
        }
    }

    /// A window that never crossed the analysis section fails everything.
    pub fn failed(window_m: f64) -> Self {
        WindowErrors {
            window_m,
            mean_pct: f64::INFINITY,
            sigma_pct: f64::INFINITY,
            max_pct: f64::INFINITY,
        }
    }

    /// Within every tolerance.
    pub fn passes(&self, t: &Tolerances) -> bool {
        self.mean_pct.abs() <= t.mean_pct
            && self.sigma_pct.abs() <= t.sigma_pct
            && self.max_pct.abs() <= t.max_pct
    }
}

/// The lattice of the search: windows `min + k · resolution` up to `max`, the coarse ones every
/// `coarse` metres.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct SearchSettings {
    /// Shortest window searched, m.
    pub min_m: f64,
    /// Longest window searched, m.
    pub max_m: f64,
    /// Spacing of the coarse scan, m.
    pub coarse_m: f64,
    /// Resolution of the search (the lattice spacing), m.
    pub resolution_m: f64,
    /// Run every window of the fine lattice from the longest down to the first failure (the
    /// claim then holds at the resolution over the whole range), instead of the coarse scan and
    /// refinement.
    pub full_scan: bool,
}

impl Tolerances {
    /// Check the tolerances, naming the flag: each a percentage in (0, 1000).
    pub fn check(&self) -> Result<(), CaseError> {
        for (flag, v) in [
            ("mean_tol_pct", self.mean_pct),
            ("sigma_tol_pct", self.sigma_pct),
            ("max_tol_pct", self.max_pct),
        ] {
            if !(v.is_finite() && v > 0.0 && v < 1000.0) {
                return Err(CaseError::Invalid {
                    field: flag.into(),
                    value: v.to_string(),
                    reason: "must be a percentage in (0, 1000)".into(),
                });
            }
        }
        Ok(())
    }
}

impl SearchSettings {
    /// [`Self::check`], and the longest window shorter than the model of `model_length_m`.
    pub fn check_for(&self, model_length_m: f64) -> Result<(), CaseError> {
        self.check()?;
        if self.max_m >= model_length_m {
            return Err(CaseError::Invalid {
                field: "max_window_m".into(),
                value: format!("{} m", self.max_m),
                reason: format!("must be shorter than the model ({model_length_m} m)"),
            });
        }
        Ok(())
    }

    /// Check the settings, naming the flag.
    pub fn check(&self) -> Result<(), CaseError> {
        let bad = |field: &str, v: f64, r: &str| CaseError::Invalid {
            field: field.into(),
            value: v.to_string(),
            reason: r.into(),
        };
        if !(self.resolution_m.is_finite() && self.resolution_m > 0.0) {
            return Err(bad("resolution_m", self.resolution_m, "must be > 0"));
        }
        if !(self.coarse_m.is_finite() && self.coarse_m >= self.resolution_m) {
            return Err(bad(
                "coarse_m",
                self.coarse_m,
                "must be at least the resolution",
            ));
        }
        if !(self.min_m.is_finite() && self.min_m > 0.0) {
            return Err(bad("min_window_m", self.min_m, "must be > 0"));
        }
        if !(self.max_m.is_finite() && self.max_m > self.min_m) {
            return Err(bad("max_window_m", self.max_m, "must exceed min_window_m"));
        }
        if (self.max_m - self.min_m) / self.resolution_m > 1e5 {
            return Err(bad(
                "resolution_m",
                self.resolution_m,
                "more than 100 000 lattice points between min_window_m and max_window_m",
            ));
        }
        Ok(())
    }

    fn lattice(&self) -> (usize, usize) {
        let k_max = ((self.max_m - self.min_m) / self.resolution_m + 1e-9).floor() as usize;
        let step = ((self.coarse_m / self.resolution_m).round() as usize).max(1);
        (k_max, step)
    }

    fn at(&self, k: usize) -> f64 {
        self.min_m + k as f64 * self.resolution_m
    }
}

/// The result of a search.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SearchResult {
    /// The accuracy-based length (`None`: even the longest window fails).
    pub length_m: Option<f64>,
    /// Every window evaluated, by length.
    pub evaluated: Vec<WindowErrors>,
    /// The claim's lattice: every window at the resolution from `length_m` up to this length was
    /// run and matches (above it, only the coarse windows were run, up to the longest). The
    /// longest window for a full scan; `None` when no length was found.
    pub fine_checked_to_m: Option<f64>,
}

/// Find the shortest window of the lattice within `tol` such that every longer evaluated window
/// passes too (see the module). `eval(L)` gives the errors of window `L`.
pub fn search<E>(
    s: &SearchSettings,
    tol: &Tolerances,
    mut eval: impl FnMut(f64) -> Result<WindowErrors, E>,
) -> Result<SearchResult, E> {
    let (k_max, step) = s.lattice();
    let mut memo: BTreeMap<usize, WindowErrors> = BTreeMap::new();
    let mut get = |k: usize, memo: &mut BTreeMap<usize, WindowErrors>| -> Result<bool, E> {
        if let Some(e) = memo.get(&k) {
            return Ok(e.passes(tol));
        }
        let e = eval(s.at(k))?;
        memo.insert(k, e);
        Ok(e.passes(tol))
    };
    if s.full_scan {
        // Every window at the resolution from the top down to the first failure.
        let mut best = None;
        for k in (0..=k_max).rev() {
            if !get(k, &mut memo)? {
                break;
            }
            best = Some(k);
        }
        return Ok(SearchResult {
            length_m: best.map(|k| s.at(k)),
            evaluated: memo.into_values().collect(),
            fine_checked_to_m: best.map(|_| s.at(k_max)),
        });
    }
    // Coarse lattice from the top (always including the longest window).
    let mut coarse: Vec<usize> = (0..=k_max).step_by(step).collect();
    if coarse.last() != Some(&k_max) {
        coarse.push(k_max);
    }
    let mut lowest_pass = None;
    let mut fail_below = None;
    for &k in coarse.iter().rev() {
        if get(k, &mut memo)? {
            lowest_pass = Some(k);
        } else {
            fail_below = Some(k);
            break;
        }
    }
    let length = match (lowest_pass, fail_below) {
        (None, _) => None,
        (Some(k), None) => Some(k),
        (Some(k), Some(f)) => {
            // Refine downward from the lowest passing coarse window.
            let mut best = k;
            let mut j = k;
            while j > f + 1 {
                j -= 1;
                if get(j, &mut memo)? {
                    best = j;
                } else {
                    break;
                }
            }
            Some(best)
        }
    };
    Ok(SearchResult {
        length_m: length.map(|k| s.at(k)),
        evaluated: memo.into_values().collect(),
        fine_checked_to_m: lowest_pass.filter(|_| length.is_some()).map(|k| s.at(k)),
    })
}

impl SearchResult {
    /// The claim in words ([`claim`]).
    pub fn claim(&self, s: &SearchSettings) -> String {
        claim(self.length_m, self.fine_checked_to_m, s)
    }
}

/// What a search's answer claims, in words: which windows above the length found were run and
/// match (`fine_checked_to_m` as in [`SearchResult`]).
pub fn claim(length_m: Option<f64>, fine_checked_to_m: Option<f64>, s: &SearchSettings) -> String {
    match (length_m, fine_checked_to_m) {
        (Some(l), Some(to)) if s.full_scan || to >= s.max_m - 1e-9 => format!(
            "every window from {l} m to {} m, every {} m, was run and matches",
            s.max_m, s.resolution_m
        ),
        (Some(l), Some(to)) => {
            let fine = if to - l < 0.5 * s.resolution_m {
                format!("the {l} m window")
            } else {
                format!(
                    "every window from {l} m to {to} m (every {} m)",
                    s.resolution_m
                )
            };
            format!(
                "{fine} and every {} m from there to {} m were run and match; the windows between those coarse points were not run (--coarse-only: without it every one is run)",
                s.coarse_m, s.max_m
            )
        }
        _ => format!("even the longest window ({} m) does not match", s.max_m),
    }
}

/// The leading pantograph's statistics of the full model's run `full` of the one-pantograph
/// case `single` ([`crate::compile::window_case`]): what the windows are measured against.
pub fn full_stats(single: &Case, full: &RunOutput) -> Result<ContactStats, SimError> {
    full.pantographs[0].stats.ok_or_else(|| {
        SimError::Case(CaseError::Invalid {
            field: "run.analysis_m".into(),
            value: format!("{:?}", single.run.analysis_m),
            reason: "the full model's pantograph never crossed the analysis section".into(),
        })
    })
}

/// The accuracy-based length of one case ([`search`]) against the full model's statistics `fs`
/// ([`full_stats`]): SIL windows of the one-pantograph case `single`, as the search asks
/// ([`crate::study::sweeps::window_sweep`] runs the full model once for both).
pub fn search_windows(
    single: &Case,
    fs: &ContactStats,
    s: &SearchSettings,
    tol: &Tolerances,
) -> Result<SearchResult, SimError> {
    search(s, tol, |w| {
        let run = run_window_sil(single, w)?;
        Ok::<_, SimError>(match run.stats {
            Some(ws) => WindowErrors::of(w, &ws, fs),
            None => WindowErrors::failed(w),
        })
    })
}

/// An energy criterion (Eq. 21 family) that predicts a window length from a case's window
/// energies.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Criterion {
    /// Which energy: `snapshot`, `max` (over the passage) or `mean` (time average).
    pub view: &'static str,
    /// `step` (the paper's: the first Δd whose energy gain is below `value` J) or `fraction`
    /// (the smallest window holding `value` of the total).
    pub kind: &'static str,
    /// The criterion's value: an energy gain, J (`step`), or a share of the total (`fraction`).
    pub value: f64,
}

impl Criterion {
    /// The family fitted by [`fit_criteria`].
    pub fn family() -> Vec<Criterion> {
        let mut v = Vec::new();
        for view in ["snapshot", "max", "mean"] {
            for f in [0.9, 0.95, 0.98, 0.99, 0.995, 0.999] {
                v.push(Criterion {
                    view,
                    kind: "fraction",
                    value: f,
                });
            }
            for t in [0.001, 0.003, 0.01, 0.03, 0.1, 0.3, 1.0] {
                v.push(Criterion {
                    view,
                    kind: "step",
                    value: t,
                });
            }
        }
        v
    }

    /// The length this criterion gives on a case's energy curves, m.
    pub fn predict(&self, c: &EnergyCurves) -> Option<f64> {
        let (e, total) = match self.view {
            "snapshot" => (&c.snapshot_j, c.snapshot_total_j),
            "max" => (&c.max_j, c.max_total_j),
            _ => (&c.mean_j, c.mean_total_j),
        };
        match self.kind {
            "fraction" => eva_by_fraction(&c.window_m, e, total, self.value),
            _ => eva_by_step(&c.window_m, e, self.value),
        }
    }

    /// A label, e.g. `max/fraction 0.99`.
    pub fn label(&self) -> String {
        match self.kind {
            "fraction" => format!("{}/fraction {}", self.view, self.value),
            _ => format!("{}/step {} J", self.view, self.value),
        }
    }
}

/// A case's window energies E(d) (Eq. 21) in the three views, and their totals: what the
/// criteria read (kept in files by `pcsim window`, so that a merge can fit them again).
#[derive(Debug, Clone, PartialEq)]
pub struct EnergyCurves {
    /// Window lengths d, m.
    pub window_m: Vec<f64>,
    /// Window energies of the snapshot, J.
    pub snapshot_j: Vec<f64>,
    /// Window energies of the maximum over the passage, J.
    pub max_j: Vec<f64>,
    /// Window energies of the time average, J.
    pub mean_j: Vec<f64>,
    /// Total energy of the snapshot, J.
    pub snapshot_total_j: f64,
    /// Total energy of the maximum view, J.
    pub max_total_j: f64,
    /// Total energy of the time-average view, J.
    pub mean_total_j: f64,
}

impl EnergyCurves {
    /// The curves of an EVA run.
    pub fn of(eva: &EvaOutput) -> Self {
        EnergyCurves {
            window_m: eva.window_m.clone(),
            snapshot_j: eva.snapshot.window_j.clone(),
            max_j: eva.max.window_j.clone(),
            mean_j: eva.mean.window_j.clone(),
            snapshot_total_j: eva.snapshot.total_j,
            max_total_j: eva.max.total_j,
            mean_total_j: eva.mean.total_j,
        }
    }
}

/// A criterion's fit over a grid: its RMS and largest error against the accuracy-based lengths
/// (cases where either is missing are counted as misses).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CriterionFit {
    /// The criterion, as `view/kind=value`.
    pub criterion: String,
    /// RMS error against the accuracy-based lengths, m.
    pub rms_error_m: f64,
    /// Largest error, m.
    pub max_error_m: f64,
    /// Cases fitted.
    pub cases: usize,
    /// Cases where either length is missing.
    pub misses: usize,
}

/// Fit every criterion of [`Criterion::family`] over the cases (accuracy length, energies): the
/// fits sorted best first (fewest misses, then smallest RMS error).
pub fn fit_criteria(cases: &[(Option<f64>, &EnergyCurves)]) -> Vec<CriterionFit> {
    let mut fits: Vec<CriterionFit> = Criterion::family()
        .into_iter()
        .map(|c| {
            let (mut s2, mut mx, mut n, mut miss) = (0.0, 0.0f64, 0, 0);
            for (acc, eva) in cases {
                match (acc, c.predict(eva)) {
                    (Some(a), Some(p)) => {
                        s2 += (p - a) * (p - a);
                        mx = mx.max((p - a).abs());
                        n += 1;
                    }
                    _ => miss += 1,
                }
            }
            CriterionFit {
                criterion: c.label(),
                rms_error_m: if n > 0 {
                    (s2 / n as f64).sqrt()
                } else {
                    f64::INFINITY
                },
                max_error_m: if n > 0 { mx } else { f64::INFINITY },
                cases: n,
                misses: miss,
            }
        })
        .collect();
    fits.sort_by(|a, b| {
        a.misses
            .cmp(&b.misses)
            .then(a.rms_error_m.total_cmp(&b.rms_error_m))
    });
    fits
}
