//! Vibration-energy density along the catenary (paper Eq. 20, made consistent with Eqs. 1–4).
//!
//! For each wire, with the deviation `u` from the static shape (README §2.4):
//!
//! ```text
//! E(x) = ½ ρA u̇² + ½ T u'² + ½ EI u''²      (+ ½ ρA ż² + ½ T z'² + ½ EI z''² + ½ ρI φ̇² + ½ GIp φ'²)
//! ```
//!
//! summed over every wire and every modelled direction, in J/m. Deviations from the printed Eq. 20
//! (README §2.3): every term carries ½ and the torsional strain uses φ' (as Eq. 3), not φ''. The
//! coefficients of each block are [`crate::model::Wire::coefficients`], the same that build the
//! modal matrices: `ρA` is the wire's dynamic mass per metre (clamps smeared in), so that ∫E dx is
//! exactly the wires' modal energy ½Σ(m_k v_k² + k_k q_k²).
//!
//! The sums `Σ c_k sin(κ_k x_j)` and `Σ c_k cos(κ_k x_j)` on the uniform grid `x_j = j L / M`
//! are one inverse FFT of length `2M` each (exact, not an approximation, for `N < 2M`); the
//! derivatives are taken analytically on the coefficients (`κ_k q_k`, `−κ_k² q_k`).

use std::sync::Arc;

use rustfft::num_complex::Complex;
use rustfft::{Fft, FftPlanner};

use crate::error::CaseError;
use crate::model::basis::SineBasis;
use crate::model::wire::Coefficients;
use crate::model::{Model, PantographKind};
use crate::solve::{CompiledModel, State, Workspace};

/// Evaluator of the energy density on a uniform grid over one basis group: the whole model
/// ([`DensityGrid::new`]), or one tension length of a line ([`DensityGrid::per_group`]).
pub struct DensityGrid {
    m: usize,
    dx: f64,
    /// Model coordinate of the grid's x = 0, m.
    origin_m: f64,
    /// The blocks (wires and directions) whose density it sums, in state order.
    blocks: Vec<usize>,
    basis: SineBasis,
    kappa: Vec<f64>,
    fft: Arc<dyn Fft<f64>>,
    buf: Vec<Complex<f64>>,
    scratch: Vec<Complex<f64>>,
    tmp: [Vec<f64>; 3],
}

/// `X_j = Σ_k c_k e^{iπkj/M}` into `buf`: real part the cosine sum, imaginary part the sine sum.
fn transform(
    fft: &Arc<dyn Fft<f64>>,
    buf: &mut [Complex<f64>],
    scratch: &mut [Complex<f64>],
    n: usize,
    coeff: impl Fn(usize) -> f64,
) {
    buf.fill(Complex::new(0.0, 0.0));
    for i in 0..n {
        buf[i + 1] = Complex::new(coeff(i), 0.0);
    }
    fft.process_with_scratch(buf, scratch);
}

impl DensityGrid {
    /// A grid with `points_per_mode` intervals per mode (at least 2 so that the highest mode's
    /// energy density is resolved). Every block must share one sine basis from x = 0 (a wire with
    /// another extent would need its own grid).
    pub fn new(model: &Model, points_per_mode: usize) -> Result<Self, CaseError> {
        let lay = &model.layout;
        let g = lay.groups.first().ok_or_else(|| CaseError::Invalid {
            field: "model".into(),
            value: "no wire".into(),
            reason: "the energy density needs at least one wire".into(),
        })?;
        if lay.groups.len() > 1 || g.origin_m != 0.0 {
            return Err(CaseError::Invalid {
                field: "model".into(),
                value: format!("{} basis groups", lay.groups.len()),
                reason: "one density grid needs every wire over the whole model (a [line] of several tension lengths has its own wires per tension length: take a grid per tension length, DensityGrid::per_group)".into(),
            });
        }
        Ok(Self::of_group(model, 0, points_per_mode))
    }

