//! Point terms of a block's system matrix taken implicitly: `A = D + Φᵀ W Φ` with `D` the
//! diagonal modal part (`M + Δt/2 C`) and `W = diag(w_j)` (a point mass, or Δt/2 × a point
//! damper). `A⁻¹` is applied with the Woodbury identity,
//! `A⁻¹ r = z − D⁻¹ Φᵀ (W⁻¹ + Φ D⁻¹ Φᵀ)⁻¹ Φ z`, `z = D⁻¹ r`, with a Cholesky factor of the small
//! capacitance matrix computed once.

use crate::linalg::{cholesky_in_place, cholesky_solve, NotPositiveDefinite};
use crate::model::basis::SineBasis;
use crate::solve::sampler::{PointSampler, SamplerScratch};

/// The implicit point terms of one block.
#[derive(Debug, Clone)]
pub struct ImplicitPoints {
    sampler: PointSampler,
    chol: Vec<f64>,
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
    /// Scratch for up to `np` points and `n` modes.
    pub fn new(np: usize, n: usize) -> Self {
        Self {
            g: vec![0.0; np],
            y: vec![0.0; np],
            tmp: vec![0.0; n],
        }
    }
}

impl ImplicitPoints {
    /// `points`: (position in the basis' coordinates, weight w_j > 0); `None` when there are
    /// none. An error when the capacitance matrix is not positive definite (it always is for
    /// positive weights; a failure means a degenerate input, never silently clamped).
    pub fn new(
        basis: &SineBasis,
        span_m: Option<f64>,
        d: &[f64],
        points: &[(f64, f64)],
    ) -> Result<Option<Self>, NotPositiveDefinite> {
        let np = points.len();
        if np == 0 {
            return Ok(None);
        }
        let n = basis.n_modes();
        let mut rows = vec![vec![0.0; n]; np];
        for (r, p) in rows.iter_mut().zip(points) {
            basis.fill_sines(p.0, r);
        }
        let mut cap = vec![0.0; np * np];
        for i in 0..np {
            for j in 0..=i {
                let mut s = 0.0;
                for k in 0..n {
                    s += rows[i][k] * rows[j][k] / d[k];
                }
                cap[i * np + j] = s;
                cap[j * np + i] = s;
            }
            cap[i * np + i] += 1.0 / points[i].1;
        }
        cholesky_in_place(&mut cap, np)?;
        let xs: Vec<f64> = points.iter().map(|p| p.0).collect();
        Ok(Some(Self {
            sampler: PointSampler::new(basis, &xs, span_m),
            chol: cap,
            np,
        }))
    }

    /// Number of points.
    pub fn n_points(&self) -> usize {
        self.np
    }

    /// The sampler over the points (its scratch size matters to the workspace).
    pub fn sampler(&self) -> &PointSampler {
        &self.sampler
    }

    /// Turn `z = D⁻¹ r` (in `a`) into `A⁻¹ r`.
    pub fn correct(
        &self,
        a: &mut [f64],
        d_inv: &[f64],
        scr: &mut SamplerScratch,
        w: &mut ImplicitScratch,
    ) {
        let np = self.np;
        let (g, y) = (&mut w.g[..np], &mut w.y[..np]);
        let tmp = &mut w.tmp[..a.len()];
        self.sampler.gather(a, 1, g, scr);
        cholesky_solve(&self.chol, np, g, y);
        tmp.fill(0.0);
        self.sampler.scatter_add(g, 1, tmp, scr);
        for ((ai, di), t) in a.iter_mut().zip(d_inv).zip(tmp.iter()) {
            *ai -= di * t;
        }
    }
}
