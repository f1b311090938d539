//! A run with the EN 50318 recorder: the observer that records what each pantograph sees, and
//! [`simulate`], which runs a set-up through the one run loop and takes the statistics.

use crate::analysis::filter::lowpass_zero_phase;
use crate::analysis::stats::{
    contact_stats, hard_spot_stats, lateral_stats, ContactStats, HardSpotStats, LateralStats,
    OverlapStats, CUTOFF_HZ,
};
use crate::compile::Setup;
use crate::error::SimError;
use crate::input::case::Case;
use crate::model::irregularity::IrregularityReport;
use crate::model::wind::WindReport;
use crate::model::Direction;
use crate::solve::run::{run, Observer, RunStatistics};
use crate::solve::{CompiledModel, Integrator, State, Workspace};

/// Time histories of one pantograph.
#[derive(Debug, Clone, PartialEq)]
pub struct PantographTrace {
    /// The pantograph's name (from the case).
    pub name: String,
    /// Position along the track, m.
    pub position_m: Vec<f64>,
    /// Raw contact force, N.
    pub force_n: Vec<f64>,
    /// Contact force low-pass filtered at 20 Hz with zero phase, N.
    pub force_filtered_n: Vec<f64>,
    /// Contact-wire height at the contact point, m.
    pub wire_height_m: Vec<f64>,
    /// See [`ContactStats::max_uplift_at_support_mm`], m.
    pub max_uplift_at_support_m: f64,
    /// EN 50318 statistics over the analysis section (`None` when the pantograph never crossed it).
    pub stats: Option<ContactStats>,
    /// Lateral position of the contact point from the track's centre line, m (empty when
    /// lateral motion is not modelled).
    pub lateral_m: Vec<f64>,
    /// Rotation of the contact wire at the contact point, rad (empty when torsion is not
    /// modelled): the twist that 3D checks observe (issue 20, item 7).
    pub twist_rad: Vec<f64>,
    /// Half-length of the head, m (when given).
    pub head_half_width_m: Option<f64>,
    /// The contact point across the head over the analysis section (lateral motion modelled).
    pub lateral: Option<LateralStats>,
    /// Per contact wire when there is more than one (a line's tension lengths): its name and
    /// the raw force on it, N (empty otherwise).
    pub wire_forces: Vec<(String, Vec<f64>)>,
    /// The passage through each overlap of a line, in track order (those passed).
    pub overlaps: Vec<OverlapStats>,
    /// The passage over each hard spot of a line (issue 55; those passed).
    pub hard_spots: Vec<HardSpotStats>,
    /// Per collector strip (issue 43; empty for a head without strips): its place on the head
    /// and its own contact force with its statistics (the pantograph's are the sum's).
    pub strips: Vec<StripTrace>,
    /// The contact gap, m: how far the nearest contact wire is above the running face under it
    /// (minus the penetration while in contact; 0 for a prescribed force), by step. What an arc
    /// at a loss of contact burns across (issue 54).
    pub gap_m: Vec<f64>,
}

/// One collector strip's contact through a run.
#[derive(Debug, Clone, PartialEq)]
pub struct StripTrace {
    /// Where its contact point is ahead of the pantograph's position, m.
    pub along_m: f64,
    /// Its raw contact force on every contact wire together, N.
    pub force_n: Vec<f64>,
    /// EN 50318 statistics of its force over the analysis section.
    pub stats: Option<ContactStats>,
}

