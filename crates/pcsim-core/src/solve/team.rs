//! One run on several cores: the step's per-group work split into fixed *parts*, and a team of
//! threads that runs a stage's parts side by side, with a barrier after each.
//!
//! # What is split, and why the bytes do not change
//! A part is a contiguous share of the modal vector, holding whole basis groups: its point
//! groups (gather and scatter), its velocity samplers, its implicit terms and the slots they
//! fill. Three of the step's stages are split (drift + gather, modal right-hand side + scatter,
//! implicit solve + kick); the others (fixed point forces, wind, moving points, pantographs)
//! stay on the calling thread. Every modal coordinate and every slot is computed by the same
//! operations in the same order whichever thread computes it, and the parts never depend on one
//! another inside a stage, so **the output bytes are the same with one thread or several**
//! (`tests/suite/threads.rs`). The partition depends on the thread count only through where it cuts.
//!
//! # Why a hand-written team and not rayon's `join`
//! A step of the 10 km line takes 50–190 µs (139 to 1 380 modes per wire, docs/performance.md)
//! and is split three times. `rayon::join` is cheap only when called from inside its pool, and
//! the run loop's observers and progress callbacks (which hold the caller's recorders, progress
//! bars, Python callbacks) are not `Send`, so the loop cannot move into a pool; from outside, each
//! join goes through the pool's injector and the caller blocks on a latch until a worker has run
//! it (a thread wake-up per stage; not measured here). The team here keeps its helpers spinning on an
//! epoch counter between stages for the whole run (the cores were given to the run), allocates
//! nothing per step, and is about a hundred lines. Rayon stays the tool of the sweeps.

use std::panic::{catch_unwind, resume_unwind, AssertUnwindSafe};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Mutex;

/// The most threads one run uses (more parts than that would be too small to pay).
pub const MAX_THREADS: usize = 16;

/// The threads one run may use for `requested`: an error for 0 or more than [`MAX_THREADS`],
/// else at most this machine's cores (the team's threads spin between the stages of a step, so a
/// thread without a core of its own slows the run down). The one rule of every front end.
pub fn usable_threads(requested: usize) -> Result<usize, String> {
    if requested == 0 || requested > MAX_THREADS {
        return Err(format!(
            "{requested}: give 1 to {MAX_THREADS} threads for one run"
        ));
    }
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    Ok(requested.min(cores))
}

/// How many of this machine's cores were idle over `sample` (from the kernel's CPU counters,
/// `/proc/stat`, read twice), at most the cores this process may use; `None` where the counters
/// cannot be read. A query of the machine, as [`std::thread::available_parallelism`] is: no input
/// file is read.
pub fn idle_cores(sample: std::time::Duration) -> Option<f64> {
    fn counters() -> Option<(u64, u64, usize)> {
        let text = std::fs::read_to_string("/proc/stat").ok()?;
        let mut lines = text.lines();
        let cpu = lines.next()?.strip_prefix("cpu ")?;
        let v: Vec<u64> = cpu
            .split_whitespace()
            .filter_map(|x| x.parse().ok())
            .collect();
        // user nice system idle iowait irq softirq steal (guest time is inside user).
        let total: u64 = v.iter().take(8).sum();
        let idle = v.get(3)? + v.get(4).copied().unwrap_or(0);
        let cpus = lines.filter(|l| l.starts_with("cpu")).count();
        Some((total, idle, cpus))
    }
    let (t0, i0, cpus) = counters()?;
    std::thread::sleep(sample);
    let (t1, i1, _) = counters()?;
    let dt = t1.checked_sub(t0)?;
    if dt == 0 || cpus == 0 {
        return None;
    }
    let idle = (i1.saturating_sub(i0)) as f64 / dt as f64 * cpus as f64;
    let mine = std::thread::available_parallelism().map_or(1, |n| n.get()) as f64;
    Some(idle.min(mine))
}

/// The threads to run on when `threads` were asked for ([`usable_threads`]) and `idle` cores
/// were measured free ([`idle_cores`]): the team's threads spin between the stages of a step, so
/// a thread whose core is busy with another process stalls every stage (on a 2-core machine
/// with both cores busy, `--threads 2` ran 2.25× slower than one thread: docs/performance.md,
/// "`--threads` on busy cores"). Fewer
/// threads, and the reason, when fewer cores than threads are idle (within half a core); the
/// output bytes are the same on any count.
pub fn threads_for_idle(threads: usize, idle: Option<f64>) -> (usize, Option<String>) {
    match idle {
        Some(idle) if threads > 1 && idle < threads as f64 - 0.5 => {
            let n = (idle.round() as usize).clamp(1, threads);
            (
                n,
                Some(format!(
                    "{threads} threads asked for, but only {idle:.1} of this machine's cores were idle: a thread without a core of its own stalls every step of the team (measured 2.25x slower than one thread with both cores of a 2-core machine busy: docs/performance.md), so the run takes {n} (the same bytes)"
                )),
            )
        }
        _ => (threads, None),
    }
}

