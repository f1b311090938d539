//! Studies built from several runs: the real-time window against the full model (paper §4.2,
//! Figs. 8–9), and `pcsim realtime` as a study of the contract ([`RealtimeStudy`]).

use serde::{Deserialize, Serialize};

use crate::analysis::record::{simulate, Recorder, RunOutput};
use crate::analysis::stats::{contact_stats, ContactStats};
use crate::analysis::sweep::parallel_map;
use crate::compile::Setup;
use crate::error::{CaseError, SimError};
use crate::input::case::{Case, PantographCase};
use crate::solve::realtime::Coupling;
use crate::solve::run::run;
use crate::study::contract::{Answer, Study, StudyFile, StudyKind};

/// Result of a window run in SIL mode.
#[derive(Debug, Clone, PartialEq)]
pub struct WindowRun {
    /// Window length, m.
    pub window_m: f64,
    /// Modes per wire and direction in the window.
    pub n_modes: usize,
    /// Window moves made.
    pub moves: usize,
    /// Time of every step, s.
    pub time_s: Vec<f64>,
    /// Pantograph position (track coordinates), m.
    pub position_m: Vec<f64>,
    /// Contact force, N.
    pub force_n: Vec<f64>,
    /// EN 50318 statistics over the analysis section.
    pub stats: Option<ContactStats>,
}

/// Run `case` with the window model in SIL mode over the same time as the full model (the one
/// run loop, with the EN 50318 recorder and the window mover as observers), and take the
/// statistics of the leading pantograph over the case's analysis section.
pub fn run_window_sil(case: &Case, window_m: f64) -> Result<WindowRun, SimError> {
    if !matches!(
        case.pantographs.first(),
        Some(PantographCase::Lumped { .. })
    ) {
        return Err(SimError::Case(CaseError::Invalid {
            field: "pantographs[0].kind".into(),
            value: "moving_force".into(),
            reason: "SIL needs a lumped pantograph".into(),
        }));
    }
    let mut rt = crate::compile::realtime_window(case, window_m, Coupling::Sil)?;
    let (duration_s, analysis_m) = rt.full_run();
    let n_steps = (duration_s / rt.dt_s()).ceil() as usize;
    let n_modes = rt.n_modes();
    if rt.is_line() {
        return run_window_line(&mut rt, window_m, n_steps, analysis_m);
    }
    let Some((integ, st, ws, mover)) = rt.parts_mut() else {
        unreachable!("a span-periodic window moves over one model");
    };
    let mut rec = Recorder::new(integ.compiled(), integ.dt_s(), n_steps, analysis_m);
    let rs = run(integ, st, ws, n_steps, &mut [&mut rec, mover], &mut |_| {
        true
    })
    .map_err(|e| match e {
        SimError::BlowUp {
            time_s,
            position_m,
            what,
        } => SimError::BlowUp {
            time_s,
            position_m,
            what: format!("window {window_m} m: {what}"),
        },
        other => other,
    })?;
    let mut out = rec.finish(integ.compiled(), rs);
    let p = out.pantographs.swap_remove(0);
    Ok(WindowRun {
        window_m,
        n_modes,
        moves: rs.window_moves as usize,
        time_s: out.time_s,
        position_m: p.position_m,
        force_n: p.force_n,
        stats: p.stats,
    })
}

/// [`run_window_sil`] on a line, whose window moves between a model per position: stepped by
/// [`crate::solve::realtime::RealtimeCatenary::step`], the statistics from the same
/// [`contact_stats`]. The window's uplift at the supports is not recorded here (its field reads
/// 0): the study compares the contact force.
fn run_window_line(
    rt: &mut crate::solve::realtime::RealtimeCatenary,
    window_m: f64,
    n_steps: usize,
    analysis_m: [f64; 2],
) -> Result<WindowRun, SimError> {
    let (mut time_s, mut position_m, mut force_n, mut height_m) = (
        Vec::with_capacity(n_steps),
        Vec::with_capacity(n_steps),
        Vec::with_capacity(n_steps),
        Vec::with_capacity(n_steps),
    );
    for _ in 0..n_steps {
        let o = rt.step();
        if let Some(what) = rt.fault() {
            return Err(SimError::BlowUp {
                time_s: o.time_s,
                position_m: o.position_m,
                what: format!("window {window_m} m: {what}"),
            });
        }
        time_s.push(o.time_s);
        position_m.push(o.position_m);
        force_n.push(o.contact_force_n);
        height_m.push(o.wire_height_m);
    }
    let stats = contact_stats(&force_n, &position_m, &height_m, rt.dt_s(), analysis_m, 0.0);
    Ok(WindowRun {
        window_m,
        n_modes: rt.n_modes(),
        moves: rt.moves(),
        time_s,
        position_m,
        force_n,
        stats,
    })
}