/// Everything a run produced.
#[derive(Debug, Clone, PartialEq)]
pub struct RunOutput {
    /// Train speed, m/s.
    pub speed_m_s: f64,
    /// Time step, s.
    pub dt_s: f64,
    /// Time of every recorded step, s.
    pub time_s: Vec<f64>,
    /// Analysis section (track coordinates), m.
    pub analysis_m: [f64; 2],
    /// Per pantograph: its time histories and statistics.
    pub pantographs: Vec<PantographTrace>,
    /// Largest number of droppers slack at once.
    pub max_slack_droppers: usize,
    /// Share of steps with at least one slack dropper, %.
    pub steps_with_slack_percent: f64,
    /// Modes per wire and direction.
    pub n_modes: usize,
    /// Threads the run stepped on (`Options::threads`, at most the model's basis groups); the
    /// outputs do not depend on it.
    pub threads: usize,
    /// Counters of what the run loop saw (snapshot-tested on the zoo).
    pub run_statistics: RunStatistics,
    /// The crosswind, if any (seed, spectrum, turbulence intensity achieved).
    pub wind: Option<WindReport>,
    /// The contact-wire irregularity's sources (seeds, RMS achieved).
    pub irregularity: Vec<IrregularityReport>,
    /// The coupled stability limit the time step was checked against.
    pub stability: Option<crate::solve::CoupledLimit>,
    /// The slowest contact wire's wave speed √(T/ρA) ([`crate::model::Wire::wave_speed`]),
    /// m/s (none: the model has no contact wire).
    pub contact_wire_wave_speed_m_s: Option<f64>,
    /// What the uplift at the supports is measured from.
    pub uplift_datum: UpliftDatum,
    /// Every contact wire's wave speed, m/s, in track order (one per tension length of a line).
    pub contact_wire_wave_speeds_m_s: Vec<f64>,
    /// Every dropper's tension through the run, its cycles and damage, when asked for
    /// ([`simulate_with`]).
    pub droppers: Option<DropperRun>,
    /// A curved track's radius, the head's offset, the chord's bow and the registrations'
    /// static (pull-off) forces.
    pub curve: Option<crate::model::lateral::CurveReport>,
}

/// What `max_uplift_at_support_mm` is measured from: the static position of the wires before
/// any pantograph arrives.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize, schemars::JsonSchema,
)]
#[serde(rename_all = "snake_case")]
pub enum UpliftDatum {
    /// The design's static shape (no steady load).
    DesignStaticPosition,
    /// The static position under the steady loads (ice, a mean wind): the wires' equilibrium
    /// below or beside the design ([`crate::solve::equilibrium`]).
    LoadedStaticPosition,
}

/// The droppers' fatigue of a run ([`crate::analysis::fatigue`]).
#[derive(Debug, Clone, PartialEq)]
pub struct DropperRun {
    /// Per dropper, in model order.
    pub droppers: Vec<crate::analysis::fatigue::DropperFatigue>,
    /// The S–N curve the damage was taken from, if the case gives one.
    pub curve: Option<crate::analysis::fatigue::SnCurve>,
    /// Every dropper's tension at every step (step after step, all droppers per step), N, when
    /// asked for and within the limit; `None` otherwise.
    pub history: Option<Vec<f64>>,
    /// The limit on the history's numbers, and whether it was asked for.
    pub history_limit: usize,
}

impl RunOutput {
    /// Simulated time, s.
    pub fn simulated_time_s(&self) -> f64 {
        self.time_s.last().copied().unwrap_or(0.0)
    }
}

/// The EN 50318 recorder: time, and per pantograph its track position, contact force and
/// contact-wire height, and the largest uplift of the contact wire at a registration point while
/// the pantograph passes it inside the analysis section.
#[derive(Debug, Clone)]
pub struct Recorder {
    time: Vec<f64>,
    pos: Vec<Vec<f64>>,
    force: Vec<Vec<f64>>,
    height: Vec<Vec<f64>>,
    lateral: Vec<Vec<f64>>,
    twist: Vec<Vec<f64>>,
    uplift: Vec<f64>,
    /// Each monitor's deviation in the static start state, m (empty: zero, the design's static
    /// shape): uplift is measured from it ([`Recorder::measure_uplift_from`]).
    datum: Vec<f64>,
    /// Largest lateral deflection of the contact wire at the probes inside the section, m.
    blowout: f64,
    /// Whether lateral motion is recorded.
    record_lateral: bool,
    /// Whether the contact wire's twist is recorded (torsion modelled).
    record_twist: bool,
    span_m: Option<f64>,
    /// The line's supports (model coordinates) when the spans do not repeat, m.
    supports_m: Vec<f64>,
    analysis_m: [f64; 2],
    /// Registration points of support number `j` (`round(x / span)`, or the line's `j`-th), by
    /// `j`: one, or one per tension length at an overlap's shared supports.
    support: Vec<Vec<usize>>,
    /// The run's time step, s.
    dt_s: f64,
    /// Per pantograph with several contact wires: the force on each, by step.
    wire_force: Vec<Vec<Vec<f64>>>,
    /// Per pantograph with several contact wires: each wire's contact points (indices into
    /// its `contact_points`, one per collector strip), in the order of their first.
    wire_points: Vec<Vec<Vec<usize>>>,
    /// Per pantograph: each collector strip's force, by step.
    strip_force: Vec<Vec<Vec<f64>>>,
    /// Per pantograph: its passage through each overlap.
    overlaps: Vec<Vec<OverlapStats>>,
    /// Per pantograph with several contact wires: the gap of the nearest idle wire above the
    /// contact point, by step, m (infinite when there is none).
    idle_gap: Vec<Vec<f64>>,
    /// Per pantograph: the contact gap, by step, m.
    gap: Vec<Vec<f64>>,
}

