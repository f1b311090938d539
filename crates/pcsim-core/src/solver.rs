//! Time integration of the coupled model (Eq. 18) in deviation coordinates.
//!
//! # Method
//! Central differences in velocity-Verlet form, with the wires' diagonal modal damping and the
//! steady-arm point masses taken implicitly:
//!
//! ```text
//! v½ = vₙ + Δt/2 aₙ,   uₙ₊₁ = uₙ + Δt v½,
//! (M + Δt/2 C_modal) aₙ₊₁ = Q(uₙ₊₁, v½) − K uₙ₊₁ − C_modal v½,   vₙ₊₁ = v½ + Δt/2 aₙ₊₁.
//! ```
//!
//! `Q` holds the point forces: droppers (tension-only with preload, Eq. 15), messenger
//! supports (spring-damper), steady-arm springs, stitch elements, the penalty contact (Eq. 19)
//! and the pantograph's own springs. The wire mass matrix is diagonal plus the arm masses
//! (`M = D + Φₐᵀ mₐ Φₐ`), and the messenger-support dampers join `C` the same way; both are solved
//! exactly with the Woodbury identity and a Cholesky factor of the small capacitance matrix
//! computed once ([`ImplicitPoints`]). Implicit support dampers matter: with a light messenger
//! and many modes an explicit 1000 N·s/m damper is unstable at Δt = 1 ms. Every step does the same fixed work: no
//! iteration, no allocation. See ARCHITECTURE.md for why this scheme was chosen over ode15s.

use crate::basis::{axpy, dot};
use crate::model::{Model, Pantograph, StaticShape};
use crate::sampler::{PointSampler, SamplerScratch};

/// Modal and pantograph state at time `t`.
#[derive(Debug, Clone, PartialEq)]
pub struct State {
    pub t: f64,
    pub qm: Vec<f64>,
    pub vm: Vec<f64>,
    pub am: Vec<f64>,
    pub qc: Vec<f64>,
    pub vc: Vec<f64>,
    pub ac: Vec<f64>,
    /// Per pantograph: heights, velocities, accelerations of its masses.
    pub py: Vec<Vec<f64>>,
    pub pv: Vec<Vec<f64>>,
    pub pa: Vec<Vec<f64>>,
    /// Stitch nodes: displacement from static, velocity, acceleration.
    pub sz: Vec<f64>,
    pub sv: Vec<f64>,
    pub sa: Vec<f64>,
}

/// What one step saw at each pantograph.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ContactSample {
    pub position_m: f64,
    /// Contact force (Eq. 19), N; for a moving force, the force itself.
    pub force_n: f64,
    /// Contact-wire height at the contact point (static profile + deviation), m.
    pub wire_height_m: f64,
    /// Contact-wire vertical velocity at the contact point, m/s.
    pub wire_velocity_m_s: f64,
}

/// Largest plausible deviation of the contact wire from its design height, m: beyond it a run is
/// treated as blown up (no catenary moves that far).
pub const MAX_PLAUSIBLE_HEIGHT_M: f64 = 2.0;
/// Largest plausible contact force, N.
pub const MAX_PLAUSIBLE_FORCE_N: f64 = 1e6;

impl ContactSample {
    /// Finite and physically plausible (the blow-up test of every run loop).
    pub fn is_sound(&self) -> bool {
        self.force_n.is_finite()
            && self.wire_height_m.is_finite()
            && self.wire_velocity_m_s.is_finite()
            && self.force_n.abs() < MAX_PLAUSIBLE_FORCE_N
            && self.wire_height_m.abs() < MAX_PLAUSIBLE_HEIGHT_M
    }
}

struct PantoMats {
    /// Inverse of (M + Δt/2 C), row-major n×n.
    a_inv: Vec<f64>,
    k: Vec<f64>,
    c: Vec<f64>,
    n: usize,
}

/// Energy of the deviation from the static state (J).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Energy {
    pub kinetic: f64,
    pub potential: f64,
    /// Potential of the constant external forces on the pantographs (−F·y).
    pub external: f64,
}

