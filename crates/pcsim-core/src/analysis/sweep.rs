//! Sweeps: a grid of cases over speed, tension and damping, split into shards, run in parallel,
//! and merged back by case index. Each case runs single-threaded and deterministically, so a
//! sweep gives the same bytes with any number of threads or shards.

use crate::compile::Setup;
use crate::error::CaseError;
use crate::input::case::{Case, Damping};

/// The most worker threads per core a pool takes (each worker runs a whole model).
pub const MAX_JOBS_PER_CORE: usize = 4;

/// The most workers a pool takes on this machine: [`MAX_JOBS_PER_CORE`] × its cores.
pub fn max_jobs() -> usize {
    MAX_JOBS_PER_CORE * std::thread::available_parallelism().map_or(1, |n| n.get())
}

/// The workers a pool of `jobs` (`None`: every core) over `n_items` items really uses: never
/// more than the items, nor more than [`max_jobs`] (10 000 threads of whole models made no
/// progress), and at least one.
pub fn workers(jobs: Option<usize>, n_items: usize) -> usize {
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    jobs.unwrap_or(cores).min(max_jobs()).min(n_items).max(1)
}

/// Map `f` over `items` on a pool of [`workers`]`(jobs, items.len())` threads, keeping the order.
pub fn parallel_map<T: Sync, R: Send>(
    items: &[T],
    jobs: Option<usize>,
    f: impl Fn(&T) -> R + Sync + Send,
) -> Vec<R> {
    use rayon::prelude::*;
    match rayon::ThreadPoolBuilder::new()
        .num_threads(workers(jobs, items.len()))
        .build()
    {
        Ok(pool) => pool.install(|| items.par_iter().map(&f).collect()),
        Err(_) => items.iter().map(f).collect(),
    }
}

/// A damping law as given on a command line: `preset` (the case's own), `rayleigh:ALPHA:BETA`
/// or `modal:RATIO`.
pub fn parse_damping(s: &str, preset: &Damping) -> Result<Damping, CaseError> {
    let bad = |reason: &str| CaseError::Invalid {
        field: "--damping".into(),
        value: s.into(),
        reason: reason.into(),
    };
    let num = |x: &str| -> Result<f64, CaseError> {
        let v: f64 = x
            .parse()
            .map_err(|_| bad(&format!("`{x}` is not a number")))?;
        if !(v.is_finite() && v >= 0.0) {
            return Err(bad("values must be finite and ≥ 0"));
        }
        Ok(v)
    };
    let parts: Vec<&str> = s.split(':').collect();
    Ok(match parts.as_slice() {
        ["preset"] => preset.clone(),
        ["rayleigh", a, b] => Damping::Rayleigh {
            alpha: num(a)?,
            beta: num(b)?,
        },
        ["modal", z] => Damping::Modal { ratio: num(z)? },
        _ => return Err(bad("use `preset`, `rayleigh:ALPHA:BETA` or `modal:RATIO`")),
    })
}

/// The label of a damping law, as [`parse_damping`] reads it.
pub fn damping_label(d: &Damping) -> String {
    match d {
        Damping::Rayleigh { alpha, beta } => format!("rayleigh:{alpha}:{beta}"),
        Damping::Modal { ratio } => format!("modal:{ratio}"),
    }
}

/// A shard `I/N` of a sweep: the cases with index ≡ I (mod N).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shard {
    /// This shard's index I (0 ≤ I < N).
    pub index: usize,
    /// Number of shards N.
    pub count: usize,
}

impl Shard {
    /// The whole sweep.
    pub const ALL: Shard = Shard { index: 0, count: 1 };

    /// Parse `I/N`.
    pub fn parse(s: &str) -> Result<Shard, CaseError> {
        let bad = |reason: &str| CaseError::Invalid {
            field: "--shard".into(),
            value: s.into(),
            reason: reason.into(),
        };
        let (i, n) = s.split_once('/').ok_or_else(|| bad("use I/N, e.g. 0/4"))?;
        let i: usize = i.trim().parse().map_err(|_| bad("I is not a number"))?;
        let n: usize = n.trim().parse().map_err(|_| bad("N is not a number"))?;
        if n == 0 || i >= n {
            return Err(bad("need 0 ≤ I < N"));
        }
        Ok(Shard { index: i, count: n })
    }

    /// Whether case `index` belongs to this shard.
    pub fn contains(&self, index: usize) -> bool {
        index % self.count == self.index
    }
}

/// The most realisations a sweep or a Monte Carlo run takes.
pub const MAX_SEEDS: usize = 100_000;