    /// One grid per basis group (a line's tension lengths, each over its own wires' extent from
    /// its origin): the density of the whole model is their sum where they overlap, and each
    /// wire's energy is taken on its own basis.
    pub fn per_group(model: &Model, points_per_mode: usize) -> Result<Vec<Self>, CaseError> {
        if model.layout.groups.is_empty() {
            return Err(CaseError::Invalid {
                field: "model".into(),
                value: "no wire".into(),
                reason: "the energy density needs at least one wire".into(),
            });
        }
        Ok((0..model.layout.groups.len())
            .map(|g| Self::of_group(model, g, points_per_mode))
            .collect())
    }

    fn of_group(model: &Model, group: usize, points_per_mode: usize) -> Self {
        let g = &model.layout.groups[group];
        let n = g.basis.n_modes();
        let m = (points_per_mode.max(2)) * n;
        let fft = FftPlanner::new().plan_fft_inverse(2 * m);
        let scratch = vec![Complex::new(0.0, 0.0); fft.get_inplace_scratch_len()];
        Self {
            m,
            dx: g.basis.length_m() / m as f64,
            origin_m: g.origin_m,
            blocks: g.blocks.clone(),
            kappa: (0..n).map(|i| g.basis.wavenumber(i)).collect(),
            basis: g.basis.clone(),
            fft,
            buf: vec![Complex::new(0.0, 0.0); 2 * m],
            scratch,
            tmp: [vec![0.0; m + 1], vec![0.0; m + 1], vec![0.0; m + 1]],
        }
    }

    /// Model coordinate of the grid's first point, m.
    pub fn origin_m(&self) -> f64 {
        self.origin_m
    }

    /// Grid spacing, m.
    pub fn dx(&self) -> f64 {
        self.dx
    }

    /// Number of grid points (`M + 1`, from x = 0 to x = L).
    pub fn n_points(&self) -> usize {
        self.m + 1
    }

    /// Add one block's density `½ (mass u̇² + slope u'² + bending u''²)` (Eq. 20, consistent
    /// form) to `out`, of the modal displacements `q(i)` and velocities `v(i)`.
    fn add_block(
        &mut self,
        c: Coefficients,
        q: impl Fn(usize) -> f64,
        v: impl Fn(usize) -> f64,
        out: &mut [f64],
    ) {
        let n = self.basis.n_modes();
        let k = &self.kappa;
        transform(&self.fft, &mut self.buf, &mut self.scratch, n, &v);
        for j in 0..=self.m {
            self.tmp[0][j] = self.buf[j].im; // u̇ (sine series)
        }
        transform(&self.fft, &mut self.buf, &mut self.scratch, n, |i| {
            q(i) * k[i]
        });
        for j in 0..=self.m {
            self.tmp[1][j] = self.buf[j].re; // u' (cosine series)
        }
        transform(&self.fft, &mut self.buf, &mut self.scratch, n, |i| {
            -q(i) * k[i] * k[i]
        });
        for j in 0..=self.m {
            self.tmp[2][j] = self.buf[j].im; // u'' (sine series)
        }
        for j in 0..=self.m {
            let (ud, u1, u2) = (self.tmp[0][j], self.tmp[1][j], self.tmp[2][j]);
            out[j] += 0.5 * (c.mass * ud * ud + c.slope * u1 * u1 + c.bending * u2 * u2);
        }
    }

    /// Energy density at the grid points `x_j = origin + j·dx`, J/m, every wire and direction of
    /// the grid's group (Eq. 20, consistent form), of the deviation from the design's static
    /// shape.
    pub fn density(&mut self, model: &Model, st: &State, out: &mut [f64]) {
        self.density_about(model, st, None, out);
    }