impl Recorder {
    /// A recorder for `n_steps` steps of Δt = `dt_s` of the compiled model `cm` over the analysis
    /// section (track coordinates).
    pub fn new(cm: &CompiledModel, dt_s: f64, n_steps: usize, analysis_m: [f64; 2]) -> Self {
        let np = cm.model().pantographs.len();
        // A line's supports are its own (an overlap's carry two arms): found in its list, not
        // at multiples of a span.
        let line = matches!(cm.model().statics, crate::model::StaticShape::Line(_));
        let span_m = cm.model().span_m.filter(|_| !line);
        let mut support = Vec::new();
        let supports_m = cm.model().supports_m.clone();
        if line {
            // Spans that do not repeat: support `j` is the line's `j`-th.
            for (k, &x) in cm.monitor_positions().iter().enumerate() {
                if let Some(j) = supports_m.iter().position(|&s| (x - s).abs() < 1e-3) {
                    if support.len() <= j {
                        support.resize(j + 1, Vec::new());
                    }
                    support[j].push(k);
                }
            }
        }
        if let Some(span) = span_m {
            for (k, &x) in cm.monitor_positions().iter().enumerate() {
                let j = (x / span).round();
                if j >= 0.0 && (x - j * span).abs() < 1e-6 {
                    let j = j as usize;
                    if support.len() <= j {
                        support.resize(j + 1, Vec::new());
                    }
                    support[j] = vec![k];
                }
            }
        }
        let lateral = cm.model().has(Direction::Lateral);
        let twist = lateral && cm.model().has(Direction::Torsional);
        // A pantograph's contact points by wire (its strips' points on one wire together).
        let wire_points: Vec<Vec<Vec<usize>>> = (0..np)
            .map(|p| {
                let mut groups: Vec<(usize, Vec<usize>)> = Vec::new();
                for (k, &mi) in cm.contact_points(p).iter().enumerate() {
                    let w = cm.moving_wire(mi);
                    match groups.iter_mut().find(|(g, _)| *g == w) {
                        Some((_, ks)) => ks.push(k),
                        None => groups.push((w, vec![k])),
                    }
                }
                if groups.len() < 2 {
                    groups.clear();
                }
                groups.into_iter().map(|(_, ks)| ks).collect()
            })
            .collect();
        let wire_force = (wire_points.iter())
            .map(|g: &Vec<Vec<usize>>| vec![Vec::with_capacity(n_steps); g.len()])
            .collect();
        let strip_force = (cm.model().pantographs.iter())
            .map(|p| vec![Vec::with_capacity(n_steps); p.strips().len()])
            .collect();
        let overlaps = vec![
            cm.model()
                .overlaps_m
                .iter()
                .map(|&s| OverlapStats::new(s))
                .collect::<Vec<_>>();
            np
        ];
        Recorder {
            idle_gap: vec![Vec::new(); np],
            gap: vec![Vec::with_capacity(n_steps); np],
            wire_force,
            wire_points,
            strip_force,
            overlaps,
            time: Vec::with_capacity(n_steps),
            pos: vec![Vec::with_capacity(n_steps); np],
            force: vec![Vec::with_capacity(n_steps); np],
            height: vec![Vec::with_capacity(n_steps); np],
            lateral: vec![Vec::with_capacity(if lateral { n_steps } else { 0 }); np],
            twist: vec![Vec::with_capacity(if twist { n_steps } else { 0 }); np],
            uplift: vec![0.0; np],
            datum: Vec::new(),
            blowout: 0.0,
            dt_s,
            record_lateral: lateral,
            record_twist: twist,
            span_m,
            supports_m,
            analysis_m,
            support,
        }
    }

