//! Products of fixed-point sines with modal coordinates: `w(x_j) = Σ_k q_k sin(κ_k x_j)` (gather)
//! and `Q_k += Σ_j f_j sin(κ_k x_j)` (scatter, the generalised force of point forces; the
//! transpose). These are the hot spot of a modal catenary model.
//!
//! # The span-periodic fast path
//! The catenary repeats every span `S`, and the model length is `L = n_s·S`. Points that share an
//! offset `d` inside the span sit at `x = d + sS`. With `P = 2 n_s` and `κ_m sS = 2πms/P` (mode
//! number `m`),
//!
//! ```text
//! w(d + sS) = Σ_m q_m [sin(κ_m d) cos(2πms/P) + cos(κ_m d) sin(2πms/P)]
//!           = Re Σ_{ρ<P} (A_ρ − i B_ρ) e^{2πiρs/P},
//! A_ρ = Σ_{m ≡ ρ (mod P)} q_m sin(κ_m d),   B_ρ = Σ_{m ≡ ρ} q_m cos(κ_m d).
//! ```
//!
//! So a group of points costs one *fold* of the modes into `P` bins (`4N` multiply-adds for two
//! blocks) and **one inverse FFT of length P for all its points** — not one `P`-term sum per
//! point, whose cost would grow with the square of the length. Two real outputs share one complex
//! FFT (the two blocks of a pair, or two groups of one block): the spectra are made Hermitian, so
//! the real and imaginary parts of the transform are the two outputs. The scatter is the exact
//! transpose: the forces of a group's points, placed at their span indices, are transformed once
//! and unfolded onto the modes.
//!
//! Mirror offsets are free: the transform's output at any index `t` is the series at `d + tS`
//! (both sides depend on `m` through `e^{2πimt/P}` only), and the series is odd and `2L = PS`
//! periodic, so the point `(s + 1)S − d` of the mirror offset `S − d` reads
//! `w((s + 1)S − d) = −w(d + (P − 1 − s)S)`: output `P − 1 − s`, negated, of its partner's
//! transform, which the primary offset's points (`s < n_s`) leave unused. The scatter places a
//! mirror point's force there, negated. Points whose offset is shared by fewer than
//! [`MIN_GROUP`] points use dense rows. Both paths are tested against each other. No allocation
//! happens in `gather`/`scatter_add`.
//!
//! Cost: `O(groups · (N + P log P))` per step, close to linear in the model's length.

use std::sync::Arc;

use rustfft::num_complex::Complex;
use rustfft::{Fft, FftPlanner, FftPlannerScalar};

use crate::model::basis::SineBasis;
use crate::solve::kernels::{self, Isa};
use crate::solve::nufft::{NufftScratch, SineNufft};

/// Smallest number of points sharing an offset for the folded path to pay off.
pub const MIN_GROUP: usize = 4;

/// Complex numbers as `[re, im, …]`.
fn reals(buf: &[Complex<f64>]) -> &[f64] {
    // SAFETY: `Complex<f64>` is `#[repr(C)]` with the fields `re`, `im`: `n` of them are `2n`
    // `f64` in that order, with the alignment of `f64`.
    unsafe { std::slice::from_raw_parts(buf.as_ptr().cast::<f64>(), 2 * buf.len()) }
}

/// [`reals`], writable.
fn reals_mut(buf: &mut [Complex<f64>]) -> &mut [f64] {
    // SAFETY: as in `reals`; the borrow of `buf` is moved into the result.
    unsafe { std::slice::from_raw_parts_mut(buf.as_mut_ptr().cast::<f64>(), 2 * buf.len()) }
}