/// A share of the step's per-group work (see the module's doc).
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Part {
    /// Modal coordinates.
    pub(crate) q: std::ops::Range<usize>,
    /// Point groups (`CompiledModel::groups`), and their displacement slots.
    pub(crate) groups: std::ops::Range<usize>,
    pub(crate) u: std::ops::Range<usize>,
    /// Velocity samplers (`CompiledModel::vels`), and their velocity slots.
    pub(crate) vels: std::ops::Range<usize>,
    pub(crate) v: std::ops::Range<usize>,
    /// Implicit point terms (`Integrator::implicit`).
    pub(crate) implicit: std::ops::Range<usize>,
}

/// What the partition needs to know of each unit it may not cut: its modal range and its cost.
pub(crate) struct Unit {
    /// Modal range of a point group.
    pub(crate) q: std::ops::Range<usize>,
    /// Displacement slots of the group.
    pub(crate) u: std::ops::Range<usize>,
}

/// Split the step's work into at most `threads` parts of about equal modal length, cutting only
/// between point groups, where every velocity sampler (`vels`: modal start, slot range) and every
/// implicit term (`implicit`: modal range) falls wholly on one side and the slot ranges follow
/// the modal order. One part when `threads` is 1 or no cut is clean. `len` is the modal length,
/// `n_u` / `n_v` the slot counts (the groups' slots start at 1: slot 0 is the ground).
pub(crate) fn partition(
    threads: usize,
    len: usize,
    groups: &[Unit],
    vels: &[(usize, std::ops::Range<usize>)],
    implicit: &[std::ops::Range<usize>],
    n_u: usize,
    n_v: usize,
) -> Vec<Part> {
    let whole = vec![Part {
        q: 0..len,
        groups: 0..groups.len(),
        u: 0..n_u,
        vels: 0..vels.len(),
        v: 0..n_v,
        implicit: 0..implicit.len(),
    }];
    let threads = threads.clamp(1, MAX_THREADS);
    if threads == 1 || groups.len() < 2 {
        return whole;
    }
    // The modal order must be the group order, the velocity order and the implicit order, and
    // the slots must follow it: then a cut at a group boundary is a cut of every list.
    let sorted = |r: &[usize]| r.windows(2).all(|w| w[0] <= w[1]);
    let gq: Vec<usize> = groups.iter().map(|g| g.q.start).collect();
    let gu: Vec<usize> = groups.iter().map(|g| g.u.start).collect();
    let vq: Vec<usize> = vels.iter().map(|v| v.0).collect();
    let vv: Vec<usize> = vels.iter().map(|v| v.1.start).collect();
    let iq: Vec<usize> = implicit.iter().map(|r| r.start).collect();
    if !(sorted(&gq) && sorted(&gu) && sorted(&vq) && sorted(&vv) && sorted(&iq)) {
        return whole;
    }
    // Candidate cuts: group starts (modal index) where no implicit term straddles.
    let clean = |q: usize| implicit.iter().all(|r| r.end <= q || r.start >= q);
    let mut cuts = Vec::new();
    for k in 1..threads {
        let target = len * k / threads;
        let best = (1..groups.len())
            .filter(|&g| clean(groups[g].q.start))
            .min_by_key(|&g| groups[g].q.start.abs_diff(target));
        if let Some(g) = best {
            if !cuts.contains(&g) {
                cuts.push(g);
            }
        }
    }
    cuts.sort_unstable();
    if cuts.is_empty() {
        return whole;
    }
    let mut parts = Vec::with_capacity(cuts.len() + 1);
    let mut bounds = vec![0];
    bounds.extend(&cuts);
    bounds.push(groups.len());
    for w in bounds.windows(2) {
        let (g0, g1) = (w[0], w[1]);
        let q0 = if g0 == 0 { 0 } else { groups[g0].q.start };
        let q1 = if g1 == groups.len() {
            len
        } else {
            groups[g1].q.start
        };
        let u0 = if g0 == 0 { 0 } else { groups[g0].u.start };
        let u1 = if g1 == groups.len() {
            n_u
        } else {
            groups[g1].u.start
        };
        let in_q = |q: usize| q >= q0 && q < q1;
        let vi0 = vq.iter().position(|&q| q >= q0).unwrap_or(vq.len());
        let vi1 = vq.iter().position(|&q| q >= q1).unwrap_or(vq.len());
        let v0 = if parts.is_empty() {
            0
        } else {
            vels.get(vi0).map_or(n_v, |v| v.1.start)
        };
        let v1 = if g1 == groups.len() {
            n_v
        } else {
            vels.get(vi1).map_or(n_v, |v| v.1.start)
        };
        let ii0 = iq.iter().position(|&q| q >= q0).unwrap_or(iq.len());
        let ii1 = iq.iter().position(|&q| q >= q1).unwrap_or(iq.len());
        debug_assert!(vq[vi0..vi1].iter().all(|&q| in_q(q)));
        parts.push(Part {
            q: q0..q1,
            groups: g0..g1,
            u: u0..u1,
            vels: vi0..vi1,
            v: v0..v1,
            implicit: ii0..ii1,
        });
    }
    parts
}