    /// Measure the uplift at the supports from `datum`, each monitor's deviation in the static
    /// start state ([`Integrator::monitors_at`]): under ice or a mean wind the wires sit below
    /// (or beside) their design position before any pantograph arrives, and the uplift a
    /// pantograph causes is the rise from there.
    pub fn measure_uplift_from(&mut self, datum: Vec<f64>) {
        self.datum = datum;
    }

    /// The uplift at monitor `k` now: its deviation less its static datum, m.
    #[inline]
    fn uplift_at(&self, cm: &CompiledModel, ws: &Workspace, k: usize) -> f64 {
        cm.monitor(ws, k) - self.datum.get(k).copied().unwrap_or(0.0)
    }

    /// Pantograph `p`'s traces and statistics (its strips', its lateral offset on the head, its
    /// overlaps), its records taken out of the recorder.
    fn pantograph_trace(&mut self, cm: &CompiledModel, p: usize) -> PantographTrace {
        let m = cm.model();
        let dt = self.dt_s;
        let fs = 1.0 / dt;
        let filtered = lowpass_zero_phase(&self.force[p], fs, CUTOFF_HZ);
        let mut stats = contact_stats(
            &self.force[p],
            &self.pos[p],
            &self.height[p],
            dt,
            self.analysis_m,
            self.uplift[p],
        );
        let pan = &m.pantographs[p];
        let overlaps = std::mem::take(&mut self.overlaps[p])
            .into_iter()
            .filter_map(|o| o.finish(&self.pos[p], &self.idle_gap[p]))
            .collect();
        let hard_spots = (m.hard_spots.iter())
            .filter_map(|h| {
                let (x, height) = (&self.pos[p], &self.height[p]);
                hard_spot_stats(h.kind, h.section_m, x, &self.force[p], |i| {
                    let xm = x[i] - m.track_origin_m;
                    height[i] - m.static_height(h.wire, Direction::Vertical, xm, m.track_origin_m)
                })
            })
            .collect();
        let lateral = if self.lateral[p].is_empty() {
            None
        } else {
            // On the head: from its centre, which a canted curve moves off the
            // track's centre line.
            let origin = m.track_origin_m;
            let on_head: Vec<f64> = (self.lateral[p].iter().zip(&self.pos[p]))
                .map(|(z, &x)| {
                    z - m
                        .lateral
                        .as_ref()
                        .map_or(0.0, |l| l.head_offset_at(x + origin))
                })
                .collect();
            lateral_stats(
                &on_head,
                &self.pos[p],
                self.analysis_m,
                pan.head_half_width_m,
                pan.working_half_width_m,
            )
        };
        if let (Some(s), Some(l)) = (stats.as_mut(), lateral.as_ref()) {
            s.max_lateral_offset_mm = Some(l.max_lateral_offset_mm);
            s.min_head_margin_mm = l.min_head_margin_mm;
            s.max_contact_wire_blowout_mm = Some(self.blowout * 1e3);
        }
        // Each strip's force and statistics, on the pantograph's positions and heights.
        let strips = (pan.strips().iter())
            .zip(std::mem::take(&mut self.strip_force[p]))
            .map(|(st, force_n)| StripTrace {
                along_m: st.along_m,
                stats: contact_stats(
                    &force_n,
                    &self.pos[p],
                    &self.height[p],
                    dt,
                    self.analysis_m,
                    self.uplift[p],
                ),
                force_n,
            })
            .collect();
        PantographTrace {
            name: pan.name.clone(),
            position_m: std::mem::take(&mut self.pos[p]),
            force_n: std::mem::take(&mut self.force[p]),
            force_filtered_n: filtered,
            wire_height_m: std::mem::take(&mut self.height[p]),
            max_uplift_at_support_m: self.uplift[p],
            stats,
            lateral_m: std::mem::take(&mut self.lateral[p]),
            twist_rad: std::mem::take(&mut self.twist[p]),
            head_half_width_m: pan.head_half_width_m,
            lateral,
            hard_spots,
            wire_forces: (self.wire_points[p].iter())
                .zip(std::mem::take(&mut self.wire_force[p]))
                .map(|(ks, f)| {
                    let mi = cm.contact_points(p)[ks[0]];
                    (m.wires[cm.moving_wire(mi)].name.clone(), f)
                })
                .collect(),
            overlaps,
            strips,
            gap_m: std::mem::take(&mut self.gap[p]),
        }
    }