/// Whether `nd` points outside the folded groups, on `n` modes, are better served by the
/// non-uniform transform than by dense rows. Measured (`examples/sampler_cost.rs`, callgrind, a
/// gather and a scatter of two blocks): dense rows cost about `2.1·nd·N` instructions (since
/// their scatter holds sixteen modes in registers while the rows pass, [`kernels::axpy2_rows`];
/// 2.9·nd·N before), the transform about `26·N·log₂(4N)` (381.8 k at 1 200 modes, since its
/// half-length sine transform; 59·N·log₂(4N) before), so the transform pays from `nd ≈
/// 12·log₂(4N)` points (about 150 at 1 200 modes). On `line-structure-2002` (151 points per
/// wire, 830 modes) it takes the step from 446 k to 335 k instructions (with the dense rows
/// of then), its statistics within 1.1e-11. Never below 64 points: the real-time windows
/// (about 35) stay on their rows.
pub fn spread_pays(nd: usize, n: usize) -> bool {
    let log = ((4 * n.max(1)) as f64).log2();
    nd >= 64 && nd as f64 > 12.0 * log
}

#[derive(Clone)]
struct Group {
    /// `sin(κ_k d)`, `cos(κ_k d)` for every mode.
    sin_d: Vec<f64>,
    cos_d: Vec<f64>,
    /// (output index, transform index `s`) of each point at `d + sS`, as runs.
    members: Vec<Run>,
    /// (output index, transform index `P − 1 − s`) of each point at `(s + 1)S − d` (the mirror
    /// offset `S − d`), whose value is the transform's negated (see the module), as runs.
    mirrored: Vec<Run>,
    /// One more than the largest output index and transform index of its points (checked once
    /// per call, so that the loops over the points need no check of their own).
    j_end: usize,
    t_end: usize,
}

/// Points whose output and transform indices both step evenly: `(j0 + k·dj, t0 + k·dt)`,
/// `k < len` (a group's points are one run when every span holds the same points, its output
/// indices a span's points apart and its transform indices one apart), so that reading and
/// placing them walks two strides instead of a list of pairs.
#[derive(Clone, Copy, Debug, PartialEq)]
#[doc(hidden)] // public for the unit tests in tests/suite/unit
pub struct Run {
    pub j0: usize,
    pub dj: isize,
    pub t0: usize,
    pub dt: isize,
    pub len: usize,
}

impl Run {
    /// The maximal runs of `pairs`, in its order.
    pub fn split(pairs: &[(usize, usize)]) -> Vec<Run> {
        let mut runs: Vec<Run> = Vec::new();
        for &(j, t) in pairs {
            if let Some(r) = runs.last_mut() {
                let (dj, dt) = (j as isize - r.j0 as isize, t as isize - r.t0 as isize);
                let steps = if r.len == 1 { Some((dj, dt)) } else { None };
                let (sj, st) = steps.unwrap_or((r.dj, r.dt));
                let k = r.len as isize;
                if r.j0 as isize + k * sj == j as isize && r.t0 as isize + k * st == t as isize {
                    (r.dj, r.dt, r.len) = (sj, st, r.len + 1);
                    continue;
                }
            }
            runs.push(Run {
                j0: j,
                dj: 0,
                t0: t,
                dt: 0,
                len: 1,
            });
        }
        runs
    }

    /// Point `k`'s (output, transform) indices.
    #[inline(always)]
    pub fn at(&self, k: usize) -> (usize, usize) {
        let k = k as isize;
        (
            (self.j0 as isize + k * self.dj) as usize,
            (self.t0 as isize + k * self.dt) as usize,
        )
    }
}

/// The real (`IM = false`) or imaginary part of a complex number.
#[inline(always)]
fn part<const IM: bool>(z: &Complex<f64>) -> &f64 {
    if IM {
        &z.im
    } else {
        &z.re
    }
}

/// [`part`], writable.
#[inline(always)]
fn part_mut<const IM: bool>(z: &mut Complex<f64>) -> &mut f64 {
    if IM {
        &mut z.im
    } else {
        &mut z.re
    }
}

impl Group {
    /// `f(j, t, negated)` for every point: the members' (output, transform) indices, then the
    /// mirror offset's (whose values are the transform's negated).
    #[inline(always)]
    fn each_point(&self, mut f: impl FnMut(usize, usize, bool)) {
        // Two calls with a constant `negated`, so that each loop is compiled without the test.
        #[inline(always)]
        fn walk(runs: &[Run], negated: bool, f: &mut impl FnMut(usize, usize, bool)) {
            for r in runs {
                for k in 0..r.len {
                    let (j, t) = r.at(k);
                    f(j, t, negated);
                }
            }
        }
        walk(&self.members, false, &mut f);
        walk(&self.mirrored, true, &mut f);
    }

