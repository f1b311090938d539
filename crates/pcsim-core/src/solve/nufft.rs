//! Point sines at arbitrary positions: a non-uniform fast sine transform (issue 21, item 4).
//!
//! The span-periodic sampler (`solve/sampler.rs`) folds the modes of points that share an
//! offset in the span. A line whose spans differ (real lines: shorter spans near structures,
//! dropper layouts scaled to each span) has points at arbitrary positions, and dense rows cost
//! `points × modes` per step. This transform evaluates
//!
//! ```text
//! w(x_p) = Σ_{m=1}^{N} q_m sin(m θ_p),   θ_p = π x_p / L      (gather)
//! Q_m   += Σ_p f_p sin(m θ_p)                                  (scatter, the exact transpose)
//! ```
//!
//! by gridding (the type-2 non-uniform FFT and its adjoint, as in FINUFFT: Barnett, Magland and
//! af Klinteberg, *SIAM J. Sci. Comput.* 41 (2019), with their "exponential of semicircle"
//! kernel `ψ(θ) = exp(β(√(1 − (θ/α)²) − 1))`, `|θ| < α`):
//! 1. **deconvolve**: `c_m = q_m / (2K ψ̂_m)`, `ψ̂_m` the kernel's Fourier coefficients (computed
//!    once by the trapezoidal rule, spectrally accurate since `ψ` vanishes to all orders at its
//!    edges, `e^{−β}`);
//! 2. **a sine transform** to the grid `θ_l = π l / K`: `g_l = Σ_m c_m sin(m θ_l)` (a DST-I of
//!    length `K − 1`, by the half-length algorithm: one complex FFT of length `K` for two blocks
//!    at once);
//! 3. **interpolate**: `w(x_p) = Σ_l g_l ψ(θ_p − θ_l)` over the `W` grid points nearest `θ_p`,
//!    the grid extended by its odd reflections at `0` and `π` (ghost cells), so every point's
//!    taps are one contiguous slice and each point costs one `W`-term dot product.
//!
//! With the grid oversampled at least twice (`K ≥ 2N + 2`, the size whose FFT is cheapest) and
//! `W = 14` taps (`β = 2.30 W`), the error is below `1e-13` of `Σ|q_m|` (measured in the tests
//! against the dense sum on random layouts: 8.2e-14).
//! The scatter runs the same steps transposed: spread, fold the ghosts back, the same DST-I
//! (symmetric), deconvolve. Cost: one FFT of length `K ≈ 2–2.3 N` per two blocks, `O(K)`
//! pre- and post-processing, and `W` multiply-adds per point and block, against `N` per point
//! and block for dense rows. No allocation in `gather`/`scatter_add`.
//!
//! Written here rather than taken from a crate: the pure-Rust NUFFTs found (the `nufft` modules
//! of `oxifft` and `scirs2-fft`) are general complex type-1/2/3 transforms whose calls return
//! newly allocated results, while the step must not allocate, its points are fixed (their taps are
//! computed once) and its series is a real sine series (the odd extension); both would also bring
//! a large dependency tree. This is a few hundred lines over `rustfft`, tested against the dense
//! sums.

use std::f64::consts::PI;
use std::sync::Arc;

use rustfft::num_complex::Complex;
use rustfft::{Fft, FftPlanner, FftPlannerScalar};

use crate::model::basis::SineBasis;
use crate::solve::kernels::{self, Isa};

/// Taps per point (the kernel's width in grid cells).
pub const TAPS: usize = 14;
/// The kernel's shape parameter for `TAPS` on a twice-oversampled grid (FINUFFT's `2.30 W`).
const BETA: f64 = 2.30 * TAPS as f64;
/// Ghost cells on each side of the grid: the taps reach `TAPS/2 + 1` cells past an end.
const GHOST: usize = TAPS / 2 + 2;

/// The grid size `K ≥ min` whose FFT is cheapest: `2^a`, `3·2^a` or `5·2^a` (`a ≥ 1`), by
/// `K log₂K` weighted 1, 1.05 and 1.1. Measured (callgrind, `rustfft`'s AVX plans, instructions
/// per transform over `K log₂K`): 2^a 1.97–2.13, 3·2^a 2.14–2.28, 5·2^a 2.12–2.26, and other
/// 5-smooth sizes 2.4–3.1 (3 600: 122.7 k, against 102.7 k for 4 096).
fn fft_friendly(min: usize) -> usize {
    let min = min.max(2);
    [(1usize, 1.0), (3, 1.05), (5, 1.1)]
        .iter()
        .map(|&(m, w)| {
            let mut k = 2 * m;
            while k < min {
                k *= 2;
            }
            (k, w * k as f64 * (k as f64).log2())
        })
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .map_or(min, |(k, _)| k)
}