/// A fork's work: part `i` of the stage.
type Job<'a> = &'a (dyn Fn(usize) + Sync);

/// The team's shared words: the job of the current fork, its epoch, the helpers' count of
/// finished parts, a stop flag and a panic flag.
struct Shared {
    /// The current job, its lifetime erased (see [`Team::fork`]'s safety argument).
    job: Mutex<Option<Job<'static>>>,
    epoch: AtomicUsize,
    done: AtomicUsize,
    stop: AtomicBool,
    panicked: AtomicBool,
}

/// A team of `n` threads (the caller and `n − 1` helpers) for one run: made by [`with_team`].
pub struct Team<'s> {
    n: usize,
    shared: &'s Shared,
}

/// Spin this many times before yielding the core (a stage of a long line lasts tens of µs; a
/// yield lets a loaded machine run others while the team waits).
const SPINS: u32 = 1 << 12;

fn wait_until(cond: impl Fn() -> bool) {
    let mut spins = 0u32;
    while !cond() {
        if spins < SPINS {
            std::hint::spin_loop();
            spins += 1;
        } else {
            std::thread::yield_now();
        }
    }
}

/// Run `f` with a team of `threads` threads (the caller and `threads − 1` scoped helpers; one
/// thread: no helper). The helpers end when `f` returns or panics.
pub fn with_team<R>(threads: usize, f: impl FnOnce(&Team) -> R) -> R {
    let n = threads.clamp(1, MAX_THREADS);
    let shared = Shared {
        job: Mutex::new(None),
        epoch: AtomicUsize::new(0),
        done: AtomicUsize::new(0),
        stop: AtomicBool::new(false),
        panicked: AtomicBool::new(false),
    };
    std::thread::scope(|s| {
        for i in 1..n {
            let sh = &shared;
            s.spawn(move || helper(sh, i));
        }
        let team = Team { n, shared: &shared };
        let out = catch_unwind(AssertUnwindSafe(|| f(&team)));
        shared.stop.store(true, Ordering::Release);
        match out {
            Ok(r) => r,
            Err(e) => resume_unwind(e),
        }
    })
}

fn helper(sh: &Shared, i: usize) {
    let mut seen = 0;
    loop {
        wait_until(|| sh.epoch.load(Ordering::Acquire) != seen || sh.stop.load(Ordering::Acquire));
        let epoch = sh.epoch.load(Ordering::Acquire);
        if epoch == seen {
            return; // stopped
        }
        seen = epoch;
        let job = *sh.job.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(job) = job {
            if catch_unwind(AssertUnwindSafe(|| job(i))).is_err() {
                sh.panicked.store(true, Ordering::Release);
            }
        }
        sh.done.fetch_add(1, Ordering::AcqRel);
    }
}

impl Team<'_> {
    /// Threads in the team.
    pub fn threads(&self) -> usize {
        self.n
    }

    /// Run `job(i)` for every `i < parts` (at most the team's size): part 0 on the calling
    /// thread, part `i` on helper `i`; returns when all are done. A panic in any part is raised
    /// here, after every part has finished.
    pub(crate) fn fork(&self, parts: usize, job: &(dyn Fn(usize) + Sync)) {
        debug_assert!(parts <= self.n);
        if parts <= 1 {
            job(0);
            return;
        }
        let sh = self.shared;
        // SAFETY: the job's lifetime is erased so that the helpers can read it from the shared
        // slot. It is only called between the epoch's increment below and the moment the
        // helper counts itself done, and this function does not return (nor unwind: the
        // caller's own part runs under `catch_unwind`) before every helper has counted itself
        // done and the slot is cleared, so no call outlives the borrow.
        let erased: Job<'static> = unsafe { std::mem::transmute::<Job<'_>, Job<'static>>(job) };
        *sh.job.lock().unwrap_or_else(|e| e.into_inner()) = Some(erased);
        sh.done.store(0, Ordering::Release);
        // Helpers beyond `parts` run nothing: they see the job and skip their index.
        sh.epoch.fetch_add(1, Ordering::AcqRel);
        let own = catch_unwind(AssertUnwindSafe(|| job(0)));
        wait_until(|| sh.done.load(Ordering::Acquire) == self.n - 1);
        *sh.job.lock().unwrap_or_else(|e| e.into_inner()) = None;
        if let Err(e) = own {
            resume_unwind(e);
        }
        if sh.panicked.swap(false, Ordering::AcqRel) {
            panic!("a part of the step panicked on a helper thread");
        }
    }
}