    /// `out[j] = ±part(buf[t])` for every point (− for the mirror offset's).
    #[inline(always)]
    fn read<const IM: bool>(&self, buf: &[Complex<f64>], out: &mut [f64]) {
        assert!(self.j_end <= out.len() && self.t_end <= buf.len());
        self.each_point(|j, t, negated| {
            // SAFETY: every `j < j_end ≤ out.len()` and `t < t_end ≤ buf.len()` (checked above;
            // `j_end`, `t_end` are made with the lists the runs reproduce, tested, and neither
            // changes after).
            unsafe {
                let v = *part::<IM>(buf.get_unchecked(t));
                *out.get_unchecked_mut(j) = if negated { -v } else { v };
            }
        });
    }

    /// `part(buf[t]) = ±f[j]` for every point (the transpose of [`Self::read`]).
    #[inline(always)]
    fn place<const IM: bool>(&self, f: &[f64], buf: &mut [Complex<f64>]) {
        assert!(self.j_end <= f.len() && self.t_end <= buf.len());
        self.each_point(|j, t, negated| {
            // SAFETY: as in `read`.
            unsafe {
                let v = *f.get_unchecked(j);
                *part_mut::<IM>(buf.get_unchecked_mut(t)) = if negated { -v } else { v };
            }
        });
    }
}

/// Precomputed sampler for a fixed set of points on one [`SineBasis`].
#[derive(Clone)]
pub struct PointSampler {
    isa: Isa,
    n_modes: usize,
    n_points: usize,
    period: usize,
    groups: Vec<Group>,
    /// Unnormalised transform `Σ_ρ W_ρ e^{+2πiρs/P}` (an inverse FFT).
    fft: Option<Arc<dyn Fft<f64>>>,
    fft_scratch: usize,
    /// The output indices of the points outside groups that take dense rows.
    dense: Vec<usize>,
    /// Their rows `sin(κ_k x_j)`, one after the other (`N` values each).
    dense_rows: Vec<f64>,
    /// The points outside groups when they are too many for dense rows: their output indices
    /// and the non-uniform transform over them ([`crate::solve::nufft`]).
    spread: Option<(Vec<usize>, SineNufft)>,
}

impl std::fmt::Debug for PointSampler {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("PointSampler")
            .field("n_modes", &self.n_modes)
            .field("n_points", &self.n_points)
            .field("period", &self.period)
            .field("groups", &self.groups.len())
            .field("dense", &self.dense.len())
            .field("spread", &self.spread.as_ref().map_or(0, |s| s.0.len()))
            .finish()
    }
}

/// Scratch for [`PointSampler`]: the bins of the current one or two groups and the complex
/// transform buffers; for the non-uniform transform, its scratch, the points' values of two
/// blocks and one block of modes.
#[derive(Debug, Clone)]
pub struct SamplerScratch {
    /// `[a1 | b1 | a2 | b2]` (two blocks) or `[a | b]` (one) of the current group.
    cur: Vec<f64>,
    /// The same for the second group of a chunk of two.
    second: Vec<f64>,
    buf: Vec<Complex<f64>>,
    fft: Vec<Complex<f64>>,
    spread: NufftScratch,
    spread_pts: Vec<f64>,
    spread_modes: Vec<f64>,
    /// The two blocks' forces of the dense rows' points, in the rows' order.
    dense_f: Vec<f64>,
}

