//! Point terms of a block's system matrix taken implicitly: `A = D + Φᵀ W Φ` with `D` the
//! diagonal modal part (`M + Δt/2 C`) and `W = diag(w_j)` (a point mass, or Δt/2 × a point
//! damper). `A⁻¹` is applied with the Woodbury identity,
//! `A⁻¹ r = z − D⁻¹ Φᵀ (W⁻¹ + Φ D⁻¹ Φᵀ)⁻¹ Φ z`, `z = D⁻¹ r`, with a Cholesky factor of the small
//! capacitance matrix computed once.
//!
//! Blocks whose implicit points sit at the same positions (the messenger's support dampers and
//! the contact wire's steady-arm masses are both at the masts) are corrected together: one
//! gather for all of them, a solve per block, and the scatter fused with the scaling by `−D⁻¹`.

use crate::linalg::{cholesky_in_place, NotPositiveDefinite};
use crate::model::basis::SineBasis;
use crate::solve::kernels::{self, Isa};
use crate::solve::sampler::{PointSampler, SamplerScratch};

/// The implicit point terms of one or more contiguous blocks sharing their points.
#[derive(Debug, Clone)]
pub struct ImplicitPoints {
    sampler: PointSampler,
    /// Start of the first block in the modal state, and the block length.
    q_off: usize,
    n: usize,
    /// Cholesky factor of each block's capacitance matrix.
    chol: Vec<Vec<f64>>,
    np: usize,
}

/// Scratch of [`ImplicitPoints::correct`].
#[derive(Debug, Clone, Default)]
pub struct ImplicitScratch {
    g: Vec<f64>,
    y: Vec<f64>,
    tmp: Vec<f64>,
}

impl ImplicitScratch {
    /// Scratch for up to `blocks` blocks of `np` points and `n` modes.
    pub fn new(blocks: usize, np: usize, n: usize) -> Self {
        Self {
            g: vec![0.0; blocks * np],
            y: vec![0.0; np],
            tmp: vec![0.0; n],
        }
    }
}

impl ImplicitPoints {
    /// The terms of `weights.len()` contiguous blocks starting at `q_off` in the state, all over
    /// `basis`, with their points at `xs` (basis coordinates) and per block the weights `w_j > 0`
    /// and the diagonal `d` (`M + Δt/2 C`). An error when a capacitance matrix is not positive
    /// definite (it always is for positive weights; a failure means a degenerate input, never
    /// silently clamped).
    pub fn new(
        basis: &SineBasis,
        span_m: Option<f64>,
        isa: Isa,
        q_off: usize,
        xs: &[f64],
        weights: &[Vec<f64>],
        d: &[&[f64]],
    ) -> Result<Self, NotPositiveDefinite> {
        let np = xs.len();
        let n = basis.n_modes();
        // Φ transposed: row k holds mode k at every point.
        let mut rows_t = vec![0.0; n * np];
        let mut row = vec![0.0; n];
        for (i, &x) in xs.iter().enumerate() {
            basis.fill_sines(x, &mut row);
            for (k, &v) in row.iter().enumerate() {
                rows_t[k * np + i] = v;
            }
        }
        let mut chol = Vec::with_capacity(weights.len());
        for (w, d) in weights.iter().zip(d) {
            let mut cap = vec![0.0; np * np];
            kernels::capacitance(isa, &rows_t, np, &d[..n], &mut cap);
            for i in 0..np {
                for j in 0..i {
                    cap[j * np + i] = cap[i * np + j];
                }
                cap[i * np + i] += 1.0 / w[i];
            }
            cholesky_in_place(&mut cap, np)?;
            chol.push(cap);
        }
        Ok(Self {
            sampler: PointSampler::new(basis, xs, span_m, isa),
            q_off,
            n,
            chol,
            np,
        })
    }

    /// Number of points.
    pub fn n_points(&self) -> usize {
        self.np
    }

    /// Number of blocks corrected together.
    pub fn n_blocks(&self) -> usize {
        self.chol.len()
    }

    /// The sampler over the points (its scratch size matters to the workspace).
    pub fn sampler(&self) -> &PointSampler {
        &self.sampler
    }

    /// Turn `z = D⁻¹ r` (in the modal accelerations `a`, the whole state vector) into `A⁻¹ r`;
    /// `neg_d_inv` is `−D⁻¹` over the whole state.
    pub fn correct(
        &self,
        a: &mut [f64],
        base: usize,
        neg_d_inv: &[f64],
        scr: &mut SamplerScratch,
        w: &mut ImplicitScratch,
    ) {
        let (np, n, k) = (self.np, self.n, self.chol.len());
        let q0 = self.q_off - base;
        let isa = self.sampler.isa();
        let g = &mut w.g[..k * np];
        self.sampler.gather(&a[q0..q0 + k * n], k, g, scr);
        for (b, l) in self.chol.iter().enumerate() {
            let gb = &mut g[b * np..(b + 1) * np];
            kernels::cholesky_solve(isa, l, np, gb, &mut w.y[..np]);
            let r = q0 + b * n..q0 + (b + 1) * n;
            let d = &neg_d_inv[base + r.start..base + r.end];
            if self.sampler.is_single_group() {
                self.sampler.scatter_scaled(gb, &mut a[r], d, scr);
            } else {
                let tmp = &mut w.tmp[..n];
                tmp.fill(0.0);
                self.sampler.scatter_add(gb, 1, tmp, scr);
                for ((ai, di), t) in a[r].iter_mut().zip(d).zip(tmp.iter()) {
                    *ai += di * t;
                }
            }
        }
    }

    /// The modal coordinates this term corrects (its blocks, contiguous).
    pub fn modal_range(&self) -> std::ops::Range<usize> {
        self.q_off..self.q_off + self.chol.len() * self.n
    }
}