    /// The statistics and traces of the recorded run.
    pub fn finish(mut self, cm: &CompiledModel, rs: RunStatistics) -> RunOutput {
        let m = cm.model();
        let dt = self.dt_s;
        let pantographs = (0..m.pantographs.len())
            .map(|p| self.pantograph_trace(cm, p))
            .collect();
        let mut out = RunOutput {
            speed_m_s: cm.speed_m_s(),
            dt_s: dt,
            time_s: self.time,
            analysis_m: self.analysis_m,
            pantographs,
            max_slack_droppers: rs.max_slack_droppers as usize,
            steps_with_slack_percent: 100.0 * rs.steps_with_slack_dropper as f64
                / rs.steps.max(1) as f64,
            n_modes: m.n_modes(),
            threads: 1,
            run_statistics: rs,
            wind: m.wind.as_ref().map(|w| w.report.clone()),
            irregularity: m
                .irregularity
                .as_ref()
                .map_or_else(Vec::new, |r| r.reports.clone()),
            stability: None,
            contact_wire_wave_speed_m_s: m.slowest_contact_wire().map(|(_, c)| c),
            uplift_datum: if self.datum.is_empty() {
                UpliftDatum::DesignStaticPosition
            } else {
                UpliftDatum::LoadedStaticPosition
            },
            contact_wire_wave_speeds_m_s: m
                .contact_wave_speeds()
                .into_iter()
                .map(|(_, c)| c)
                .collect(),
            droppers: None,
            curve: m.lateral.as_ref().and_then(|l| {
                // Each wire's polyline with its own tension, by role.
                let of = |role| -> Vec<(usize, f64)> {
                    (m.wires.iter().enumerate())
                        .filter(|(_, w)| w.role == role)
                        .filter_map(|(i, w)| {
                            Some((l.wire_line.get(i).copied()??, w.section.tension_n))
                        })
                        .collect()
                };
                l.curve_report(
                    &of(crate::model::WireRole::Contact),
                    &of(crate::model::WireRole::Messenger),
                )
            }),
        };
        on_head_per_curve(&mut out, m.track_origin_m);
        out
    }
}

/// Each curve section's record of where every pantograph's contact point ran on its head
/// (from the head's centre, the section's; samples whose track position lies in the section).
fn on_head_per_curve(out: &mut RunOutput, origin_m: f64) {
    let Some(curve) = out.curve.as_mut() else {
        return;
    };
    for c in &mut curve.sections {
        for p in out.pantographs.iter().filter(|p| !p.lateral_m.is_empty()) {
            let mut r = [f64::INFINITY, f64::NEG_INFINITY];
            for (z, &x) in p.lateral_m.iter().zip(&p.position_m) {
                if x + origin_m >= c.from_m && x + origin_m < c.to_m {
                    let y = z - c.head_offset_m;
                    r = [r[0].min(y), r[1].max(y)];
                }
            }
            if r[0] <= r[1] {
                c.on_head.push(crate::model::lateral::OnHead {
                    pantograph: p.name.clone(),
                    lateral_m: r,
                    min_head_margin_m: p.head_half_width_m.map(|h| h - r[0].abs().max(r[1].abs())),
                });
            }
        }
    }
}

