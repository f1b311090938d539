//! Dropper fatigue (issue 22, item 5): every dropper's tension through a run, its rainflow cycles
//! (ASTM E1049-85 §5.4.4) and its Miner damage from an S–N curve given in the case.
//!
//! # Rainflow counting
//! [`reversals`] keeps the points where the slope changes sign (plateaus collapse to their
//! first point; the first and the last points count), and [`rainflow`] counts them by the
//! standard's rainflow procedure: with `X` the most recent range and `Y` the one before it, while
//! `X ≥ Y`, `Y` is a full cycle (its two points are discarded), or half a cycle when it contains
//! the starting point (which is discarded); the ranges left at the end are half cycles. This is
//! the standard's own three-point statement; the four-point method closes the same loops but
//! counts the residue differently where reversals tie, and the golden (the Python `rainflow`
//! package, `scripts/gen_rainflow_golden.py`) follows the standard, which the test matches
//! exactly.
//!
//! # Miner's rule
//! A Basquin S–N curve `N(Δσ) = N_ref (Δσ_ref / Δσ)^m` gives the cycles to failure at a stress
//! range `Δσ = ΔF / A`; the damage is `D = Σ n_i / N(Δσ_i)` (a half cycle counts ½). The curve
//! and the dropper wire's cross-section come from the case (`[dropper_fatigue]`, each with its
//! source): no default is invented.

use crate::error::SimError;
use crate::model::elements::dropper::Droppers;
use crate::model::Attach;
use crate::solve::compiled::CompiledModel;
use crate::solve::run::Observer;
use crate::solve::state::State;
use crate::solve::workspace::Workspace;

/// One rainflow cycle: its range and mean, whether full (1) or half (½), and the indices of its
/// two points in the series.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cycle {
    /// Range `|x₁ − x₂|`.
    pub range: f64,
    /// Mean `(x₁ + x₂)/2`.
    pub mean: f64,
    /// 1 for a full cycle, 0.5 for a half cycle.
    pub count: f64,
    /// Index of its first point in the series.
    pub start: usize,
    /// Index of its second point in the series.
    pub end: usize,
}

impl Cycle {
    fn of((i1, x1): (usize, f64), (i2, x2): (usize, f64), count: f64) -> Self {
        Cycle {
            range: (x1 - x2).abs(),
            mean: 0.5 * (x1 + x2),
            count,
            start: i1,
            end: i2,
        }
    }
}

/// The reversal points of a series, with their indices: where the slope changes sign (a plateau
/// counts once, at its last point), and the first and the last points. (A series of two points
/// gives both; the Python package, the golden's tool, gives only the first.)
pub fn reversals(series: &[f64]) -> Vec<(usize, f64)> {
    let mut out = Vec::new();
    let mut r = Reversals::default();
    for (i, &x) in series.iter().enumerate() {
        r.push(i, x, &mut out);
    }
    r.finish(&mut out);
    out
}

/// [`reversals`] point by point: a recorder keeps only the reversals of a long record.
#[derive(Debug, Clone, Default)]
pub struct Reversals {
    /// The last point of the current value (a plateau's last), and the slope into it.
    last: Option<(usize, f64)>,
    slope: f64,
    /// The most recent point (the series' last, for `finish`).
    newest: Option<(usize, f64)>,
}

impl Reversals {
    /// Take the point `(i, x)`; a reversal found is appended to `out`.
    pub fn push(&mut self, i: usize, x: f64, out: &mut Vec<(usize, f64)>) {
        match self.last {
            None => {
                out.push((i, x));
                self.last = Some((i, x));
            }
            // A plateau's reversal is its last point.
            Some((_, xl)) if x == xl => self.last = Some((i, xl)),
            Some(prev) => {
                let d = x - prev.1;
                if self.slope * d < 0.0 {
                    out.push(prev);
                }
                self.slope = d;
                self.last = Some((i, x));
            }
        }
        self.newest = Some((i, x));
    }

    /// The last point of the series closes the reversals.
    pub fn finish(&self, out: &mut Vec<(usize, f64)>) {
        if let Some(p) = self.newest {
            if out.last().map(|q| q.0) != Some(p.0) {
                out.push(p);
            }
        }
    }
}

