//! Vibration-energy density along the catenary (paper Eq. 20, made consistent with Eqs. 1–4).
//!
//! For each wire, with the deviation `u` from the static shape (README §2.4):
//!
//! ```text
//! E(x) = ½ ρA u̇² + ½ T u'² + ½ EI u''²      (+ ½ ρA ż² + ½ T z'² + ½ EI z''² + ½ ρI φ̇² + ½ GIp φ'²)
//! ```
//!
//! summed over messenger and contact wire, in J/m. Deviations from the printed Eq. 20 (README
//! §2.3): every term carries ½ and the torsional strain uses φ' (as Eq. 3), not φ''. The lateral
//! and torsional terms are part of the definition but zero here: the model does not excite them
//! (no lateral or torsional series is built yet). `ρA` is the wire's dynamic mass per metre (clamps
//! smeared in), so that ∫E dx is exactly the wires' modal energy ½Σ(m_k v_k² + k_k q_k²).
//!
//! The sums `Σ c_k sin(κ_k x_j)` and `Σ c_k cos(κ_k x_j)` on the uniform grid `x_j = j L / M`
//! are one inverse FFT of length `2M` each (exact, not an approximation, for `N < 2M`); the
//! derivatives are taken analytically on the coefficients (`κ_k q_k`, `−κ_k² q_k`).

use std::sync::Arc;

use rustfft::num_complex::Complex;
use rustfft::{Fft, FftPlanner};

use crate::model::{Model, Wire};
use crate::solver::State;

/// Evaluator of the energy density on a uniform grid over the whole model.
pub struct DensityGrid {
    m: usize,
    dx: f64,
    n: usize,
    kappa: Vec<f64>,
    fft: Arc<dyn Fft<f64>>,
    buf: Vec<Complex<f64>>,
    scratch: Vec<Complex<f64>>,
    tmp: [Vec<f64>; 3],
}

impl DensityGrid {
    /// A grid with `points_per_mode` intervals per mode (at least 2 so that the highest mode's
    /// energy density is resolved).
    pub fn new(model: &Model, points_per_mode: usize) -> Self {
        let n = model.basis.n_modes();
        let m = (points_per_mode.max(2)) * n;
        let fft = FftPlanner::new().plan_fft_inverse(2 * m);
        let scratch = vec![Complex::new(0.0, 0.0); fft.get_inplace_scratch_len()];
        Self {
            m,
            dx: model.basis.length_m() / m as f64,
            n,
            kappa: (0..n).map(|i| model.basis.wavenumber(i)).collect(),
            fft,
            buf: vec![Complex::new(0.0, 0.0); 2 * m],
            scratch,
            tmp: [vec![0.0; m + 1], vec![0.0; m + 1], vec![0.0; m + 1]],
        }
    }

    /// Grid spacing, m.
    pub fn dx(&self) -> f64 {
        self.dx
    }

    /// Number of grid points (`M + 1`, from x = 0 to x = L).
    pub fn n_points(&self) -> usize {
        self.m + 1
    }

    /// `X_j = Σ_k c_k e^{iπkj/M}`: real part the cosine sum, imaginary part the sine sum.
    fn transform(&mut self, coeff: impl Fn(usize) -> f64) {
        self.buf.fill(Complex::new(0.0, 0.0));
        for i in 0..self.n {
            self.buf[i + 1] = Complex::new(coeff(i), 0.0);
        }
        self.fft
            .process_with_scratch(&mut self.buf, &mut self.scratch);
    }

    fn add_wire(&mut self, w: &Wire, q: &[f64], v: &[f64], out: &mut [f64]) {
        let k = self.kappa.clone();
        self.transform(|i| v[i]);
        for j in 0..=self.m {
            self.tmp[0][j] = self.buf[j].im; // u̇ (sine series)
        }
        self.transform(|i| q[i] * k[i]);
        for j in 0..=self.m {
            self.tmp[1][j] = self.buf[j].re; // u' (cosine series)
        }
        self.transform(|i| -q[i] * k[i] * k[i]);
        for j in 0..=self.m {
            self.tmp[2][j] = self.buf[j].im; // u'' (sine series)
        }
        let (rho, t, ei) = (w.mass_per_m_kg, w.tension_n, w.ei_nm2);
        for j in 0..=self.m {
            let (ud, u1, u2) = (self.tmp[0][j], self.tmp[1][j], self.tmp[2][j]);
            out[j] += 0.5 * (rho * ud * ud + t * u1 * u1 + ei * u2 * u2);
        }
    }

    /// Energy density at the grid points `x_j = j·dx`, J/m, both wires (Eq. 20, consistent form).
    pub fn density(&mut self, model: &Model, st: &State, out: &mut [f64]) {
        out.fill(0.0);
        self.add_wire(&model.messenger, &st.qm, &st.vm, out);
        self.add_wire(&model.contact, &st.qc, &st.vc, out);
    }
}

/// Trapezoid integral of grid values with spacing `dx`.
pub fn integrate(values: &[f64], dx: f64) -> f64 {
    if values.len() < 2 {
        return 0.0;
    }
    dx * (values.iter().sum::<f64>() - 0.5 * (values[0] + values[values.len() - 1]))
}

/// Modal energy of both wires, ½Σ(m_k v_k² + k_k q_k²), J (the exact integral of the density).
pub fn modal_energy(model: &Model, st: &State) -> f64 {
    let mut e = 0.0;
    for (w, q, v) in [
        (&model.messenger, &st.qm, &st.vm),
        (&model.contact, &st.qc, &st.vc),
    ] {
        for i in 0..q.len() {
            e += 0.5 * (w.vertical.mass[i] * v[i] * v[i] + w.vertical.stiffness[i] * q[i] * q[i]);
        }
    }
    e
}