impl Energy {
    pub fn total(&self) -> f64 {
        self.kinetic + self.potential + self.external
    }
}

/// The stepper: precomputed operators plus scratch. Build once, then [`Solver::step`].
pub struct Solver {
    model: Model,
    nd: usize,
    /// Droppers, supports and arms, for both wires.
    sp: PointSampler,
    sup_idx: Vec<usize>,
    arm_idx: Vec<usize>,
    arm_u: Vec<f64>,
    s_sup: PointSampler,
    s_arm: PointSampler,
    scr: SamplerScratch,
    /// Reciprocals of the M + Δt/2 C diagonals.
    dm_inv: Vec<f64>,
    dc_inv: Vec<f64>,
    /// Woodbury scratch (length N).
    /// Point terms taken implicitly: arm masses on the contact wire, support dampers on the
    /// messenger.
    imp_c: Option<ImplicitPoints>,
    imp_m: Option<ImplicitPoints>,
    /// Woodbury: arms with mass, Cholesky factor (lower, row-major) of the capacitance matrix.
    panto: Vec<Option<PantoMats>>,
    // scratch
    um_pts: Vec<f64>,
    uc_pts: Vec<f64>,
    fm_pts: Vec<f64>,
    fc_pts: Vec<f64>,
    v_sup: Vec<f64>,
    /// Point index (the dropper's) of each stitch element, and the force on each stitch node.
    stitch_pt: Vec<usize>,
    f_stitch: Vec<f64>,
    rows: Vec<Vec<f64>>,
    prhs: Vec<f64>,
    samples: Vec<ContactSample>,
    slack: usize,
    /// Position (m, model coordinates) and upward force (N) of each external pantograph.
    external: Vec<(f64, f64)>,
}