impl Observer for Recorder {
    fn observe(
        &mut self,
        cm: &CompiledModel,
        st: &mut State,
        ws: &Workspace,
    ) -> Result<(), SimError> {
        self.time.push(st.t);
        let origin = st.track_origin_m;
        for (k, &x) in cm.probe_positions().iter().enumerate() {
            let xt = x + origin;
            if xt >= self.analysis_m[0] && xt <= self.analysis_m[1] {
                self.blowout = self.blowout.max(cm.probe(ws, k).abs());
            }
        }
        for (p, s) in ws.samples().iter().enumerate() {
            for (k, f) in self.strip_force[p].iter_mut().enumerate() {
                f.push(cm.head_force(ws, p, k));
            }
            let pts = cm.contact_points(p);
            if !self.wire_points[p].is_empty() {
                // Several contact wires: the force on each; inside an overlap, how many carry
                // force and how far above the contact point the nearest idle one is.
                let (mut touching, mut gap) = (0, f64::INFINITY);
                for (k, ks) in self.wire_points[p].iter().enumerate() {
                    let (_, h, present) = cm.moving_sample(ws, pts[ks[0]]);
                    let f: f64 = ks.iter().map(|&j| cm.moving_sample(ws, pts[j]).0).sum();
                    self.wire_force[p][k].push(f);
                    if f > 0.0 {
                        touching += 1;
                    } else if present && h != s.wire_height_m {
                        // An idle wire other than the one the pantograph runs on.
                        gap = gap.min(h - s.wire_height_m);
                    }
                }
                self.idle_gap[p].push(gap);
                let x = s.position_m + origin;
                for o in self.overlaps[p].iter_mut().filter(|o| o.contains(x)) {
                    o.add(x, s.force_n, touching);
                }
            }
            self.pos[p].push(s.position_m + origin);
            self.force[p].push(s.force_n);
            self.gap[p].push(cm.contact_gap(ws, p));
            self.height[p].push(s.wire_height_m);
            if self.record_lateral {
                self.lateral[p].push(s.lateral_m);
            }
            if self.record_twist {
                self.twist[p].push(s.twist_rad);
            }
            if self.span_m.is_none() && !self.supports_m.is_empty() {
                // The nearest support of the line.
                let x = s.position_m;
                let i = self.supports_m.partition_point(|&xs| xs < x);
                let j = if i == 0 {
                    0
                } else if i == self.supports_m.len()
                    || x - self.supports_m[i - 1] <= self.supports_m[i] - x
                {
                    i - 1
                } else {
                    i
                };
                let xs = self.supports_m[j] + origin;
                let monitors = self.support.get(j).map_or(&[][..], |v| &v[..]);
                if xs >= self.analysis_m[0] && xs <= self.analysis_m[1] {
                    for &k in monitors {
                        self.uplift[p] = self.uplift[p].max(self.uplift_at(cm, ws, k));
                    }
                }
                let datum = &self.datum;
                for o in self.overlaps[p].iter_mut().filter(|o| o.contains(xs)) {
                    for &k in monitors {
                        let u = cm.monitor(ws, k) - datum.get(k).copied().unwrap_or(0.0);
                        o.max_uplift_at_support_mm = o.max_uplift_at_support_mm.max(u * 1e3);
                    }
                }
            }
            if let Some(span) = self.span_m {
                let j = (s.position_m / span).round();
                let xs = j * span + origin;
                if j >= 0.0 && xs >= self.analysis_m[0] && xs <= self.analysis_m[1] {
                    if let Some(&[k]) = self.support.get(j as usize).map(|v| &v[..]) {
                        self.uplift[p] = self.uplift[p].max(self.uplift_at(cm, ws, k));
                    }
                }
            }
        }
        Ok(())
    }
}

/// Run a case (validated first).
pub fn run_case(case: &Case, progress: &mut dyn FnMut(f64) -> bool) -> Result<RunOutput, SimError> {
    simulate(&Setup::from_case(case)?, progress)
}