/// The kernel `ψ(θ)` of half-width `alpha`.
fn kernel(theta: f64, alpha: f64) -> f64 {
    let z = theta / alpha;
    if z.abs() >= 1.0 {
        0.0
    } else {
        (BETA * ((1.0 - z * z).sqrt() - 1.0)).exp()
    }
}

/// Non-uniform sine transform of a fixed set of points on one [`SineBasis`].
#[derive(Clone)]
pub struct SineNufft {
    isa: Isa,
    n_modes: usize,
    /// Grid: `θ_l = π l / K`, `l = 0..=K`.
    k: usize,
    /// `1 / (2K ψ̂_m)`, `m = 1..=N` (index `m − 1`): the deconvolution.
    deconv: Vec<f64>,
    /// The gather's packing weights `(2 sin(πm/K) ± 1)/2 · deconv_m` (see
    /// [`Self::modes_to_grid`]).
    pack_plus: Vec<f64>,
    pack_minus: Vec<f64>,
    /// `sin(π j / K)`, `j = 0..=K/2`.
    sines: Vec<f64>,
    /// Per point: the first tap's index in the extended grid, and its `TAPS` weights.
    start: Vec<usize>,
    weights: Vec<f64>,
    fft: Arc<dyn Fft<f64>>,
    fft_scratch: usize,
}

impl std::fmt::Debug for SineNufft {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SineNufft")
            .field("n_modes", &self.n_modes)
            .field("grid", &self.k)
            .field("n_points", &self.start.len())
            .finish()
    }
}

/// Scratch for [`SineNufft`]: the complex FFT buffer and its scratch, the extended grids of two
/// blocks for the gather, and those of the scatter, which are zero between calls (each scatter
/// zeroes the cells it wrote, not the whole grid).
#[derive(Debug, Clone, Default)]
pub struct NufftScratch {
    buf: Vec<Complex<f64>>,
    fft: Vec<Complex<f64>>,
    grid: [Vec<f64>; 2],
    spread: [Vec<f64>; 2],
}

impl NufftScratch {
    /// Whether any buffer of `self` is larger than `o`'s.
    pub fn is_larger_than(&self, o: &NufftScratch) -> bool {
        self.buf.len() > o.buf.len()
            || self.fft.len() > o.fft.len()
            || self.grid[0].len() > o.grid[0].len()
    }

    /// The larger of two scratches, buffer by buffer.
    pub fn max(self, o: NufftScratch) -> NufftScratch {
        let g = self.grid[0].len().max(o.grid[0].len());
        NufftScratch {
            buf: vec![Complex::new(0.0, 0.0); self.buf.len().max(o.buf.len())],
            fft: vec![Complex::new(0.0, 0.0); self.fft.len().max(o.fft.len())],
            grid: [vec![0.0; g], vec![0.0; g]],
            spread: [vec![0.0; g], vec![0.0; g]],
        }
    }
}