impl Solver {
    /// Precompute everything a step needs.
    pub fn new(model: Model) -> Self {
        let n = model.basis.n_modes();
        let dt = model.dt_s;
        let nd = model.droppers.len();
        // One point set for both wires: droppers first, then supports and arms (which share the
        // masts' positions), so one sampler serves both wires with shared sine tables.
        let mut pts: Vec<f64> = model.droppers.iter().map(|d| d.x_m).collect();
        let mut index_of = |x: f64| match pts.iter().position(|&p| (p - x).abs() < 1e-9) {
            Some(i) => i,
            None => {
                pts.push(x);
                pts.len() - 1
            }
        };
        let sup_idx: Vec<usize> = model.supports.iter().map(|s| index_of(s.x_m)).collect();
        let arm_idx: Vec<usize> = model.arms.iter().map(|a| index_of(a.x_m)).collect();
        // Velocity points: supports (dampers), then stitch attachments (stitch dampers).
        let mut xs: Vec<f64> = model.supports.iter().map(|s| s.x_m).collect();
        xs.extend(model.stitches.iter().map(|s| s.x_m));
        let mut stitch_pt = vec![0usize; model.stitches.len()];
        for (i, d) in model.droppers.iter().enumerate() {
            if let Some(j) = d.stitch {
                stitch_pt[j] = i;
            }
        }
        let xa: Vec<f64> = model.arms.iter().map(|a| a.x_m).collect();
        let sp = PointSampler::new(&model.basis, &pts, model.span_m);
        let s_sup = PointSampler::new(&model.basis, &xs, model.span_m);
        let s_arm = PointSampler::new(&model.basis, &xa, model.span_m);
        let scr = [&sp, &s_sup, &s_arm]
            .iter()
            .map(|s| s.scratch())
            .max_by_key(|s| s.len())
            .unwrap_or_else(|| sp.scratch());
        let eff = |w: &crate::model::Wire| -> Vec<f64> {
            (0..n)
                .map(|i| w.vertical.mass[i] + 0.5 * dt * w.vertical.damping[i])
                .collect()
        };
        let dm_eff = eff(&model.messenger);
        let dc_eff = eff(&model.contact);

        // Implicit point terms: arm masses (M) and support dampers (Δt/2 C), by Woodbury.
        let arms: Vec<(f64, f64)> = model
            .arms
            .iter()
            .filter(|a| a.mass_kg > 0.0)
            .map(|a| (a.x_m, a.mass_kg))
            .collect();
        let imp_c = ImplicitPoints::new(&model.basis, model.span_m, &dc_eff, &arms);
        let dampers: Vec<(f64, f64)> = model
            .supports
            .iter()
            .filter(|s| s.damping_ns_per_m > 0.0)
            .map(|s| (s.x_m, 0.5 * dt * s.damping_ns_per_m))
            .collect();
        let imp_m = ImplicitPoints::new(&model.basis, model.span_m, &dm_eff, &dampers);

        let panto = model
            .pantographs
            .iter()
            .map(|p| match p {
                Pantograph::Lumped {
                    masses_kg,
                    stiffness_n_per_m,
                    damping_ns_per_m,
                    ..
                } => {
                    let n = masses_kg.len();
                    let k = chain_matrix(stiffness_n_per_m, n);
                    let c = chain_matrix(damping_ns_per_m, n);
                    let mut a = c.iter().map(|x| 0.5 * dt * x).collect::<Vec<_>>();
                    for i in 0..n {
                        a[i * n + i] += masses_kg[i];
                    }
                    Some(PantoMats {
                        a_inv: invert_small(&a, n),
                        k,
                        c,
                        n,
                    })
                }
                Pantograph::MovingForce { .. } | Pantograph::External { .. } => None,
            })
            .collect();
        let npan = model.pantographs.len();
        let max_pdof = model
            .pantographs
            .iter()
            .map(|p| p.n_dof())
            .max()
            .unwrap_or(0);
        Self {
            nd,
            um_pts: vec![0.0; pts.len()],
            uc_pts: vec![0.0; pts.len()],
            fm_pts: vec![0.0; pts.len()],
            fc_pts: vec![0.0; pts.len()],
            arm_u: vec![0.0; arm_idx.len()],
            sup_idx,
            arm_idx,
            v_sup: vec![0.0; xs.len()],
            f_stitch: vec![0.0; stitch_pt.len()],
            stitch_pt,
            rows: vec![vec![0.0; n]; npan],
            prhs: vec![0.0; max_pdof],
            samples: vec![ContactSample::default(); npan],
            external: vec![(0.0, 0.0); npan],
            sp,
            s_sup,
            s_arm,
            scr,
            dm_inv: dm_eff.iter().map(|d| 1.0 / d).collect(),
            dc_inv: dc_eff.iter().map(|d| 1.0 / d).collect(),
            imp_c,
            imp_m,
            panto,
            slack: 0,
            model,
        }
    }

    pub fn model(&self) -> &Model {
        &self.model
    }

    /// The static state: zero deviation, wires at rest, each pantograph in static equilibrium
    /// against the rigid static wire at its start position.
    pub fn initial_state(&self) -> State {
        let n = self.model.basis.n_modes();
        let z = vec![0.0; n];
        let mut py = Vec::new();
        for (p, pm) in self.model.pantographs.iter().zip(&self.panto) {
            match (p, pm) {
                (
                    Pantograph::Lumped {
                        uplift_n, aero_n, ..
                    },
                    Some(m),
                ) => {
                    let nn = m.n;
                    let x0 = self.model.pantograph_position(py.len(), 0.0);
                    let h = self.model.statics.contact_height(x0);
                    let kn = self.model.contact_stiffness_n_per_m;
                    let mut a = m.k.clone();
                    a[0] += kn;
                    let mut f = vec![0.0; nn];
                    f[nn - 1] += uplift_n;
                    f[0] += aero_n + kn * h;
                    let inv = invert_small(&a, nn);
                    py.push(
                        (0..nn)
                            .map(|i| (0..nn).map(|j| inv[i * nn + j] * f[j]).sum())
                            .collect(),
                    );
                }
                _ => py.push(vec![]),
            }
        }
        let pv: Vec<Vec<f64>> = py.iter().map(|y: &Vec<f64>| vec![0.0; y.len()]).collect();
        State {
            t: 0.0,
            qm: z.clone(),
            vm: z.clone(),
            am: z.clone(),
            qc: z.clone(),
            vc: z.clone(),
            ac: z,
            pa: pv.clone(),
            pv,
            py,
            sz: vec![0.0; self.model.stitches.len()],
            sv: vec![0.0; self.model.stitches.len()],
            sa: vec![0.0; self.model.stitches.len()],
        }
    }