/// The number of realisations asked for `case` (`None`: not asked, one run), checked once for
/// every front end: at least 1, at most [`MAX_SEEDS`], and only for a case with a seeded random
/// input (otherwise every realisation would be the same). The error says why; each front end
/// prefixes its own name of the setting (`--seeds 3: …`, `seeds = 3: …`).
pub fn check_seeds(seeds: Option<usize>, case: &Case) -> Result<usize, String> {
    match seeds {
        None => Ok(1),
        Some(0) => Err("run at least 1 realisation".into()),
        Some(n) if n > MAX_SEEDS => Err(format!("at most {MAX_SEEDS} realisations")),
        Some(_) if !case.is_random() => Err("the case has no seeded random input (an [[irregularity]] of kind psd or droppers, a [wind] with turbulence, or run.perturb_uplift_rel), so every realisation would be the same".into()),
        Some(n) => Ok(n),
    }
}

/// A grid of cases: every seed × damping × tension × speed (speed fastest).
#[derive(Debug, Clone)]
pub struct Grid {
    /// The case every grid point starts from.
    pub base: Case,
    /// Speeds, km/h (the fastest-varying axis).
    pub speeds_kmh: Vec<f64>,
    /// Contact-wire tensions, N (empty: the base case's).
    pub tensions_n: Vec<f64>,
    /// Dampings (empty: the base case's).
    pub dampings: Vec<Damping>,
    /// Seed offsets of the realisations (Monte Carlo; `[0]` for one).
    pub seeds: Vec<u64>,
}

/// One case of a grid.
#[derive(Debug, Clone)]
pub struct Job {
    /// Index of the case in the grid (stable across shards).
    pub index: usize,
    /// Train speed, km/h.
    pub speed_kmh: f64,
    /// Contact-wire tension, N.
    pub tension_n: f64,
    /// Damping, as written in the output.
    pub damping: String,
    /// Seed offset of the realisation (every seed of the case's random inputs plus this).
    pub seed_offset: u64,
    /// The case, with the grid point's values applied.
    pub case: Case,
}

impl Grid {
    /// The grid over the base case's own speed, tension and damping where an axis is empty.
    pub fn new(
        base: Case,
        speeds_kmh: Vec<f64>,
        tensions_n: Vec<f64>,
        dampings: Vec<Damping>,
    ) -> Self {
        let speeds_kmh = if speeds_kmh.is_empty() {
            vec![base.run.speed_kmh]
        } else {
            speeds_kmh
        };
        let tensions_n = if tensions_n.is_empty() {
            vec![base.catenary.contact_wire.tension_n]
        } else {
            tensions_n
        };
        let dampings = if dampings.is_empty() {
            vec![base.catenary.damping.clone()]
        } else {
            dampings
        };
        Grid {
            base,
            speeds_kmh,
            tensions_n,
            dampings,
            seeds: vec![0],
        }
    }

    /// `n` realisations of every grid point (seed offsets 0..n, outermost).
    pub fn with_seeds(mut self, n: usize) -> Self {
        self.seeds = (0..n.max(1) as u64).collect();
        self
    }

    /// Every case of the grid, each validated up front (a bad grid point fails before any work
    /// is done; the error names the case).
    pub fn jobs(&self) -> Result<Vec<Job>, CaseError> {
        let mut jobs = Vec::new();
        for &k in &self.seeds {
            for d in &self.dampings {
                let label = damping_label(d);
                for &t in &self.tensions_n {
                    for &v in &self.speeds_kmh {
                        let index = jobs.len();
                        let mut c = self.base.with_seed_offset(k);
                        c.run.speed_kmh = v;
                        c.catenary.contact_wire.tension_n = t;
                        c.catenary.damping = d.clone();
                        if k == 0 {
                            // The realisations differ in their seeds only: check each grid
                            // point once.
                            Setup::from_case(&c).map_err(|e| CaseError::InCase {
                                case: format!("case {index} ({v} km/h, {} kN, {label})", t / 1e3),
                                error: Box::new(e),
                            })?;
                        }
                        jobs.push(Job {
                            index,
                            speed_kmh: v,
                            tension_n: t,
                            damping: label.clone(),
                            seed_offset: k,
                            case: c,
                        });
                    }
                }
            }
        }
        Ok(jobs)
    }
}

/// Merge the rows of shards (case index, row): sorted by index; every index from 0 to the last
/// exactly once.
pub fn merge_rows(mut rows: Vec<(usize, String)>) -> Result<Vec<(usize, String)>, CaseError> {
    rows.sort_by_key(|r| r.0);
    for w in rows.windows(2) {
        if w[0].0 == w[1].0 {
            return Err(CaseError::Invalid {
                field: "shards".into(),
                value: format!("case {}", w[0].0),
                reason: "the case appears in more than one shard".into(),
            });
        }
    }
    if let Some((k, _)) = rows.iter().enumerate().find(|(k, r)| *k != r.0) {
        return Err(CaseError::Invalid {
            field: "shards".into(),
            value: format!("case {k}"),
            reason: "the case is missing from the shards".into(),
        });
    }
    Ok(rows)
}