/// Simulate a set-up over its plan and take the EN 50318 statistics. `progress(fraction)` is
/// called every few hundred steps; returning `false` cancels the run.
pub fn simulate(
    setup: &Setup,
    progress: &mut dyn FnMut(f64) -> bool,
) -> Result<RunOutput, SimError> {
    simulate_with(setup, None, progress)
}

/// What a run records of its droppers ([`simulate_with`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DropperOptions {
    /// Keep every dropper's tension at every step (else only the cycles and the extremes).
    pub history: bool,
    /// The most numbers the history may hold (droppers × steps); beyond it only the cycles and
    /// the extremes are kept, and [`DropperRun::history`] is `None`.
    pub history_limit: usize,
    /// The S–N curve for Miner's damage (the case's `[dropper_fatigue]`).
    pub curve: Option<crate::analysis::fatigue::SnCurve>,
}

/// [`simulate`], and with `droppers` every dropper's tension through the run, its rainflow
/// cycles and its damage ([`crate::analysis::fatigue::DropperRecorder`], a second observer of
/// the same run loop).
pub fn simulate_with(
    setup: &Setup,
    droppers: Option<DropperOptions>,
    progress: &mut dyn FnMut(f64) -> bool,
) -> Result<RunOutput, SimError> {
    simulate_beside(setup, droppers, |_, _| Ok(Unobserved), progress).map(|(out, _)| out)
}

/// An observer that sees nothing ([`simulate_with`] has no third observer).
struct Unobserved;

impl Observer for Unobserved {
    fn observe(&mut self, _: &CompiledModel, _: &mut State, _: &Workspace) -> Result<(), SimError> {
        Ok(())
    }
}

/// [`simulate_with`], and beside the recorders one more observer of the same run, made by
/// `beside` from the integrator and its initial state (the energy sampler of
/// [`crate::analysis::eva::simulate_with_eva`]); it is handed back after the run.
pub(crate) fn simulate_beside<O: Observer>(
    setup: &Setup,
    droppers: Option<DropperOptions>,
    beside: impl FnOnce(&Integrator, &State) -> Result<O, SimError>,
    progress: &mut dyn FnMut(f64) -> bool,
) -> Result<(RunOutput, O), SimError> {
    let integ = setup.integrator()?;
    let mut st = integ.initial_state(setup.plan.start_m);
    let mut ws = integ.workspace();
    let n_steps = setup.n_steps();
    let mut rec = Recorder::new(
        integ.compiled(),
        integ.dt_s(),
        n_steps,
        setup.plan.analysis_m,
    );
    if integ.compiled().initial.is_some() {
        // Steady loads (ice, a mean wind): the uplift is measured from the loaded static state.
        rec.measure_uplift_from(integ.monitors_at(&st));
    }
    let mut drec = droppers.map(|o| {
        let mut d = crate::analysis::fatigue::DropperRecorder::new(
            integ.compiled(),
            n_steps,
            o.history,
            o.history_limit,
        );
        if integ.compiled().initial.is_some() {
            // Steady loads: each dropper's static tension is the loaded start's.
            d.static_from(integ.compiled(), &integ.gathered_at(&st));
        }
        d
    });
    let mut extra = beside(&integ, &st)?;
    let rs = match &mut drec {
        Some(d) => run(
            &integ,
            &mut st,
            &mut ws,
            n_steps,
            &mut [&mut rec, d, &mut extra],
            progress,
        )?,
        None => run(
            &integ,
            &mut st,
            &mut ws,
            n_steps,
            &mut [&mut rec, &mut extra],
            progress,
        )?,
    };
    let mut out = rec.finish(integ.compiled(), rs);
    out.stability = integ.stability().cloned();
    out.threads = integ.threads();
    if let (Some(d), Some(o)) = (drec, droppers) {
        out.droppers = Some(DropperRun {
            droppers: d.finish(integ.compiled(), o.curve.as_ref()),
            curve: o.curve,
            history: d.into_history(),
            history_limit: o.history_limit,
        });
    }
    Ok((out, extra))
}