/// The window study: the full model and the window model at each length, leading pantograph.
#[derive(Debug, Clone, PartialEq)]
pub struct WindowStudy {
    /// The full model's run.
    pub full: RunOutput,
    /// The window's run at each length.
    pub windows: Vec<WindowRun>,
}

impl WindowStudy {
    /// Relative errors (%) of the window's mean, σ and maximum of the 0–20 Hz force against the
    /// full model, per window (`None` where a run did not cross the analysis section): the one
    /// law of the window's accuracy, [`crate::study::window_search::WindowErrors::of`], the
    /// window sweep's too.
    pub fn errors_percent(&self) -> Vec<Option<crate::study::window_search::WindowErrors>> {
        let Some(fs) = self.full.pantographs[0].stats else {
            return vec![None; self.windows.len()];
        };
        self.windows
            .iter()
            .map(|r| {
                r.stats
                    .map(|s| crate::study::window_search::WindowErrors::of(r.window_m, &s, &fs))
            })
            .collect()
    }
}

/// Run the full model of `case` (leading pantograph only), then the window model at every length
/// in `windows_m` side by side on up to `jobs` threads.
pub fn window_study(
    case: &Case,
    windows_m: &[f64],
    jobs: Option<usize>,
    progress: &mut dyn FnMut(f64) -> bool,
) -> Result<WindowStudy, SimError> {
    let single = crate::compile::window_case(case)?;
    crate::compile::require_contact(&single, "the real-time window study")?;
    let full = simulate(&Setup::from_case(&single)?, progress)?;
    let windows = parallel_map(windows_m, jobs, |&w| run_window_sil(&single, w))
        .into_iter()
        .collect::<Result<_, _>>()?;
    Ok(WindowStudy { full, windows })
}

/// The header of `realtime.csv` (every column numeric; an empty cell where a value is absent).
pub const REALTIME_HEADER: &str = "window_m,modes,moves,mean_n,std_n,mean_error_percent,std_error_percent,full_mean_n,full_std_n,measured_mean_n,measured_std_n,max_error_percent";

/// `pcsim realtime` as a study (issue 52): the real-time window of one pantograph's case
/// ([`crate::compile::window_case`]) at several lengths against the full model, in SIL mode
/// ([`window_study`]), written as `realtime.csv`, `timeseries.csv` (the 0–20 Hz forces) and
/// `realtime.json`, with the answer the terminal and the report open with. The front end loads
/// the case, applies its flags and fills this.
#[derive(Debug, Clone, PartialEq)]
pub struct RealtimeStudy {
    /// The one-pantograph case the window follows.
    pub case: Case,
    /// Its name (as the terminal and the report name it).
    pub case_name: String,
    /// The window lengths, m.
    pub windows_m: Vec<f64>,
    /// Pantographs of the case as given (the window carries one of them).
    pub together: usize,
}

/// One window against the full model (a row of `realtime.csv`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct RealtimeWindow {
    /// Window length, m.
    pub window_m: f64,
    /// Modes per wire and direction in the window.
    pub modes: usize,
    /// Window moves made.
    pub moves: usize,
    /// Mean of the 0–20 Hz contact force over the analysis section, N.
    pub mean_n: f64,
    /// Its standard deviation, N.
    pub std_n: f64,
    /// Error of the mean against the full model, %.
    pub mean_error_percent: f64,
    /// Error of σ against the full model, %.
    pub std_error_percent: f64,
    /// Error of the actual maximum against the full model, %.
    pub max_error_percent: f64,
}