impl SamplerScratch {
    /// Length of the bin arrays (the period).
    pub fn len(&self) -> usize {
        self.buf.len()
    }
    /// True when empty.
    pub fn is_empty(&self) -> bool {
        self.buf.is_empty()
    }
    /// The larger of two scratches (one scratch serves several samplers).
    pub fn max(self, o: SamplerScratch) -> SamplerScratch {
        let grows = o.buf.len() > self.buf.len()
            || o.fft.len() > self.fft.len()
            || o.spread_pts.len() > self.spread_pts.len()
            || o.spread_modes.len() > self.spread_modes.len()
            || o.dense_f.len() > self.dense_f.len()
            || o.spread.is_larger_than(&self.spread);
        if grows {
            SamplerScratch {
                cur: vec![0.0; o.cur.len().max(self.cur.len())],
                second: vec![0.0; o.second.len().max(self.second.len())],
                buf: vec![Complex::new(0.0, 0.0); o.buf.len().max(self.buf.len())],
                fft: vec![Complex::new(0.0, 0.0); o.fft.len().max(self.fft.len())],
                spread: self.spread.max(o.spread),
                spread_pts: vec![0.0; o.spread_pts.len().max(self.spread_pts.len())],
                spread_modes: vec![0.0; o.spread_modes.len().max(self.spread_modes.len())],
                dense_f: vec![0.0; o.dense_f.len().max(self.dense_f.len())],
            }
        } else {
            self
        }
    }
}

/// The points `xs` grouped by their offset in the span (`span_m` long, `n_spans` of them, offsets
/// equal within `tol`): each offset with its points (index in `xs`, span index).
#[allow(clippy::type_complexity)]
fn offsets_in_span(
    xs: &[f64],
    span_m: f64,
    n_spans: usize,
    tol: f64,
) -> Vec<(f64, Vec<(usize, usize)>)> {
    let (s, ns) = (span_m, n_spans);
    let mut offsets: Vec<(f64, Vec<(usize, usize)>)> = Vec::new();
    for (j, &x) in xs.iter().enumerate() {
        let mut sidx = (x / s).floor();
        let mut d = x - sidx * s;
        if d > s - tol {
            d -= s;
            sidx += 1.0;
        }
        if d.abs() < tol {
            d = 0.0;
        }
        let sidx = sidx as usize;
        if sidx >= ns {
            continue;
        }
        match offsets.iter_mut().find(|(od, _)| (od - d).abs() < tol) {
            Some((_, m)) => m.push((j, sidx)),
            None => offsets.push((d, vec![(j, sidx)])),
        }
    }
    offsets
}

impl PointSampler {
    /// Build a sampler for points `xs` on `basis`. `span_m` enables the periodic path when the
    /// model length is a whole number of spans; pass `None` for dense rows only.
    pub fn new(basis: &SineBasis, xs: &[f64], span_m: Option<f64>, isa: Isa) -> Self {
        let n = basis.n_modes();
        let l = basis.length_m();
        let mut groups = Vec::new();
        let mut dense = Vec::new();
        let mut dense_rows = Vec::new();
        let mut period = 2;
        let n_spans = span_m.and_then(|s| {
            let ns = (l / s).round();
            ((ns * s - l).abs() < 1e-9 * l && ns >= 1.0).then_some(ns as usize)
        });
        let mut used = vec![false; xs.len()];
        if let (Some(ns), Some(s)) = (n_spans, span_m) {
            period = 2 * ns;
            let tol = 1e-9 * l.max(1.0);
            let mut offsets = offsets_in_span(xs, s, ns, tol);
            offsets.retain(|(_, m)| m.len() >= MIN_GROUP);
            // Order as primary, then its mirror (offset S − d) if present.
            let mut taken = vec![false; offsets.len()];
            for i in 0..offsets.len() {
                if taken[i] {
                    continue;
                }
                taken[i] = true;
                let d = offsets[i].0;
                let mut sin_d = vec![0.0; n];
                let mut cos_d = vec![0.0; n];
                basis.fill_sines_cosines(d, &mut sin_d, &mut cos_d);
                let mut mirrored = Vec::new();
                if d > tol && (d - 0.5 * s).abs() > tol {
                    if let Some(k) = (0..offsets.len())
                        .find(|&k| !taken[k] && (offsets[k].0 - (s - d)).abs() < tol)
                    {
                        taken[k] = true;
                        mirrored = offsets[k]
                            .1
                            .iter()
                            .map(|&(j, si)| (j, period - 1 - si))
                            .collect();
                    }
                }
                let members = offsets[i].1.clone();
                let all = || members.iter().chain(&mirrored);
                let j_end = all().map(|&(j, _)| j + 1).max().unwrap_or(0);
                let t_end = all().map(|&(_, t)| t + 1).max().unwrap_or(0);
                groups.push(Group {
                    sin_d,
                    cos_d,
                    members: Run::split(&members),
                    mirrored: Run::split(&mirrored),
                    j_end,
                    t_end,
                });
            }
            for g in &groups {
                g.each_point(|j, _, _| used[j] = true);
            }
        }
        let rest: Vec<usize> = (0..xs.len()).filter(|&j| !used[j]).collect();
        let spread = spread_pays(rest.len(), n).then(|| {
            let pts: Vec<f64> = rest.iter().map(|&j| xs[j]).collect();
            (rest.clone(), SineNufft::new(basis, &pts, isa))
        });
        if spread.is_none() {
            for &j in &rest {
                let mut row = vec![0.0; n];
                basis.fill_sines(xs[j], &mut row);
                dense.push(j);
                dense_rows.extend_from_slice(&row);
            }
        }
        let fft: Option<Arc<dyn Fft<f64>>> = (!groups.is_empty()).then(|| match isa {
            Isa::Portable => FftPlannerScalar::new().plan_fft_inverse(period),
            Isa::X86V3 => FftPlanner::new().plan_fft_inverse(period),
        });
        let fft_scratch = fft.as_ref().map_or(0, |f| f.get_inplace_scratch_len());
        Self {
            isa,
            n_modes: n,
            n_points: xs.len(),
            period,
            groups,
            fft,
            fft_scratch,
            dense,
            dense_rows,
            spread,
        }
    }

