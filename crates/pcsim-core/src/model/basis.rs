//! Sine-series (modal) basis of a wire simply supported at both ends of the modelled length
//! (paper Eqs. 5–8; README §1).
//!
//! A wire's deviation from its static shape is `w(x, t) = Σ_k q_k(t) sin(κ_k x)` with
//! `κ_k = kπ/L`, `k = 1..=N`. Mode `k` is stored at index `k − 1`.
//!
//! The same basis serves every motion direction: the paper's lateral (`z`) and torsional (`φ`)
//! series use the same trial functions with other mass and stiffness coefficients (Eqs. 11–14), so
//! they are further [`crate::model::wire::ModalSeries`] over the same trial functions.

use std::f64::consts::PI;

use crate::linalg::dot;

/// How often the rotation recurrence is re-seeded from direct `sin_cos` calls (bounds the
/// rounding drift of the recurrence to ~`RESEED · ε`).
pub const RESEED: usize = 64;

/// The seeds of [`SineBasis::fill_sines`]'s four chains: `(sin, cos)` of `(1 + l) θ`,
/// `l = 0..4`, each a direct `sin_cos` (the last is the chains' step, `4θ`).
#[inline]
pub fn chain_seeds(theta: f64) -> ([f64; 4], [f64; 4]) {
    let (mut s, mut c) = ([0.0; 4], [0.0; 4]);
    for l in 0..4 {
        (s[l], c[l]) = ((1 + l) as f64 * theta).sin_cos();
    }
    (s, c)
}

/// The turn that carries the chains' seeds to block `b` of [`SineBasis::fill_sines`] (modes
/// `4 · RESEED · b + 1 + l`): `(sin, cos)` of `4 · RESEED · b · θ`, one direct `sin_cos` per block
/// (the seeds are `e^{i(1+l)θ}` turned by it: `s c_b + c s_b`, `c c_b − s s_b`). The error stays
/// that of a direct call at every block: no block's seed is carried from the one before.
#[inline]
pub fn block_turn(theta: f64, b: usize) -> (f64, f64) {
    ((4 * RESEED * b) as f64 * theta).sin_cos()
}

/// The trial functions `sin(kπx/L)`, `k = 1..=N`, over a modelled length `L`.
#[derive(Debug, Clone, PartialEq)]
pub struct SineBasis {
    length_m: f64,
    n_modes: usize,
}

impl SineBasis {
    /// A basis of `n_modes` sine modes over `[0, length_m]`.
    pub fn new(length_m: f64, n_modes: usize) -> Self {
        assert!(
            length_m > 0.0 && n_modes > 0,
            "SineBasis needs L > 0 and N > 0"
        );
        Self { length_m, n_modes }
    }

    /// Modelled length `L` in metres.
    pub fn length_m(&self) -> f64 {
        self.length_m
    }

    /// Number of modes `N`.
    pub fn n_modes(&self) -> usize {
        self.n_modes
    }

    /// Wavenumber `κ = kπ/L` of the mode stored at `index` (mode number `k = index + 1`), rad/m.
    pub fn wavenumber(&self, index: usize) -> f64 {
        (index + 1) as f64 * PI / self.length_m
    }

    /// Frequency in Hz of the highest mode of a tensioned beam with this basis.
    pub fn max_frequency_hz(&self, tension_n: f64, ei_nm2: f64, mass_per_m_kg: f64) -> f64 {
        let k = self.wavenumber(self.n_modes - 1);
        k * ((tension_n + ei_nm2 * k * k) / mass_per_m_kg).sqrt() / (2.0 * PI)
    }

    /// Fill `out[i] = sin(κ_i x)` for all modes, without a trig call per mode: the complex
    /// rotation `e^{i(k+4)θ} = e^{ikθ} e^{i4θ}` in four interleaved chains (modes k, k+1, k+2,
    /// k+3; they break the latency chain of a single recurrence), re-seeded every `4 · RESEED`
    /// modes from [`chain_seeds`] (the recurrence the issue suggests for the moving contact point).
    pub fn fill_sines(&self, x: f64, out: &mut [f64]) {
        debug_assert_eq!(out.len(), self.n_modes);
        let theta = self.theta(x);
        let (s0, c0) = chain_seeds(theta);
        let (s4, c4) = (s0[3], c0[3]);
        for (b, block) in out.chunks_mut(4 * RESEED).enumerate() {
            let (mut s, mut c) = (s0, c0);
            if b > 0 {
                let (sb, cb) = block_turn(theta, b);
                for l in 0..4 {
                    s[l] = s0[l] * cb + c0[l] * sb;
                    c[l] = c0[l] * cb - s0[l] * sb;
                }
            }
            let mut chunks = block.chunks_exact_mut(4);
            for chunk in &mut chunks {
                for l in 0..4 {
                    chunk[l] = s[l];
                    let sn = s[l] * c4 + c[l] * s4;
                    c[l] = c[l] * c4 - s[l] * s4;
                    s[l] = sn;
                }
            }
            for (l, o) in chunks.into_remainder().iter_mut().enumerate() {
                *o = s[l];
            }
        }
    }

    /// The first mode's phase at `x`, `θ = π x / L` (mode `i` has `(i + 1) θ`).
    #[inline]
    pub fn theta(&self, x: f64) -> f64 {
        PI * x / self.length_m
    }

    /// Fill `sin_out[i] = sin(κ_i x)` and `cos_out[i] = cos(κ_i x)`.
    pub fn fill_sines_cosines(&self, x: f64, sin_out: &mut [f64], cos_out: &mut [f64]) {
        let theta = PI * x / self.length_m;
        let (s1, c1) = theta.sin_cos();
        let mut i = 0;
        while i < self.n_modes {
            let (mut s, mut c) = ((i + 1) as f64 * theta).sin_cos();
            let end = (i + RESEED).min(self.n_modes);
            for j in i..end {
                sin_out[j] = s;
                cos_out[j] = c;
                let sn = s * c1 + c * s1;
                c = c * c1 - s * s1;
                s = sn;
            }
            i = end;
        }
    }

    /// `w(x) = Σ q_k sin(κ_k x)` (Eq. 5), using `scratch` (length N) for the sines.
    pub fn eval(&self, q: &[f64], x: f64, scratch: &mut [f64]) -> f64 {
        self.fill_sines(x, scratch);
        dot(q, scratch)
    }

    /// Value, slope and curvature `(w, w', w'')` at `x` (Eq. 8), derivatives taken analytically.
    pub fn eval_derivatives(&self, q: &[f64], x: f64, s: &mut [f64], c: &mut [f64]) -> [f64; 3] {
        self.fill_sines_cosines(x, s, c);
        let mut w = 0.0;
        let mut w1 = 0.0;
        let mut w2 = 0.0;
        for i in 0..self.n_modes {
            let k = self.wavenumber(i);
            w += q[i] * s[i];
            w1 += q[i] * k * c[i];
            w2 -= q[i] * k * k * s[i];
        }
        [w, w1, w2]
    }
}