/// What a real-time study gives (`realtime.json`, written and read back through this type;
/// `pcsim schema realtime`); the filtered time histories travel beside it, in `timeseries.csv`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct RealtimeOutput {
    /// The case's name.
    pub case_name: String,
    /// Train speed, km/h.
    pub speed_kmh: f64,
    /// The analysis section, m.
    pub analysis_m: [f64; 2],
    /// The pantograph the window follows (alone in the full model too).
    pub pantograph: String,
    /// Pantographs of the case as given.
    pub together: usize,
    /// The full model's modes per wire.
    pub full_modes: usize,
    /// The full model's mean 0–20 Hz force, N.
    pub full_mean_n: f64,
    /// The full model's σ, N.
    pub full_std_n: f64,
    /// The paper's measured mean and σ (§4.2), N, when the case is the one it measured.
    pub measured_n: Option<[f64; 2]>,
    /// Each window, in the order asked.
    pub windows: Vec<RealtimeWindow>,
    /// `timeseries.csv`'s text (not in realtime.json).
    #[serde(skip)]
    #[schemars(skip)]
    pub timeseries_csv: String,
}

/// The paper's measured mean and σ (`[paper_realtime]`) when the case is the SYT preset at
/// 222 km/h, N.
fn paper_measurement(case_name: &str, speed_kmh: f64) -> Option<[f64; 2]> {
    use crate::input::targets::target_value;
    if case_name != "syt-7.0-9.8" || (speed_kmh - 222.0).abs() > 1e-9 {
        return None;
    }
    Some([
        target_value("paper_realtime", "measured_mean_n")?,
        target_value("paper_realtime", "measured_std_n")?,
    ])
}

/// A window that never crossed the analysis section: refused, naming the section.
fn not_crossed(case: &Case, window_m: f64) -> SimError {
    SimError::Case(CaseError::Invalid {
        field: "run.analysis_m".into(),
        value: format!("{:?}", case.run.analysis_m),
        reason: format!("the {window_m} m window did not cross the analysis section"),
    })
}

/// `timeseries.csv` of a real-time study: the time, the position and the 0–20 Hz force of the
/// full model and of each window.
fn filtered_histories(full: &RunOutput, runs: &[WindowRun]) -> String {
    use crate::analysis::filter::lowpass_zero_phase;
    use crate::analysis::stats::CUTOFF_HZ;
    use std::fmt::Write as _;
    let fs_hz = 1.0 / full.dt_s;
    let ff = lowpass_zero_phase(&full.pantographs[0].force_n, fs_hz, CUTOFF_HZ);
    let wf: Vec<Vec<f64>> = runs
        .iter()
        .map(|r| lowpass_zero_phase(&r.force_n, fs_hz, CUTOFF_HZ))
        .collect();
    let mut ts = String::from("time_s,position_m,full_force_filtered_n");
    for r in runs {
        let _ = write!(ts, ",window_{}m_force_filtered_n", r.window_m);
    }
    ts.push('\n');
    let n = ff
        .len()
        .min(wf.iter().map(|v| v.len()).min().unwrap_or(usize::MAX));
    for k in 0..n {
        let _ = write!(
            ts,
            "{:.6},{:.4},{:.4}",
            full.time_s[k], full.pantographs[0].position_m[k], ff[k]
        );
        for w in &wf {
            let _ = write!(ts, ",{:.4}", w[k]);
        }
        ts.push('\n');
    }
    ts
}

impl RealtimeOutput {
    /// `realtime.csv`: one row per window ([`REALTIME_HEADER`]).
    pub fn to_csv(&self) -> String {
        use std::fmt::Write as _;
        let cell = |v: Option<f64>| v.map(|x| format!("{x}")).unwrap_or_default();
        let mut table = format!("{REALTIME_HEADER}\n");
        for w in &self.windows {
            let _ = writeln!(
                table,
                "{},{},{},{:.4},{:.4},{:.3},{:.3},{:.4},{:.4},{},{},{:.3}",
                w.window_m,
                w.modes,
                w.moves,
                w.mean_n,
                w.std_n,
                w.mean_error_percent,
                w.std_error_percent,
                self.full_mean_n,
                self.full_std_n,
                cell(self.measured_n.map(|m| m[0])),
                cell(self.measured_n.map(|m| m[1])),
                w.max_error_percent
            );
        }
        table
    }
}

