//! Progress on stderr: a bar on a terminal, a plain line every few seconds otherwise (logs, CI,
//! cluster jobs), or nothing.

use clap::ValueEnum;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Mutex;
use std::time::{Duration, Instant};

/// How progress is shown.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum ProgressMode {
    /// A bar when stderr is a terminal, plain lines otherwise.
    Auto,
    /// A bar (drawn only on a terminal).
    Bar,
    /// A line every few seconds.
    Plain,
    /// Nothing.
    None,
}

/// Seconds between plain progress lines (the environment variable `PCSIM_PROGRESS_EVERY_S`
/// changes it, for tests).
pub const PLAIN_EVERY_S: u64 = 5;

fn plain_every() -> Duration {
    let s = std::env::var("PCSIM_PROGRESS_EVERY_S")
        .ok()
        .and_then(|v| v.parse::<f64>().ok())
        .filter(|v| v.is_finite() && *v >= 0.0)
        .unwrap_or(PLAIN_EVERY_S as f64);
    Duration::from_secs_f64(s)
}

/// A progress reporter, safe to share between threads.
pub struct Progress {
    label: String,
    len: u64,
    bar: Option<ProgressBar>,
    plain: Option<Mutex<(Instant, Instant)>>,
    count: AtomicU64,
}

impl Progress {
    /// A reporter of `len` units (per-mille for a run).
    pub fn new(label: &str, len: u64, mode: ProgressMode, template: &str) -> Self {
        let tty = std::io::stderr().is_terminal();
        let (bar, plain) = match mode {
            ProgressMode::None => (None, false),
            ProgressMode::Plain => (None, true),
            ProgressMode::Bar => (Some(()), false),
            ProgressMode::Auto if tty => (Some(()), false),
            ProgressMode::Auto => (None, true),
        };
        let bar = bar.map(|_| {
            let pb = ProgressBar::new(len);
            if !tty {
                pb.set_draw_target(ProgressDrawTarget::hidden());
            }
            pb.set_style(
                ProgressStyle::with_template(template)
                    .unwrap_or_else(|_| ProgressStyle::default_bar())
                    .progress_chars("=> "),
            );
            pb.set_prefix(label.to_string());
            pb
        });
        let now = Instant::now();
        Progress {
            label: label.to_string(),
            len,
            bar,
            plain: plain.then(|| Mutex::new((now, now))),
            count: AtomicU64::new(0),
        }
    }

    /// A run's reporter in per-mille.
    pub fn run(label: &str, mode: ProgressMode) -> Self {
        Self::new(
            label,
            1000,
            mode,
            "{prefix:>14} [{bar:40}] {percent:>3}% {elapsed_precise} eta {eta}",
        )
    }

    /// Set the position.
    pub fn set(&self, pos: u64) {
        if let Some(b) = &self.bar {
            b.set_position(pos);
        }
        if let Some(p) = &self.plain {
            let mut g = p.lock().unwrap_or_else(|e| e.into_inner());
            if g.1.elapsed() >= plain_every() {
                g.1 = Instant::now();
                let frac = pos as f64 / self.len.max(1) as f64;
                let wall = g.0.elapsed().as_secs_f64();
                let eta = if frac > 0.0 {
                    format!(", about {:.0} s left", wall * (1.0 - frac) / frac)
                } else {
                    String::new()
                };
                eprintln!(
                    "{}: {:.0} % ({pos}/{}) after {wall:.0} s{eta}",
                    self.label,
                    100.0 * frac,
                    self.len
                );
            }
        }
    }

    /// Add one unit (sweeps count cases).
    pub fn inc(&self) {
        let n = self.count.fetch_add(1, Ordering::Relaxed) + 1;
        self.set(n);
    }

    /// Done.
    pub fn finish(&self) {
        if let Some(b) = &self.bar {
            b.finish_and_clear();
        }
    }
}