    /// Set the position (model coordinates, m) and the upward contact force (N) that an
    /// [`Pantograph::External`] applies during the next step.
    pub fn set_external(&mut self, p: usize, x_m: f64, force_n: f64) {
        self.external[p] = (x_m, force_n);
    }

    /// Move the model's origin forward by `d` metres (the pantographs' positions in model
    /// coordinates drop by `d`). Used by the real-time window when it moves.
    pub fn shift_origin(&mut self, d: f64) {
        self.model.start_m -= d;
    }

    /// Contact samples of the last step (one per pantograph).
    pub fn samples(&self) -> &[ContactSample] {
        &self.samples
    }

    /// Contact-wire deviation at the steady arms after the last step, m (same order as
    /// `model.arms`).
    pub fn arm_displacements(&self) -> &[f64] {
        &self.arm_u
    }

    /// Dropper tensions after the last step, N (Eq. 15 with preload: `max(F0 + k·Δ, 0)`).
    pub fn dropper_tensions(&self, out: &mut [f64]) {
        for (i, d) in self.model.droppers.iter().enumerate() {
            let e = self.um_pts[i] - self.uc_pts[i];
            out[i] = (d.preload_n + d.stiffness_n_per_m * e).max(0.0);
        }
    }

    /// Dropper elongations from the static state after the last step (messenger minus contact
    /// wire), m.
    pub fn dropper_elongations(&self, out: &mut [f64]) {
        for i in 0..self.nd {
            out[i] = self.um_pts[i] - self.uc_pts[i];
        }
    }

    /// Droppers slack after the last step.
    pub fn slack_droppers(&self) -> usize {
        self.slack
    }