impl Study for RealtimeStudy {
    const KIND: StudyKind = StudyKind::Realtime;
    type Output = RealtimeOutput;

    fn check(&self) -> Result<(), CaseError> {
        if self.windows_m.is_empty() {
            return Err(CaseError::Invalid {
                field: "window".into(),
                value: String::new(),
                reason: "give at least one window length".into(),
            });
        }
        crate::compile::require_contact(&self.case, "the real-time window study")
    }

    fn work(&self) -> usize {
        1 + self.windows_m.len()
    }

    fn run(&self, done: &(dyn Fn() + Sync)) -> Result<RealtimeOutput, SimError> {
        let study = window_study(&self.case, &self.windows_m, None, &mut |_| true)?;
        done();
        let full = &study.full;
        let fs = crate::study::window_search::full_stats(&self.case, full)?;
        let mut windows = Vec::new();
        for (r, e) in study.windows.iter().zip(study.errors_percent()) {
            done();
            let (s, e) = r
                .stats
                .zip(e)
                .ok_or_else(|| not_crossed(&self.case, r.window_m))?;
            windows.push(RealtimeWindow {
                window_m: r.window_m,
                modes: r.n_modes,
                moves: r.moves,
                mean_n: s.mean_n,
                std_n: s.std_n,
                mean_error_percent: e.mean_pct,
                std_error_percent: e.sigma_pct,
                max_error_percent: e.max_pct,
            });
        }
        Ok(RealtimeOutput {
            case_name: self.case_name.clone(),
            speed_kmh: self.case.run.speed_kmh,
            analysis_m: self.case.run.analysis_m,
            pantograph: full.pantographs[0].name.clone(),
            together: self.together,
            full_modes: full.n_modes,
            full_mean_n: fs.mean_n,
            full_std_n: fs.std_n,
            measured_n: paper_measurement(&self.case_name, self.case.run.speed_kmh),
            windows,
            timeseries_csv: filtered_histories(full, &study.windows),
        })
    }

    fn files(&self, o: &RealtimeOutput) -> Vec<StudyFile> {
        vec![
            StudyFile::text("realtime.csv", o.to_csv()),
            StudyFile::text("timeseries.csv", o.timeseries_csv.clone()),
            StudyFile::text(
                "realtime.json",
                serde_json::to_string_pretty(o).expect("a record of numbers and names") + "\n",
            ),
        ]
    }

    fn answer(o: &RealtimeOutput) -> Answer {
        let mut rows: Vec<(String, String)> = o
            .windows
            .iter()
            .map(|w| {
                (
                    format!("window {} m:", w.window_m),
                    format!(
                        "{} modes, {} moves, mean {:.2} N ({:+.2} %), σ {:.2} N ({:+.2} %), max {:+.2} %",
                        w.modes,
                        w.moves,
                        w.mean_n,
                        w.mean_error_percent,
                        w.std_n,
                        w.std_error_percent,
                        w.max_error_percent
                    ),
                )
            })
            .collect();
        rows.push((
            "full model:".into(),
            format!(
                "{} modes, mean {:.2} N, σ {:.2} N (pantograph {} alone)",
                o.full_modes, o.full_mean_n, o.full_std_n, o.pantograph
            ),
        ));
        if let Some([m, s]) = o.measured_n {
            rows.push((
                "measured (paper §4.2):".into(),
                format!("mean {m:.2} N, σ {s:.2} N"),
            ));
        }
        if o.together > 1 {
            rows.push((
                "note:".into(),
                format!(
                    "the window and its reference carry one pantograph, the rig's: the case runs {} together, and their waves change this one's force (pcsim run gives it among them)",
                    o.together
                ),
            ));
        }
        Answer {
            headline: format!(
                "{} at {} km/h: the real-time window against the full model, 0–20 Hz contact force over {:?} m",
                o.case_name, o.speed_kmh, o.analysis_m
            ),
            rows,
            warnings: Vec::new(),
            failures: Vec::new(),
        }
    }
}