    /// [`DensityGrid::density`] of the vibration about `reference` (the static state under
    /// steady loads, or a twin run without the pantographs in a turbulent wind): the density of
    /// `st − reference` in every modal coordinate and velocity. `None`: about the design's static
    /// shape (the same numbers as [`DensityGrid::density`]).
    pub fn density_about(
        &mut self,
        model: &Model,
        st: &State,
        reference: Option<&State>,
        out: &mut [f64],
    ) {
        out.fill(0.0);
        for bi in 0..self.blocks.len() {
            let b = self.blocks[bi];
            let key = model.layout.blocks[b].key;
            let c = model.wires[key.wire].coefficients(key.dir);
            let r = model.layout.range(b);
            let (q, v) = (&st.modal.u[r.clone()], &st.modal.v[r.clone()]);
            match reference {
                None => self.add_block(c, |i| q[i], |i| v[i], out),
                Some(s0) => {
                    let (q0, v0) = (&s0.modal.u[r.clone()], &s0.modal.v[r]);
                    self.add_block(c, |i| q[i] - q0[i], |i| v[i] - v0[i], out)
                }
            }
        }
    }
}

/// Trapezoid integral of grid values with spacing `dx`.
pub fn integrate(values: &[f64], dx: f64) -> f64 {
    if values.len() < 2 {
        return 0.0;
    }
    dx * (values.iter().sum::<f64>() - 0.5 * (values[0] + values[values.len() - 1]))
}

/// Modal energy of every wire, ½Σ(m_k v_k² + k_k q_k²), J (the exact integral of the density).
pub fn modal_energy(model: &Model, st: &State) -> f64 {
    st.modal_energy(model)
}

/// Energy of the deviation from the static state (J).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Energy {
    /// Kinetic energy of the wires' modes, the nodes and the pantographs.
    pub kinetic: f64,
    /// Strain energy of the wires' modes and the pantograph springs.
    pub potential: f64,
    /// Energy stored in the point elements: their springs, the contact springs, and the kinetic
    /// energy of point masses on the wires (steady arms).
    pub elements: f64,
    /// Potential of the constant external forces on the pantographs (−F·y).
    pub external: f64,
}

impl Energy {
    /// The system's energy, J: kinetic + potential + elements + external.
    pub fn total(&self) -> f64 {
        self.kinetic + self.potential + self.elements + self.external
    }
}

/// Energy of the deviation from the static state of the whole system at `st`. Allocates
/// nothing: it uses the workspace's energy arrays.
pub fn system_energy(cm: &CompiledModel, st: &State, ws: &mut Workspace) -> Energy {
    let m = cm.model();
    let mut e = Energy::default();
    for b in 0..m.layout.blocks.len() {
        let s = m.series(b);
        for (i, k) in m.layout.range(b).enumerate() {
            let (q, v) = (st.modal.u[k], st.modal.v[k]);
            e.kinetic += 0.5 * s.mass[i] * v * v;
            e.potential += 0.5 * s.stiffness[i] * q * q;
        }
    }
    for (j, n) in m.nodes.iter().enumerate() {
        e.kinetic += 0.5 * n.mass_kg * st.nodes.v[j] * st.nodes.v[j];
    }
    let io = cm.energy_io(st, ws);
    for (k, el) in m.elements.iter().enumerate() {
        e.elements += el.energy(cm.energy_slots(k), &io);
    }
    for (p, pan) in m.pantographs.iter().enumerate() {
        if let PantographKind::Lumped(l) = &pan.kind {
            let r = cm.pantograph_dofs(p);
            let (kin, pot, ext) = l.energy_all(
                &st.pantographs.u[r.clone()],
                &st.pantographs.v[r],
                cm.speed_kmh(),
            );
            e.kinetic += kin;
            e.potential += pot;
            e.external += ext;
        }
    }
    e
}

/// Rate of energy dissipation by every damper at the state's velocities, W. Allocates nothing.
pub fn dissipation_rate(cm: &CompiledModel, st: &State, ws: &mut Workspace) -> f64 {
    let m = cm.model();
    let mut d: f64 = st
        .modal
        .v
        .iter()
        .zip(cm.modal_damping())
        .map(|(v, c)| c * v * v)
        .sum();
    let io = cm.energy_io(st, ws);
    for (k, el) in m.elements.iter().enumerate() {
        d += el.dissipation(cm.energy_slots(k), &io);
    }
    for (p, pan) in m.pantographs.iter().enumerate() {
        if let PantographKind::Lumped(l) = &pan.kind {
            d += l.dissipation_all(&st.pantographs.v[cm.pantograph_dofs(p)]);
        }
    }
    d
}