    /// Advance `st` by one fixed step Δt. Allocation-free.
    pub fn step(&mut self, st: &mut State) {
        let m = &self.model;
        let dt = m.dt_s;
        let h = 0.5 * dt;
        for ((q, v), a) in st.qm.iter_mut().zip(st.vm.iter_mut()).zip(st.am.iter()) {
            *v += h * a;
            *q += dt * *v;
        }
        for ((q, v), a) in st.qc.iter_mut().zip(st.vc.iter_mut()).zip(st.ac.iter()) {
            *v += h * a;
            *q += dt * *v;
        }
        for p in 0..st.py.len() {
            for i in 0..st.py[p].len() {
                st.pv[p][i] += h * st.pa[p][i];
                st.py[p][i] += dt * st.pv[p][i];
            }
        }
        for j in 0..st.sz.len() {
            st.sv[j] += h * st.sa[j];
            st.sz[j] += dt * st.sv[j];
        }
        st.t += dt;

        // Point displacements and forces.
        self.sp.gather_pair(
            &st.qm,
            &st.qc,
            &mut self.um_pts,
            &mut self.uc_pts,
            &mut self.scr,
        );
        self.fm_pts.fill(0.0);
        self.fc_pts.fill(0.0);
        self.s_sup.gather(&st.vm, &mut self.v_sup, &mut self.scr);
        let mut slack = 0;
        for (i, d) in m.droppers.iter().enumerate() {
            // A stitch dropper hangs from its stitch node instead of the messenger.
            let top = match d.stitch {
                Some(j) => st.sz[j],
                None => self.um_pts[i],
            };
            let e = top - self.uc_pts[i];
            let t = d.preload_n + d.stiffness_n_per_m * e;
            let df = if t > 0.0 {
                t - d.preload_n
            } else {
                slack += 1;
                -d.preload_n
            };
            self.fc_pts[i] = df;
            match d.stitch {
                Some(j) => self.f_stitch[j] = -df,
                None => self.fm_pts[i] = -df,
            }
        }
        self.slack = slack;
        let nsup = m.supports.len();
        for (j, s) in m.stitches.iter().enumerate() {
            let i = self.stitch_pt[j];
            let f = -s.stiffness_n_per_m * (st.sz[j] - self.um_pts[i])
                - s.damping_ns_per_m * (st.sv[j] - self.v_sup[nsup + j]);
            self.f_stitch[j] += f;
            self.fm_pts[i] -= f;
            st.sa[j] = self.f_stitch[j] / s.mass_kg;
            st.sv[j] += h * st.sa[j];
        }
        for (j, s) in m.supports.iter().enumerate() {
            let k = self.sup_idx[j];
            self.fm_pts[k] +=
                -s.stiffness_n_per_m * self.um_pts[k] - s.damping_ns_per_m * self.v_sup[j];
        }
        for (j, a) in m.arms.iter().enumerate() {
            let k = self.arm_idx[j];
            self.arm_u[j] = self.uc_pts[k];
            self.fc_pts[k] += -a.stiffness_n_per_m * self.uc_pts[k];
        }
        // Right-hand sides, stored in the acceleration arrays.
        let (wm, wc) = (&m.messenger.vertical, &m.contact.vertical);
        for (((a, q), v), (k, c)) in st
            .am
            .iter_mut()
            .zip(&st.qm)
            .zip(&st.vm)
            .zip(wm.stiffness.iter().zip(&wm.damping))
        {
            *a = -k * q - c * v;
        }
        for (((a, q), v), (k, c)) in st
            .ac
            .iter_mut()
            .zip(&st.qc)
            .zip(&st.vc)
            .zip(wc.stiffness.iter().zip(&wc.damping))
        {
            *a = -k * q - c * v;
        }
        self.sp.scatter_add_pair(
            &self.fm_pts,
            &self.fc_pts,
            &mut st.am,
            &mut st.ac,
            &mut self.scr,
        );

        // Contact at each pantograph (Eq. 19).
        let kn = m.contact_stiffness_n_per_m;
        for p in 0..m.pantographs.len() {
            let x = match &m.pantographs[p] {
                Pantograph::External { .. } => self.external[p].0,
                _ => m.pantograph_position(p, st.t),
            };
            let row = &mut self.rows[p];
            m.basis.fill_sines(x, row);
            let wire = static_height(&m.statics, x) + dot(&st.qc, row);
            let f = match &m.pantographs[p] {
                Pantograph::Lumped { .. } => kn * (st.py[p][0] - wire).max(0.0),
                Pantograph::MovingForce { force_n, .. } => *force_n,
                Pantograph::External { .. } => self.external[p].1,
            };
            axpy(f, row, &mut st.ac);
            self.samples[p] = ContactSample {
                position_m: x,
                force_n: f,
                wire_height_m: wire,
                wire_velocity_m_s: 0.0,
            };
        }

        // Solve for the accelerations and finish the velocities.
        for (a, d) in st.am.iter_mut().zip(&self.dm_inv) {
            *a *= d;
        }
        for (a, d) in st.ac.iter_mut().zip(&self.dc_inv) {
            *a *= d;
        }
        if let Some(imp) = &mut self.imp_m {
            imp.correct(&mut st.am, &self.dm_inv, &mut self.scr);
        }
        if let Some(imp) = &mut self.imp_c {
            imp.correct(&mut st.ac, &self.dc_inv, &mut self.scr);
        }
        for (v, a) in st.vm.iter_mut().zip(&st.am) {
            *v += h * a;
        }
        for (v, a) in st.vc.iter_mut().zip(&st.ac) {
            *v += h * a;
        }
        for p in 0..m.pantographs.len() {
            self.samples[p].wire_velocity_m_s = dot(&st.vc, &self.rows[p]);
            if let (
                Pantograph::Lumped {
                    uplift_n, aero_n, ..
                },
                Some(pm),
            ) = (&m.pantographs[p], &self.panto[p])
            {
                let n = pm.n;
                let r = &mut self.prhs[..n];
                for i in 0..n {
                    let mut s = 0.0;
                    for j in 0..n {
                        s -= pm.k[i * n + j] * st.py[p][j] + pm.c[i * n + j] * st.pv[p][j];
                    }
                    r[i] = s;
                }
                r[0] += aero_n - self.samples[p].force_n;
                r[n - 1] += uplift_n;
                for i in 0..n {
                    let mut a = 0.0;
                    for j in 0..n {
                        a += pm.a_inv[i * n + j] * r[j];
                    }
                    st.pa[p][i] = a;
                    st.pv[p][i] += h * a;
                }
            }
        }
    }