/// Rainflow cycles of a series (ASTM E1049-85 §5.4.4, see the module), in the order the
/// procedure finds them.
pub fn rainflow(series: &[f64]) -> Vec<Cycle> {
    rainflow_of_reversals(&reversals(series))
}

/// [`rainflow`] on reversal points already extracted (with their indices in the series).
pub fn rainflow_of_reversals(rev: &[(usize, f64)]) -> Vec<Cycle> {
    let mut out = Vec::new();
    // A deque as a vector with a moving front.
    let mut pts: Vec<(usize, f64)> = Vec::new();
    let mut front = 0;
    for &p in rev {
        pts.push(p);
        while pts.len() - front >= 3 {
            let n = pts.len();
            let (x1, x2, x3) = (pts[n - 3].1, pts[n - 2].1, pts[n - 1].1);
            let (x, y) = ((x3 - x2).abs(), (x2 - x1).abs());
            if x < y {
                break;
            } else if n - front == 3 {
                out.push(Cycle::of(pts[front], pts[front + 1], 0.5));
                front += 1;
            } else {
                out.push(Cycle::of(pts[n - 3], pts[n - 2], 1.0));
                let last = pts[n - 1];
                pts.truncate(n - 3);
                pts.push(last);
            }
        }
    }
    while pts.len() - front > 1 {
        out.push(Cycle::of(pts[front], pts[front + 1], 0.5));
        front += 1;
    }
    out
}

/// A Basquin S–N curve in stress range: `N(Δσ) = cycles_ref (Δσ_ref / Δσ)^m`, and the wire's
/// cross-section that turns a force range into a stress range.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SnCurve {
    /// The slope `m` (inverse Basquin exponent).
    pub m: f64,
    /// The reference stress range `Δσ_ref`, Pa.
    pub stress_range_pa: f64,
    /// Cycles to failure at the reference stress range.
    pub cycles: f64,
    /// The dropper wire's cross-section, m².
    pub area_m2: f64,
}

impl From<&crate::input::case::DropperFatigueCase> for SnCurve {
    /// The case's curve (`[dropper_fatigue]`, mm² and MPa) in SI units.
    fn from(f: &crate::input::case::DropperFatigueCase) -> Self {
        SnCurve {
            m: f.sn_slope,
            stress_range_pa: f.sn_stress_range_mpa * 1e6,
            cycles: f.sn_cycles,
            area_m2: f.area_mm2 * 1e-6,
        }
    }
}

impl SnCurve {
    /// Cycles to failure at a force range `ΔF` (N): `N(ΔF / A)`; infinite at zero range.
    pub fn cycles_to_failure(&self, force_range_n: f64) -> f64 {
        let s = force_range_n / self.area_m2;
        if s <= 0.0 {
            f64::INFINITY
        } else {
            self.cycles * (self.stress_range_pa / s).powf(self.m)
        }
    }

    /// Miner's damage of force cycles: `Σ count / N(range)`.
    pub fn damage(&self, cycles: &[Cycle]) -> f64 {
        cycles
            .iter()
            .map(|c| c.count / self.cycles_to_failure(c.range))
            .sum()
    }
}

/// One dropper's tension through a run.
#[derive(Debug, Clone, PartialEq)]
pub struct DropperFatigue {
    /// Position along the track, m.
    pub x_m: f64,
    /// The wire its lower end holds (a line's tension length), by name.
    pub wire: String,
    /// Its static tension, N: the preload of the design, or under steady loads (ice, a mean
    /// wind) its tension in the loaded static start.
    pub preload_n: f64,
    /// Smallest and largest tension, N.
    pub min_n: f64,
    /// Largest tension, N.
    pub max_n: f64,
    /// Steps it was slack.
    pub slack_steps: usize,
    /// Its rainflow cycles (full and half), by count.
    pub cycles: f64,
    /// Its largest cycle's range, N.
    pub max_range_n: f64,
    /// Miner's damage of this run (one passage), when the case gives an S–N curve.
    pub damage: Option<f64>,
}