    /// Number of points.
    pub fn n_points(&self) -> usize {
        self.n_points
    }

    /// The instruction set of its kernels.
    pub fn isa(&self) -> Isa {
        self.isa
    }

    /// Number of modes of the basis.
    pub fn n_modes(&self) -> usize {
        self.n_modes
    }

    /// Scratch sized for this sampler.
    pub fn scratch(&self) -> SamplerScratch {
        let p = self.period;
        let (spread, np, nm) = match &self.spread {
            Some((idx, t)) => (t.scratch(), idx.len(), t.n_modes()),
            None => (NufftScratch::default(), 0, 0),
        };
        SamplerScratch {
            cur: vec![0.0; 4 * p],
            second: vec![0.0; 4 * p],
            buf: vec![Complex::new(0.0, 0.0); p],
            fft: vec![Complex::new(0.0, 0.0); self.fft_scratch],
            spread,
            spread_pts: vec![0.0; 2 * np],
            spread_modes: vec![0.0; nm],
            dense_f: vec![0.0; 2 * self.dense.len()],
        }
    }

    /// The dense rows' points: (output index, row).
    fn dense_rows(&self) -> impl Iterator<Item = (&usize, &[f64])> {
        self.dense
            .iter()
            .zip(self.dense_rows.chunks_exact(self.n_modes.max(1)))
    }

    /// Number of points handled by the folded (periodic) path.
    pub fn n_folded(&self) -> usize {
        self.groups
            .iter()
            .map(|g| {
                g.members
                    .iter()
                    .chain(&g.mirrored)
                    .map(|r| r.len)
                    .sum::<usize>()
            })
            .sum()
    }

    /// Number of offset groups that need a pass over the modes (a mirror offset shares its
    /// partner's).
    pub fn n_mode_passes(&self) -> usize {
        self.groups.len()
    }

    /// Whether the folded path covers every point with a single group and no dense row (then
    /// a scaled scatter can be fused, see [`Self::scatter_scaled`]).
    pub fn is_single_group(&self) -> bool {
        self.groups.len() == 1 && self.dense.is_empty() && self.spread.is_none()
    }

    /// Number of points served by the non-uniform transform.
    pub fn n_spread(&self) -> usize {
        self.spread.as_ref().map_or(0, |s| s.0.len())
    }