    /// Energy of the deviation from the static state (kinetic, potential of wires, point
    /// elements, contact and pantographs, and the potential of the constant pantograph forces).
    /// Not used in stepping; allocates.
    pub fn energy(&mut self, st: &State) -> Energy {
        let m = &self.model;
        let (wm, wc) = (&m.messenger.vertical, &m.contact.vertical);
        let mut kin = 0.0;
        let mut pot = 0.0;
        for i in 0..st.qm.len() {
            kin += 0.5 * (wm.mass[i] * st.vm[i] * st.vm[i] + wc.mass[i] * st.vc[i] * st.vc[i]);
            pot += 0.5
                * (wm.stiffness[i] * st.qm[i] * st.qm[i] + wc.stiffness[i] * st.qc[i] * st.qc[i]);
        }
        let mut um = vec![0.0; self.um_pts.len()];
        let mut uc = vec![0.0; self.uc_pts.len()];
        let mut va = vec![0.0; m.arms.len()];
        self.sp
            .gather_pair(&st.qm, &st.qc, &mut um, &mut uc, &mut self.scr);
        self.s_arm.gather(&st.vc, &mut va, &mut self.scr);
        for (j, s) in m.stitches.iter().enumerate() {
            let i = self.stitch_pt[j];
            kin += 0.5 * s.mass_kg * st.sv[j] * st.sv[j];
            pot += 0.5 * s.stiffness_n_per_m * (st.sz[j] - um[i]).powi(2);
        }
        for (i, d) in m.droppers.iter().enumerate() {
            let top = match d.stitch {
                Some(j) => st.sz[j],
                None => um[i],
            };
            let e = top - uc[i];
            let (f0, k) = (d.preload_n, d.stiffness_n_per_m);
            pot += if f0 + k * e >= 0.0 {
                0.5 * k * e * e
            } else {
                -f0 * e - f0 * f0 / (2.0 * k)
            };
        }
        for (j, s) in m.supports.iter().enumerate() {
            pot += 0.5 * s.stiffness_n_per_m * um[self.sup_idx[j]].powi(2);
        }
        for (j, a) in m.arms.iter().enumerate() {
            pot += 0.5 * a.stiffness_n_per_m * uc[self.arm_idx[j]].powi(2);
            kin += 0.5 * a.mass_kg * va[j] * va[j];
        }
        let mut ext = 0.0;
        let mut row = vec![0.0; st.qc.len()];
        for (p, pan) in m.pantographs.iter().enumerate() {
            if let Pantograph::Lumped {
                masses_kg,
                stiffness_n_per_m,
                uplift_n,
                aero_n,
                ..
            } = pan
            {
                let n = masses_kg.len();
                let (y, v) = (&st.py[p], &st.pv[p]);
                for i in 0..n {
                    kin += 0.5 * masses_kg[i] * v[i] * v[i];
                    let stretch = if i + 1 < n { y[i] - y[i + 1] } else { y[i] };
                    pot += 0.5 * stiffness_n_per_m[i] * stretch * stretch;
                }
                ext -= aero_n * y[0] + uplift_n * y[n - 1];
                let x = m.pantograph_position(p, st.t);
                m.basis.fill_sines(x, &mut row);
                let pen = y[0] - static_height(&m.statics, x) - dot(&st.qc, &row);
                if pen > 0.0 {
                    pot += 0.5 * m.contact_stiffness_n_per_m * pen * pen;
                }
            }
        }
        Energy {
            kinetic: kin,
            potential: pot,
            external: ext,
        }
    }