impl SineNufft {
    /// Plan the transform of `basis`'s modes at the points `xs` (basis coordinates, in
    /// `[0, L]`).
    pub fn new(basis: &SineBasis, xs: &[f64], isa: Isa) -> Self {
        let n = basis.n_modes();
        let l = basis.length_m();
        let k = fft_friendly((2 * n + 2).max(2 * TAPS));
        let h = PI / k as f64;
        let alpha = 0.5 * TAPS as f64 * h;
        // ψ̂_m = (1/π) ∫₀^α ψ(θ) cos(mθ) dθ, by the trapezoidal rule (ψ(α) = 0 to e^{−β}).
        let nq = 64 * TAPS;
        let dq = alpha / nq as f64;
        let psi: Vec<f64> = (0..=nq).map(|i| kernel(i as f64 * dq, alpha)).collect();
        let deconv: Vec<f64> = (1..=n)
            .map(|m| {
                let mut s = 0.5 * psi[0];
                for (i, p) in psi.iter().enumerate().skip(1) {
                    s += p * (m as f64 * i as f64 * dq).cos();
                }
                let hat = s * dq / PI;
                1.0 / (2.0 * k as f64 * hat)
            })
            .collect();
        let sines: Vec<f64> = (0..=k / 2)
            .map(|j| (PI * j as f64 / k as f64).sin())
            .collect();
        let pack_plus = (1..=n).map(|m| (sines[m] + 0.5) * deconv[m - 1]).collect();
        let pack_minus = (1..=n).map(|m| (sines[m] - 0.5) * deconv[m - 1]).collect();
        let mut start = Vec::with_capacity(xs.len());
        let mut weights = Vec::with_capacity(xs.len() * TAPS);
        for &x in xs {
            let theta = PI * (x / l).clamp(0.0, 1.0);
            // The TAPS grid points within the kernel's reach, |θ − l h| < α = TAPS h/2:
            // l0 .. l0 + TAPS − 1 (in grid units, may be < 0 or > K: ghost cells).
            let l0 = (theta / h - 0.5 * TAPS as f64).floor() as i64 + 1;
            start.push((l0 + GHOST as i64) as usize);
            for t in 0..TAPS {
                let lt = l0 + t as i64;
                weights.push(kernel(theta - lt as f64 * h, alpha));
            }
        }
        let fft: Arc<dyn Fft<f64>> = match isa {
            Isa::Portable => FftPlannerScalar::new().plan_fft_inverse(k),
            Isa::X86V3 => FftPlanner::new().plan_fft_inverse(k),
        };
        let fft_scratch = fft.get_inplace_scratch_len();
        Self {
            isa,
            n_modes: n,
            k,
            deconv,
            pack_plus,
            pack_minus,
            sines,
            start,
            weights,
            fft,
            fft_scratch,
        }
    }

    /// Number of modes.
    pub fn n_modes(&self) -> usize {
        self.n_modes
    }

    /// Number of points.
    pub fn n_points(&self) -> usize {
        self.start.len()
    }

    /// Scratch sized for this transform.
    pub fn scratch(&self) -> NufftScratch {
        let g = self.k + 1 + 2 * GHOST;
        NufftScratch {
            buf: vec![Complex::new(0.0, 0.0); self.k],
            fft: vec![Complex::new(0.0, 0.0); self.fft_scratch],
            grid: [vec![0.0; g], vec![0.0; g]],
            spread: [vec![0.0; g], vec![0.0; g]],
        }
    }