    /// The spread points of the `k` blocks of `q`: gathered by the non-uniform transform, two
    /// blocks per transform, and written to their places in `out` (block-major).
    fn gather_spread(&self, q: &[f64], k: usize, out: &mut [f64], sc: &mut SamplerScratch) {
        let Some((idx, t)) = &self.spread else {
            return;
        };
        let (n, np, ns) = (self.n_modes, self.n_points, idx.len());
        let mut b = 0;
        while b < k {
            let nb = (k - b).min(2);
            t.gather(
                &q[b * n..(b + nb) * n],
                nb,
                &mut sc.spread_pts[..nb * ns],
                &mut sc.spread,
            );
            for i in 0..nb {
                let o = &mut out[(b + i) * np..(b + i + 1) * np];
                for (v, &j) in sc.spread_pts[i * ns..(i + 1) * ns].iter().zip(idx) {
                    o[j] = *v;
                }
            }
            b += nb;
        }
    }

    /// The spread points' forces of the `k` blocks of `f`, scattered by the non-uniform
    /// transform onto `out` (`k · N`), two blocks per transform; with `scale` (one block),
    /// `out += scale ⊙ Φᵀ f`.
    fn scatter_spread(
        &self,
        f: &[f64],
        k: usize,
        out: &mut [f64],
        scale: &[f64],
        sc: &mut SamplerScratch,
    ) {
        let Some((idx, t)) = &self.spread else {
            return;
        };
        let (n, np, ns) = (self.n_modes, self.n_points, idx.len());
        let mut b = 0;
        while b < k {
            let nb = (k - b).min(2);
            for i in 0..nb {
                let fb = &f[(b + i) * np..(b + i + 1) * np];
                for (v, &j) in sc.spread_pts[i * ns..(i + 1) * ns].iter_mut().zip(idx) {
                    *v = fb[j];
                }
            }
            if scale.is_empty() {
                t.scatter_add(
                    &sc.spread_pts[..nb * ns],
                    nb,
                    &mut out[b * n..(b + nb) * n],
                    &mut sc.spread,
                );
            } else {
                let m = &mut sc.spread_modes[..n];
                m.fill(0.0);
                t.scatter_add(&sc.spread_pts[..ns], 1, m, &mut sc.spread);
                for ((o, v), s) in out[..n].iter_mut().zip(m.iter()).zip(scale) {
                    *o += s * v;
                }
            }
            b += nb;
        }
    }

    /// The Hermitian spectrum of two units (`x = [ax | bx]`, `y = [ay | by]`, each `2P`) packed
    /// into one complex sequence, so that the transform's real part is unit x's output and its
    /// imaginary part unit y's: `W_ρ = herm(A_x − iB_x)_ρ + i herm(A_y − iB_y)_ρ`.
    ///
    /// Bin `r` holds mode numbers `≡ r + 1 (mod P)`, so DFT index `ρ ≥ 1` reads bin `ρ − 1` and
    /// its negative `P − ρ` reads bin `P − 1 − ρ`; `ρ = 0` reads bin `P − 1` (both ways).
    /// [`kernels::pack_bins`] walks the bins forwards and backwards at once, four at a time.
    fn pack(&self, x: &[f64], y: Option<&[f64]>, buf: &mut [Complex<f64>]) {
        let p = self.period;
        kernels::pack_bins(self.isa, x, y.unwrap_or(&[]), p, reals_mut(&mut buf[..p]));
    }

    /// The transpose of [`Self::pack`] for the scatter: from the transform `Y` of `F_x + i F_y`,
    /// the bins `[C | S]` of each unit, `C_ρ + iS_ρ = Σ_s F(s) e^{2πiρs/P}`. Bin `i` takes
    /// `ρ = i + 1` and its negative `P − 1 − i`; bin `P − 1` takes `ρ = 0`
    /// ([`kernels::unpack_bins`]).
    fn unpack(&self, buf: &[Complex<f64>], x: &mut [f64], y: Option<&mut [f64]>) {
        let p = self.period;
        kernels::unpack_bins(self.isa, reals(&buf[..p]), p, x, y.unwrap_or(&mut []));
    }

    fn transform(&self, sc: &mut SamplerScratch) {
        if let Some(f) = &self.fft {
            f.process_with_scratch(&mut sc.buf[..self.period], &mut sc.fft[..self.fft_scratch]);
        }
    }