    /// Rate of energy dissipation by all dampers at the state's velocities, W.
    pub fn dissipation_rate(&mut self, st: &State) -> f64 {
        let m = &self.model;
        let (wm, wc) = (&m.messenger.vertical, &m.contact.vertical);
        let mut d = 0.0;
        for i in 0..st.vm.len() {
            d += wm.damping[i] * st.vm[i].powi(2) + wc.damping[i] * st.vc[i].powi(2);
        }
        let mut vs = vec![0.0; m.supports.len() + m.stitches.len()];
        self.s_sup.gather(&st.vm, &mut vs, &mut self.scr);
        for (s, v) in m.supports.iter().zip(&vs) {
            d += s.damping_ns_per_m * v * v;
        }
        for (j, s) in m.stitches.iter().enumerate() {
            d += s.damping_ns_per_m * (st.sv[j] - vs[m.supports.len() + j]).powi(2);
        }
        for (p, pan) in m.pantographs.iter().enumerate() {
            if let Pantograph::Lumped {
                damping_ns_per_m,
                masses_kg,
                ..
            } = pan
            {
                let n = masses_kg.len();
                let v = &st.pv[p];
                for i in 0..n {
                    let rel = if i + 1 < n { v[i] - v[i + 1] } else { v[i] };
                    d += damping_ns_per_m[i] * rel * rel;
                }
            }
        }
        d
    }
}

#[inline]
fn static_height(s: &StaticShape, x: f64) -> f64 {
    s.contact_height(x)
}

/// Point terms of a wire's system matrix taken implicitly: `A = D + Φᵀ W Φ` with `D` the diagonal
/// modal part and `W = diag(w_j)` (a point mass, or Δt/2 × a point damper). `A⁻¹` is applied with
/// the Woodbury identity, `A⁻¹ r = z − D⁻¹ Φᵀ (W⁻¹ + Φ D⁻¹ Φᵀ)⁻¹ Φ z`, `z = D⁻¹ r`, and a Cholesky
/// factor of the small capacitance matrix computed once.
struct ImplicitPoints {
    sampler: PointSampler,
    chol: Vec<f64>,
    g: Vec<f64>,
    y: Vec<f64>,
    tmp: Vec<f64>,
}