/// An observer that follows every dropper's tension: its reversals (for the rainflow count),
/// its extremes and slack steps, and, when asked and within `max_values`, the whole history.
#[derive(Debug, Clone)]
pub struct DropperRecorder {
    tension: Vec<f64>,
    rev: Vec<Reversals>,
    points: Vec<Vec<(usize, f64)>>,
    min: Vec<f64>,
    max: Vec<f64>,
    slack: Vec<usize>,
    step: usize,
    /// The histories, step after step (all droppers per step), when kept.
    history: Option<Vec<f64>>,
    /// The tensions in the start state, when it is not the design's (steady loads).
    static_n: Option<Vec<f64>>,
}

impl DropperRecorder {
    /// A recorder for the droppers of `cm` over `n_steps`; the histories are kept when
    /// `keep_history` and they hold at most `max_values` numbers (else only the cycles and the
    /// extremes: [`Self::history`] says which).
    pub fn new(cm: &CompiledModel, n_steps: usize, keep_history: bool, max_values: usize) -> Self {
        let n = cm.element::<Droppers>().map_or(0, |(d, _)| d.list().len());
        let history = (keep_history && n.saturating_mul(n_steps) <= max_values)
            .then(|| Vec::with_capacity(n * n_steps));
        DropperRecorder {
            tension: vec![0.0; n],
            rev: vec![Reversals::default(); n],
            points: vec![Vec::new(); n],
            min: vec![f64::INFINITY; n],
            max: vec![f64::NEG_INFINITY; n],
            slack: vec![0; n],
            step: 0,
            history,
            static_n: None,
        }
    }

    /// Take each dropper's static tension from the start state `ws` was gathered at
    /// ([`crate::solve::Integrator::gathered_at`]): under steady loads (the ice's weight, a mean
    /// wind) the start is not the design's, and the droppers carry more than their preload.
    pub fn static_from(&mut self, cm: &CompiledModel, ws: &Workspace) {
        if let Some((droppers, slots)) = cm.element::<Droppers>() {
            let mut t = vec![0.0; droppers.list().len()];
            droppers.tensions(slots, cm.displacements(ws), &mut t);
            self.static_n = Some(t);
        }
    }

    /// The tension histories (step after step, every dropper per step), if they were kept.
    pub fn history(&self) -> Option<&[f64]> {
        self.history.as_deref()
    }

    /// The histories, taken out.
    pub fn into_history(self) -> Option<Vec<f64>> {
        self.history
    }

    /// Every dropper's extremes, cycles and (with `curve`) damage.
    pub fn finish(&self, cm: &CompiledModel, curve: Option<&SnCurve>) -> Vec<DropperFatigue> {
        let Some((droppers, _)) = cm.element::<Droppers>() else {
            return Vec::new();
        };
        let m = cm.model();
        droppers
            .list()
            .iter()
            .enumerate()
            .map(|(i, d)| {
                let mut pts = self.points[i].clone();
                self.rev[i].finish(&mut pts);
                let cycles = rainflow_of_reversals(&pts);
                let wire = match d.bottom {
                    Attach::Wire { wire, .. } => m.wires[wire].name.clone(),
                    _ => String::new(),
                };
                DropperFatigue {
                    x_m: d.x_m,
                    wire,
                    preload_n: self.static_n.as_ref().map_or(d.preload_n, |t| t[i]),
                    min_n: self.min[i],
                    max_n: self.max[i],
                    slack_steps: self.slack[i],
                    cycles: cycles.iter().map(|c| c.count).sum(),
                    max_range_n: cycles.iter().map(|c| c.range).fold(0.0, f64::max),
                    damage: curve.map(|c| c.damage(&cycles)),
                }
            })
            .collect()
    }
}

impl Observer for DropperRecorder {
    fn observe(
        &mut self,
        cm: &CompiledModel,
        _st: &mut State,
        ws: &Workspace,
    ) -> Result<(), SimError> {
        let Some((droppers, slots)) = cm.element::<Droppers>() else {
            return Ok(());
        };
        droppers.tensions(slots, cm.displacements(ws), &mut self.tension);
        for (i, &t) in self.tension.iter().enumerate() {
            self.rev[i].push(self.step, t, &mut self.points[i]);
            self.min[i] = self.min[i].min(t);
            self.max[i] = self.max[i].max(t);
            self.slack[i] += (t == 0.0) as usize;
        }
        if let Some(h) = &mut self.history {
            h.extend_from_slice(&self.tension);
        }
        self.step += 1;
        Ok(())
    }
}