    /// Gather for `k` blocks of modal coordinates sharing this basis: `q` holds the blocks one
    /// after the other (`k · N` values), `out` receives `k · n_points` values, block-major.
    pub fn gather(&self, q: &[f64], k: usize, out: &mut [f64], sc: &mut SamplerScratch) {
        let (n, np) = (self.n_modes, self.n_points);
        let mut b = 0;
        while b + 1 < k {
            let (o1, o2) = out[b * np..(b + 2) * np].split_at_mut(np);
            self.gather_pair(
                &q[b * n..(b + 1) * n],
                &q[(b + 1) * n..(b + 2) * n],
                o1,
                o2,
                sc,
            );
            b += 2;
        }
        if b < k {
            self.gather_one(&q[b * n..(b + 1) * n], &mut out[b * np..(b + 1) * np], sc);
        }
        self.gather_spread(q, k, out, sc);
    }

    /// Two blocks: one transform per group (its mirror offset's points included); the folds of
    /// two groups in one pass over the modes ([`kernels::fold2x2`]).
    fn gather_pair(
        &self,
        q1: &[f64],
        q2: &[f64],
        o1: &mut [f64],
        o2: &mut [f64],
        sc: &mut SamplerScratch,
    ) {
        let p = self.period;
        for two in self.groups.chunks(2) {
            match two {
                [g, h] => {
                    let tabs = [&g.sin_d[..], &g.cos_d, &h.sin_d, &h.cos_d];
                    let out = [&mut sc.cur[..4 * p], &mut sc.second[..4 * p]];
                    kernels::fold2x2(self.isa, q1, q2, tabs, p, out);
                }
                [g] => kernels::fold2(
                    self.isa,
                    q1,
                    q2,
                    &g.sin_d,
                    &g.cos_d,
                    p,
                    &mut sc.cur[..4 * p],
                ),
                _ => unreachable!("chunks of one or two"),
            }
            for (i, g) in two.iter().enumerate() {
                let bins = if i == 0 { &sc.cur } else { &sc.second };
                let (x, y) = bins[..4 * p].split_at(2 * p);
                self.pack(x, Some(y), &mut sc.buf);
                self.transform(sc);
                g.read::<false>(&sc.buf, o1);
                g.read::<true>(&sc.buf, o2);
            }
        }
        for (&j, row) in self.dense_rows() {
            let (a, b) = kernels::dot2(self.isa, row, q1, q2);
            o1[j] = a;
            o2[j] = b;
        }
    }

    /// One block: groups two at a time share a transform.
    fn gather_one(&self, q: &[f64], out: &mut [f64], sc: &mut SamplerScratch) {
        let p = self.period;
        for pair in self.groups.chunks(2) {
            match pair {
                [g, h] => {
                    let tabs = [&g.sin_d[..], &g.cos_d, &h.sin_d, &h.cos_d];
                    let out = [&mut sc.cur[..2 * p], &mut sc.second[..2 * p]];
                    kernels::fold1x2(self.isa, q, tabs, p, out);
                }
                [g] => kernels::fold1(self.isa, q, &g.sin_d, &g.cos_d, p, &mut sc.cur[..2 * p]),
                _ => unreachable!("chunks of one or two"),
            }
            let y = (pair.len() == 2).then_some(&sc.second[..2 * p]);
            self.pack(&sc.cur[..2 * p], y, &mut sc.buf);
            self.transform(sc);
            pair[0].read::<false>(&sc.buf, out);
            if let Some(g) = pair.get(1) {
                g.read::<true>(&sc.buf, out);
            }
        }
        for (&j, row) in self.dense_rows() {
            out[j] = kernels::dot(self.isa, q, row);
        }
    }

    /// Scatter for `k` blocks: `out` (`k · N` values) `+=` the generalised forces of the point
    /// forces `f` (`k · n_points` values, block-major).
    pub fn scatter_add(&self, f: &[f64], k: usize, out: &mut [f64], sc: &mut SamplerScratch) {
        let (n, np) = (self.n_modes, self.n_points);
        let mut b = 0;
        while b + 1 < k {
            let (o1, o2) = out[b * n..(b + 2) * n].split_at_mut(n);
            self.scatter_pair(
                &f[b * np..(b + 1) * np],
                &f[(b + 1) * np..(b + 2) * np],
                o1,
                o2,
                sc,
            );
            b += 2;
        }
        if b < k {
            self.scatter_one(
                &f[b * np..(b + 1) * np],
                &mut out[b * n..(b + 1) * n],
                &[],
                sc,
            );
        }
        self.scatter_spread(f, k, out, &[], sc);
    }