impl ImplicitPoints {
    /// `points`: (position, weight w_j > 0); `None` when there are none.
    fn new(
        basis: &crate::basis::SineBasis,
        span_m: Option<f64>,
        d: &[f64],
        points: &[(f64, f64)],
    ) -> Option<Self> {
        let np = points.len();
        if np == 0 {
            return None;
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
        cholesky_in_place(&mut cap, np);
        let xs: Vec<f64> = points.iter().map(|p| p.0).collect();
        Some(Self {
            sampler: PointSampler::new(basis, &xs, span_m),
            chol: cap,
            g: vec![0.0; np],
            y: vec![0.0; np],
            tmp: vec![0.0; n],
        })
    }

    /// Turn `z = D⁻¹ r` (in `a`) into `A⁻¹ r`.
    fn correct(&mut self, a: &mut [f64], d_inv: &[f64], scr: &mut SamplerScratch) {
        let np = self.g.len();
        self.sampler.gather(a, &mut self.g, scr);
        cholesky_solve(&self.chol, np, &mut self.g, &mut self.y);
        self.tmp.fill(0.0);
        self.sampler.scatter_add(&self.g, &mut self.tmp, scr);
        for ((ai, di), t) in a.iter_mut().zip(d_inv).zip(&self.tmp) {
            *ai -= di * t;
        }
    }
}

/// Stiffness (or damping) matrix of a chain: element `i` joins `i` and `i+1`, the last joins
/// the last mass to ground. Row-major n×n.
fn chain_matrix(k: &[f64], n: usize) -> Vec<f64> {
    let mut m = vec![0.0; n * n];
    for i in 0..n {
        if i + 1 < n {
            m[i * n + i] += k[i];
            m[(i + 1) * n + i + 1] += k[i];
            m[i * n + i + 1] -= k[i];
            m[(i + 1) * n + i] -= k[i];
        } else {
            m[i * n + i] += k[i];
        }
    }
    m
}

/// Inverse of a small dense matrix by Gauss–Jordan with partial pivoting (pantographs have a
/// handful of masses; a linear-algebra crate is not worth its build time here).
fn invert_small(a: &[f64], n: usize) -> Vec<f64> {
    let mut m = a.to_vec();
    let mut inv = vec![0.0; n * n];
    for i in 0..n {
        inv[i * n + i] = 1.0;
    }
    for col in 0..n {
        let piv = (col..n)
            .max_by(|&i, &j| m[i * n + col].abs().total_cmp(&m[j * n + col].abs()))
            .unwrap_or(col);
        if piv != col {
            for j in 0..n {
                m.swap(col * n + j, piv * n + j);
                inv.swap(col * n + j, piv * n + j);
            }
        }
        let d = m[col * n + col];
        for j in 0..n {
            m[col * n + j] /= d;
            inv[col * n + j] /= d;
        }
        for i in 0..n {
            if i != col {
                let f = m[i * n + col];
                if f != 0.0 {
                    for j in 0..n {
                        m[i * n + j] -= f * m[col * n + j];
                        inv[i * n + j] -= f * inv[col * n + j];
                    }
                }
            }
        }
    }
    inv
}

/// In-place Cholesky of an SPD row-major n×n matrix; the lower triangle holds L afterwards.
/// Hand-written (30 lines) because the capacitance matrix is small and built once; faer's build
/// time on a 2-core CI would outweigh it.
fn cholesky_in_place(a: &mut [f64], n: usize) {
    for j in 0..n {
        let mut d = a[j * n + j];
        for k in 0..j {
            d -= a[j * n + k] * a[j * n + k];
        }
        let d = d.max(f64::MIN_POSITIVE).sqrt();
        a[j * n + j] = d;
        for i in j + 1..n {
            let mut s = a[i * n + j];
            for k in 0..j {
                s -= a[i * n + k] * a[j * n + k];
            }
            a[i * n + j] = s / d;
        }
    }
}

/// Solve `L Lᵀ x = b` in place in `b` (`tmp` is scratch of length n).
fn cholesky_solve(l: &[f64], n: usize, b: &mut [f64], tmp: &mut [f64]) {
    for i in 0..n {
        let mut s = b[i];
        for k in 0..i {
            s -= l[i * n + k] * tmp[k];
        }
        tmp[i] = s / l[i * n + i];
    }
    for i in (0..n).rev() {
        let mut s = tmp[i];
        for k in i + 1..n {
            s -= l[k * n + i] * b[k];
        }
        b[i] = s / l[i * n + i];
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn small_inverse_and_cholesky() {
        let a = [4.0, 1.0, 0.5, 1.0, 3.0, 0.2, 0.5, 0.2, 2.0];
        let inv = invert_small(&a, 3);
        for i in 0..3 {
            for j in 0..3 {
                let s: f64 = (0..3).map(|k| a[i * 3 + k] * inv[k * 3 + j]).sum();
                assert!((s - if i == j { 1.0 } else { 0.0 }).abs() < 1e-12);
            }
        }
        let mut l = a.to_vec();
        cholesky_in_place(&mut l, 3);
        let mut b = [1.0, 2.0, 3.0];
        let mut tmp = [0.0; 3];
        cholesky_solve(&l, 3, &mut b, &mut tmp);
        for i in 0..3 {
            let s: f64 = (0..3).map(|k| a[i * 3 + k] * b[k]).sum();
            assert!((s - [1.0, 2.0, 3.0][i]).abs() < 1e-12);
        }
    }
}