    /// The Hermitian split of `z = FFT(y¹ + i y²)` (length `K`): `(Re Y¹_l, Im Y¹_l, Re Y²_l,
    /// Im Y²_l)` for `l = 1..K/2` (`Y¹ = (Z_l + conj Z_{K−l})/2`, `Y² = (Z_l − conj Z_{K−l})/2i`).
    fn split(z: &[Complex<f64>]) -> impl Iterator<Item = (f64, f64, f64, f64)> + '_ {
        let half = z.len() / 2;
        z[1..half]
            .iter()
            .zip(z[half + 1..].iter().rev())
            .map(|(z, zn)| {
                (
                    0.5 * (z.re + zn.re),
                    0.5 * (z.im - zn.im),
                    0.5 * (z.im + zn.im),
                    -0.5 * (z.re - zn.re),
                )
            })
    }

    /// The sine transform of one or two coefficient vectors onto the grid (step 2), the
    /// results in `grid[b][GHOST + l]`, `l = 0..=K`, with the odd ghost cells filled.
    ///
    /// Two half-length DST-I at once (Press et al., *Numerical Recipes*, §12.4, `sinft`): for
    /// two real sequences `f¹, f²` (`f_0 = 0`), from `z_j = y¹_j + i y²_j` with
    /// `y_j = sin(πj/K)(f_j + f_{K−j}) + ½(f_j − f_{K−j})`, one complex FFT of length `K` gives
    /// `Y_l = Σ_j y_j e^{2πijl/K}` of each ([`Self::split`]), and
    /// `F_l = Σ_{j=1}^{K−1} f_j sin(πjl/K)` follows as `F_{2l} = Im Y_l`,
    /// `F_{2l+1} = F_{2l−1} + Re Y_l`, `F_1 = ½ Re Y_0`. Half the FFT of the odd extension.
    fn modes_to_grid(&self, c: [Option<&[f64]>; 2], s: &mut NufftScratch) {
        let k = self.k;
        let n = self.n_modes;
        let NufftScratch { buf, fft, grid, .. } = s;
        let buf = &mut buf[..k];
        // The input is `f_m = c_m / (2K ψ̂_m)`, zero beyond N < K/2: so
        // `y_m = (sin(πm/K) + ½) f_m`, `y_{K−m} = (sin(πm/K) − ½) f_m` for `m ≤ N`, and zero
        // between (the only entries zeroed).
        buf[0] = Complex::new(0.0, 0.0);
        buf[n + 1..k - n].fill(Complex::new(0.0, 0.0));
        {
            let (lo, hi) = buf.split_at_mut(k - n);
            let pairs = lo[1..=n].iter_mut().zip(hi.iter_mut().rev());
            let w = self.pack_plus.iter().zip(&self.pack_minus);
            let zero = [0.0; 0];
            let (a, b) = (c[0].unwrap_or(&zero), c[1].unwrap_or(&zero));
            match (a.is_empty(), b.is_empty()) {
                (false, false) => {
                    for (((y, ny), (av, bv)), (wp, wm)) in pairs.zip(a.iter().zip(b)).zip(w) {
                        *y = Complex::new(av * wp, bv * wp);
                        *ny = Complex::new(av * wm, bv * wm);
                    }
                }
                (false, true) => {
                    for (((y, ny), av), (wp, wm)) in pairs.zip(a).zip(w) {
                        *y = Complex::new(av * wp, 0.0);
                        *ny = Complex::new(av * wm, 0.0);
                    }
                }
                (true, _) => {
                    for (((y, ny), bv), (wp, wm)) in pairs.zip(b).zip(w) {
                        *y = Complex::new(0.0, bv * wp);
                        *ny = Complex::new(0.0, bv * wm);
                    }
                }
            }
        }
        self.fft
            .process_with_scratch(buf, &mut fft[..self.fft_scratch]);
        let [g0, g1] = grid;
        let (g0, g1) = (&mut g0[..k + 1 + 2 * GHOST], &mut g1[..k + 1 + 2 * GHOST]);
        let (mut odd1, mut odd2) = (0.5 * buf[0].re, 0.5 * buf[0].im);
        g0[GHOST + 1] = odd1;
        g1[GHOST + 1] = odd2;
        let cells = g0[GHOST + 2..GHOST + k]
            .chunks_exact_mut(2)
            .zip(g1[GHOST + 2..GHOST + k].chunks_exact_mut(2));
        for ((c0, c1), (re1, im1, re2, im2)) in cells.zip(Self::split(buf)) {
            odd1 += re1;
            odd2 += re2;
            c0[0] = im1;
            c0[1] = odd1;
            c1[0] = im2;
            c1[1] = odd2;
        }
        for (b, g) in [g0, g1].into_iter().enumerate() {
            if c[b].is_none() {
                continue;
            }
            g[GHOST] = 0.0;
            g[GHOST + k] = 0.0;
            for j in 1..=GHOST {
                g[GHOST - j] = -g[GHOST + j];
                g[GHOST + k + j] = -g[GHOST + k - j];
            }
        }
    }

    /// The grids' sine transform back to the modes (the transpose of [`Self::modes_to_grid`]):
    /// ghosts folded into the grid, the same half-length DST-I (its own transpose),
    /// deconvolved and added to `out`.
    fn grid_to_modes(&self, out: [Option<&mut [f64]>; 2], s: &mut NufftScratch) {
        let k = self.k;
        let half = k / 2;
        // An unused block's grid is zero (the invariant of `NufftScratch::spread`).
        for (b, grid) in s.spread.iter_mut().enumerate() {
            let g = &mut grid[..k + 1 + 2 * GHOST];
            if out[b].is_none() {
                continue;
            }
            for j in 1..=GHOST {
                let lo = g[GHOST - j];
                g[GHOST + j] -= lo;
                let hi = g[GHOST + k + j];
                g[GHOST + k - j] -= hi;
            }
        }
        let NufftScratch {
            buf, fft, spread, ..
        } = s;
        let buf = &mut buf[..k];
        {
            // y_j and y_{K−j} from G_j and G_{K−j}, j = 1..K/2; the middle one is 2 G_{K/2}.
            let g0 = &spread[0][GHOST..=GHOST + k];
            let g1 = &spread[1][GHOST..=GHOST + k];
            let (lo, hi) = buf[1..].split_at_mut(half - 1);
            hi[0] = Complex::new(2.0 * g0[half], 2.0 * g1[half]);
            let sides = lo.iter_mut().zip(hi[1..].iter_mut().rev());
            let gl = g0[1..half].iter().zip(g1[1..half].iter());
            let gr = g0[half + 1..k]
                .iter()
                .rev()
                .zip(g1[half + 1..k].iter().rev());
            for ((((y, ny), (a, b)), (an, bn)), sj) in
                sides.zip(gl).zip(gr).zip(&self.sines[1..half])
            {
                let (sa, da) = (sj * (a + an), 0.5 * (a - an));
                let (sb, db) = (sj * (b + bn), 0.5 * (b - bn));
                *y = Complex::new(sa + da, sb + db);
                *ny = Complex::new(sa - da, sb - db);
            }
        }
        buf[0] = Complex::new(0.0, 0.0);
        self.fft
            .process_with_scratch(buf, &mut fft[..self.fft_scratch]);
        let n = self.n_modes;
        let d = &self.deconv;
        for (b, o) in out.into_iter().enumerate() {
            let Some(o) = o else { continue };
            let pick = |t: (f64, f64, f64, f64)| if b == 0 { (t.0, t.1) } else { (t.2, t.3) };
            let mut odd = 0.5 * if b == 0 { buf[0].re } else { buf[0].im };
            o[0] += odd * d[0];
            let pairs = o[1..n].chunks_mut(2).zip(d[1..n].chunks(2));
            for ((oc, dc), t) in pairs.zip(Self::split(buf)) {
                let (re, im) = pick(t);
                oc[0] += im * dc[0];
                odd += re;
                if let (Some(ov), Some(dv)) = (oc.get_mut(1), dc.get(1)) {
                    *ov += odd * dv;
                }
            }
        }
    }

    /// `out[b·P + p] = Σ_m q[b·N + m] sin(κ_m x_p)` for the `nb` blocks of `q`.
    pub fn gather(&self, q: &[f64], nb: usize, out: &mut [f64], s: &mut NufftScratch) {
        let (n, np) = (self.n_modes, self.n_points());
        let mut b = 0;
        while b < nb {
            let two = b + 1 < nb;
            let c0 = &q[b * n..(b + 1) * n];
            let c1 = two.then(|| &q[(b + 1) * n..(b + 2) * n]);
            self.modes_to_grid([Some(c0), c1], s);
            for (j, blk) in (b..b + 1 + two as usize).enumerate() {
                let g = &s.grid[j];
                let o = &mut out[blk * np..(blk + 1) * np];
                for (p, op) in o.iter_mut().enumerate() {
                    let st = self.start[p];
                    *op = kernels::dot(
                        self.isa,
                        &g[st..st + TAPS],
                        &self.weights[p * TAPS..(p + 1) * TAPS],
                    );
                }
            }
            b += 2;
        }
    }

    /// `q[b·N + m] += Σ_p f[b·P + p] sin(κ_m x_p)` for the `nb` blocks (the transpose of
    /// [`Self::gather`]).
    pub fn scatter_add(&self, f: &[f64], nb: usize, q: &mut [f64], s: &mut NufftScratch) {
        let (n, np) = (self.n_modes, self.n_points());
        let mut b = 0;
        while b < nb {
            let two = b + 1 < nb;
            for (j, blk) in (b..b + 1 + two as usize).enumerate() {
                let g = &mut s.spread[j][..self.k + 1 + 2 * GHOST];
                let fb = &f[blk * np..(blk + 1) * np];
                for (p, fp) in fb.iter().enumerate() {
                    let st = self.start[p];
                    kernels::axpy(
                        self.isa,
                        *fp,
                        &self.weights[p * TAPS..(p + 1) * TAPS],
                        &mut g[st..st + TAPS],
                    );
                }
            }
            let (q0, rest) = q[b * n..].split_at_mut(n);
            let q1 = two.then(|| &mut rest[..n]);
            self.grid_to_modes([Some(q0), q1], s);
            // Back to zero: the taps' cells, and the `2·GHOST + 1` cells at each end, which
            // hold every cell the ghosts were folded into.
            let ends = 2 * GHOST + 1;
            for g in s.spread.iter_mut().take(1 + two as usize) {
                let g = &mut g[..self.k + 1 + 2 * GHOST];
                for &st in &self.start {
                    g[st..st + TAPS].fill(0.0);
                }
                let len = g.len();
                g[..ends].fill(0.0);
                g[len - ends..].fill(0.0);
            }
            b += 2;
        }
    }
}