    /// `out_k += scale_k Σ_j f_j sin(κ_k x_j)` for one block: the Woodbury correction's
    /// `a −= D⁻¹ Φᵀ g` in one pass (with `scale = −D⁻¹`).
    pub fn scatter_scaled(
        &self,
        f: &[f64],
        out: &mut [f64],
        scale: &[f64],
        sc: &mut SamplerScratch,
    ) {
        self.scatter_one(f, out, scale, sc);
        self.scatter_spread(f, 1, out, scale, sc);
    }

    fn scatter_pair(
        &self,
        f1: &[f64],
        f2: &[f64],
        o1: &mut [f64],
        o2: &mut [f64],
        sc: &mut SamplerScratch,
    ) {
        let p = self.period;
        for two in self.groups.chunks(2) {
            for (i, g) in two.iter().enumerate() {
                sc.buf.fill(Complex::new(0.0, 0.0));
                g.place::<false>(f1, &mut sc.buf);
                g.place::<true>(f2, &mut sc.buf);
                self.transform(sc);
                let bins = if i == 0 { &mut sc.cur } else { &mut sc.second };
                let (x, y) = bins[..4 * p].split_at_mut(2 * p);
                self.unpack(&sc.buf, x, Some(y));
            }
            match two {
                [g, h] => {
                    let tabs = [&g.sin_d[..], &g.cos_d, &h.sin_d, &h.cos_d];
                    let bins = [&sc.cur[..4 * p], &sc.second[..4 * p]];
                    kernels::unfold2x2(self.isa, bins, tabs, p, o1, o2);
                }
                [g] => kernels::unfold2(self.isa, &sc.cur[..4 * p], &g.sin_d, &g.cos_d, p, o1, o2),
                _ => unreachable!("chunks of one or two"),
            }
        }
        let nd = self.dense.len();
        let (fx, fy) = sc.dense_f[..2 * nd].split_at_mut(nd);
        for ((&j, x), y) in self.dense.iter().zip(fx.iter_mut()).zip(fy.iter_mut()) {
            (*x, *y) = (f1[j], f2[j]);
        }
        kernels::axpy2_rows(self.isa, &self.dense_rows, fx, fy, o1, o2);
    }

    fn scatter_one(&self, f: &[f64], out: &mut [f64], scale: &[f64], sc: &mut SamplerScratch) {
        let p = self.period;
        for pair in self.groups.chunks(2) {
            sc.buf.fill(Complex::new(0.0, 0.0));
            pair[0].place::<false>(f, &mut sc.buf);
            if let Some(g) = pair.get(1) {
                g.place::<true>(f, &mut sc.buf);
            }
            self.transform(sc);
            let y = (pair.len() == 2).then_some(&mut sc.second[..2 * p]);
            self.unpack(&sc.buf, &mut sc.cur[..2 * p], y);
            match pair {
                [g, h] => {
                    let tabs = [&g.sin_d[..], &g.cos_d, &h.sin_d, &h.cos_d];
                    let bins = [&sc.cur[..2 * p], &sc.second[..2 * p]];
                    kernels::unfold1x2(self.isa, bins, tabs, p, out, scale);
                }
                [g] => kernels::unfold1(
                    self.isa,
                    &sc.cur[..2 * p],
                    &g.sin_d,
                    &g.cos_d,
                    p,
                    out,
                    scale,
                ),
                _ => unreachable!("chunks of one or two"),
            }
        }
        for (&j, row) in self.dense_rows() {
            let fj = f[j];
            if fj != 0.0 {
                if scale.is_empty() {
                    kernels::axpy(self.isa, fj, row, out);
                } else {
                    for ((o, r), s) in out.iter_mut().zip(row).zip(scale) {
                        *o += s * fj * r;
                    }
                }
            }
        }
    }
}
