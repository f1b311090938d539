//! Pantographs: lumped-mass chains (Eq. 16), constant moving forces (analytic checks), and
//! external loads (hardware in the loop). Every law of the pantograph lives here: the chain
//! matrices, the aerodynamic force (Eq. 17), the static equilibrium, the accelerations, the energy
//! and the dissipation.

use crate::linalg::{invert_small, mat_vec};
use rustfft::num_complex::Complex;

/// A lumped-mass pantograph (Eq. 16): masses head first; spring and damper `i` join mass `i` to
/// mass `i+1`, the last ones join the lowest mass to the roof. Heights are absolute, with zero at
/// the contact-wire height at the supports, where every spring is unstretched. With collector
/// strips (issue 43) the head mass is the head's frame, and each strip, a mass on its own spring
/// and damper to the frame, carries its own contact: the degrees of freedom are then the strips
/// first, then the chain ([`Lumped::frame_dof`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Lumped {
    /// Masses, head first, kg.
    pub masses_kg: Vec<f64>,
    /// Springs, one per mass, N/m.
    pub stiffness_n_per_m: Vec<f64>,
    /// Dampers, one per mass, N·s/m.
    pub damping_ns_per_m: Vec<f64>,
    /// Net static uplift on the lowest mass (gravity included), N.
    pub uplift_n: f64,
    /// The static uplift as a function of the head's height (none: `uplift_n` at every height).
    pub uplift_by_height: Option<UpliftTable>,
    /// Aerodynamic force on the head, `Σ c_i v^i` with `v` in km/h, N (Eq. 17 as a configurable
    /// polynomial; reference README §2.1).
    pub aero_coeffs_kmh: Vec<f64>,
    /// Collector strips on the head's frame (none: the head mass carries the contact).
    pub strips: Vec<Strip>,
}

/// A collector strip (issue 43, item 1): a mass on a spring and a damper to the head's frame,
/// with its own contact point along the track.
#[derive(Debug, Clone, PartialEq)]
pub struct Strip {
    /// The strip's mass, kg.
    pub mass_kg: f64,
    /// Its suspension's stiffness to the frame, N/m.
    pub stiffness_n_per_m: f64,
    /// Its suspension's damping, N·s/m.
    pub damping_ns_per_m: f64,
    /// Where its contact point is along the track, ahead of the pantograph's position, m.
    pub along_m: f64,
    /// Its running face's height above the other strips' at rest (negative: lower), m.
    pub height_offset_m: f64,
    /// The penalty stiffness of its contact (Eq. 19), N/m.
    pub contact_stiffness_n_per_m: f64,
}

/// A frame's static uplift against the head's height (issue 43, item 2): points `(height_m,
/// uplift_n)`, heights increasing.
#[derive(Debug, Clone, PartialEq)]
pub struct UpliftTable {
    /// Heights of the head, m (zero at the contact wire's height at the supports).
    pub height_m: Vec<f64>,
    /// The uplift at each, N.
    pub uplift_n: Vec<f64>,
}

impl UpliftTable {
    /// The uplift at head height `h_m`: linear between the points, the end values beyond them.
    #[inline]
    pub fn at(&self, h_m: f64) -> f64 {
        let (x, y) = (&self.height_m, &self.uplift_n);
        let n = x.len();
        if h_m <= x[0] {
            return y[0];
        }
        if h_m >= x[n - 1] {
            return y[n - 1];
        }
        let k = x.partition_point(|&xi| xi <= h_m).clamp(1, n - 1);
        let t = (h_m - x[k - 1]) / (x[k] - x[k - 1]);
        y[k - 1] + t * (y[k] - y[k - 1])
    }
}

/// What runs along the contact wire.
#[derive(Debug, Clone, PartialEq)]
pub enum PantographKind {
    /// A lumped-mass pantograph (Eq. 16).
    Lumped(Lumped),
    /// A constant upward force on the contact wire.
    MovingForce {
        /// The force, N.
        force_n: f64,
        /// The lateral force on the contact wire, N (applied where lateral motion is modelled).
        lateral_force_n: f64,
    },
    /// A force and a position given from outside at every step (hardware in the loop).
    External,
}

/// A pantograph with its name and its place in the train.
#[derive(Debug, Clone, PartialEq)]
pub struct Pantograph {
    /// Name (shown in outputs).
    pub name: String,
    /// Distance behind the leading pantograph, m.
    pub offset_m: f64,
    /// What runs along the wire.
    pub kind: PantographKind,
    /// Half-length of the head and half the strip's working range, m (for the lateral outputs).
    pub head_half_width_m: Option<f64>,
    /// Half the strip's working range, m.
    pub working_half_width_m: Option<f64>,
}

impl Pantograph {
    /// The collector strips (none for a single head or a prescribed load).
    pub fn strips(&self) -> &[Strip] {
        match &self.kind {
            PantographKind::Lumped(l) => &l.strips,
            _ => &[],
        }
    }

    /// The number of contact heads: its strips, or one.
    pub fn n_heads(&self) -> usize {
        self.strips().len().max(1)
    }

    /// Number of degrees of freedom.
    pub fn n_dof(&self) -> usize {
        match &self.kind {
            PantographKind::Lumped(l) => l.strips.len() + l.masses_kg.len(),
            _ => 0,
        }
    }
}

/// Eq. 17 as a polynomial: the aerodynamic force `Σ c_i v^i` at `v_kmh` (Horner), N.
pub fn aero_force_n(coeffs_kmh: &[f64], v_kmh: f64) -> f64 {
    coeffs_kmh
        .iter()
        .rev()
        .fold(0.0, |acc, ci| acc * v_kmh + ci)
}

/// Stiffness (or damping) matrix of a chain (Eq. 16's K_P and C_P): element `i` joins `i` and
/// `i+1`, the last joins the last mass to the ground. Row-major `n × n`.
pub fn chain_matrix(k: &[f64], n: usize) -> Vec<f64> {
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

/// The precomputed operators of a lumped pantograph for a time step Δt.
#[derive(Debug, Clone, PartialEq)]
pub struct ChainOperators {
    /// Number of masses (degrees of freedom: strips and chain).
    pub n: usize,
    /// The head frame's degree of freedom (the number of strips): the aerodynamic force acts
    /// there, the uplift table reads its height.
    pub frame: usize,
    /// Inverse of `M + Δt/2 C`, row-major.
    pub a_inv: Vec<f64>,
    /// Stiffness matrix K_P (Eq. 16), row-major.
    pub k: Vec<f64>,
    /// Damping matrix C_P (Eq. 16), row-major.
    pub c: Vec<f64>,
    /// Aerodynamic force at the run speed, N.
    pub aero_n: f64,
    /// Net static uplift on the lowest mass, N.
    pub uplift_n: f64,
    /// The uplift against the head's height, when it depends on it.
    pub uplift_by_height: Option<UpliftTable>,
}

impl Lumped {
    /// The head frame's degree of freedom: the chain's first mass, after the strips.
    pub fn frame_dof(&self) -> usize {
        self.strips.len()
    }

    /// The masses by degree of freedom (the strips', then the chain's), kg.
    pub fn mass_vector(&self) -> Vec<f64> {
        (self.strips.iter().map(|s| s.mass_kg))
            .chain(self.masses_kg.iter().copied())
            .collect()
    }

    /// The stiffness and damping matrices `K_P`, `C_P` (Eq. 16) by degree of freedom: the
    /// chain's ([`chain_matrix`]), and each strip's spring and damper to the frame.
    pub fn matrices(&self) -> (Vec<f64>, Vec<f64>) {
        let nm = self.masses_kg.len();
        let kc = chain_matrix(&self.stiffness_n_per_m, nm);
        let cc = chain_matrix(&self.damping_ns_per_m, nm);
        let ns = self.strips.len();
        if ns == 0 {
            return (kc, cc);
        }
        let n = ns + nm;
        let (mut k, mut c) = (vec![0.0; n * n], vec![0.0; n * n]);
        for i in 0..nm {
            for j in 0..nm {
                k[(ns + i) * n + ns + j] = kc[i * nm + j];
                c[(ns + i) * n + ns + j] = cc[i * nm + j];
            }
        }
        for (s, st) in self.strips.iter().enumerate() {
            for (m, v) in [
                (&mut k, st.stiffness_n_per_m),
                (&mut c, st.damping_ns_per_m),
            ] {
                m[s * n + s] += v;
                m[ns * n + ns] += v;
                m[s * n + ns] -= v;
                m[ns * n + s] -= v;
            }
        }
        (k, c)
    }

    /// Operators for time step `dt` at speed `v_kmh`; `None` when `M + Δt/2 C` is singular.
    pub fn operators(&self, dt: f64, v_kmh: f64) -> Option<ChainOperators> {
        let (k, c) = self.matrices();
        let m = self.mass_vector();
        let n = m.len();
        let mut a = c.iter().map(|x| 0.5 * dt * x).collect::<Vec<_>>();
        for i in 0..n {
            a[i * n + i] += m[i];
        }
        Some(ChainOperators {
            n,
            frame: self.frame_dof(),
            a_inv: invert_small(&a, n)?,
            k,
            c,
            aero_n: aero_force_n(&self.aero_coeffs_kmh, v_kmh),
            uplift_n: self.uplift_n,
            uplift_by_height: self.uplift_by_height.clone(),
        })
    }
}

impl ChainOperators {
    /// Static equilibrium of the chain pressed on a rigid wire at height `wire_m` through a
    /// contact spring `k_n` (the initial state): `(K + k_n e₀e₀ᵀ) y = uplift e_last + (aero +
    /// k_n h) e₀`. `None` when the chain has no static equilibrium (a singular stiffness).
    /// With an uplift that depends on the head's height the equilibrium is found by fixed-point
    /// iteration on the head's height (to 1e-12 m; `None` if it does not settle in 100 steps).
    pub fn static_equilibrium(&self, k_n: f64, wire_m: f64) -> Option<Vec<f64>> {
        let n = self.n;
        let mut a = self.k.clone();
        a[0] += k_n;
        let inv = invert_small(&a, n)?;
        let solve = |uplift: f64| {
            let mut f = vec![0.0; n];
            f[n - 1] += uplift;
            f[0] += self.aero_n + k_n * wire_m;
            mat_vec(&inv, n, &f)
        };
        let Some(t) = &self.uplift_by_height else {
            return Some(solve(self.uplift_n));
        };
        let mut y = solve(t.at(wire_m));
        for _ in 0..100 {
            let next = solve(t.at(y[0]));
            let settled = (next[0] - y[0]).abs() <= 1e-12;
            y = next;
            if settled {
                return Some(y);
            }
        }
        None
    }

    /// Static equilibrium of a head of strips, strip `s` pressed on a rigid wire at height
    /// `wire_m[s]` through its contact spring `k_n[s]` (its running face `offset_m[s]` above the
    /// strip's own height): the strips that would not touch (the wire above their face at the
    /// equilibrium of the others) are left free, found by re-solving until the set of strips in
    /// contact settles (at most one pass per strip). The uplift is the table's at the frame's
    /// height, by fixed point as in [`Self::static_equilibrium`].
    pub fn static_equilibrium_strips(
        &self,
        k_n: &[f64],
        wire_m: &[f64],
        offset_m: &[f64],
    ) -> Option<Vec<f64>> {
        let (n, f0) = (self.n, self.frame);
        let mut touching = vec![true; f0];
        let solve = |touching: &[bool], uplift: f64| {
            let mut a = self.k.clone();
            let mut f = vec![0.0; n];
            f[n - 1] += uplift;
            f[f0] += self.aero_n;
            for s in (0..f0).filter(|&s| touching[s]) {
                a[s * n + s] += k_n[s];
                f[s] += k_n[s] * (wire_m[s] - offset_m[s]);
            }
            Some(mat_vec(&invert_small(&a, n)?, n, &f))
        };
        let settle = |touching: &[bool]| -> Option<Vec<f64>> {
            if self.uplift_by_height.is_none() {
                return solve(touching, self.uplift_n);
            }
            let mut y = solve(touching, self.uplift_at(wire_m[0]))?;
            for _ in 0..100 {
                let next = solve(touching, self.uplift_at(y[f0]))?;
                let settled = (next[f0] - y[f0]).abs() <= 1e-12;
                y = next;
                if settled {
                    return Some(y);
                }
            }
            None
        };
        for _ in 0..=f0 {
            let y = settle(&touching)?;
            let now: Vec<bool> = (0..f0).map(|s| y[s] + offset_m[s] >= wire_m[s]).collect();
            if now == touching || !now.iter().any(|&t| t) {
                return Some(y);
            }
            touching = now;
        }
        None
    }

    /// The uplift on the lowest mass with the head at `head_m`, N.
    #[inline]
    pub fn uplift_at(&self, head_m: f64) -> f64 {
        match &self.uplift_by_height {
            Some(t) => t.at(head_m),
            None => self.uplift_n,
        }
    }

    /// Eq. 16 solved for the accelerations: `(M + Δt/2 C) a = −K y − C v + (aero + f_head) e₀ +
    /// uplift e_last`, with `f_head[0]` the force of the wire on the head; with strips, each
    /// strip `s` takes `f_head[s]` and the frame the aerodynamic force. `r` is scratch (length
    /// n).
    #[inline]
    pub fn accelerations(
        &self,
        y: &[f64],
        v: &[f64],
        f_head: &[f64],
        r: &mut [f64],
        a: &mut [f64],
    ) {
        let n = self.n;
        for i in 0..n {
            let mut s = 0.0;
            for j in 0..n {
                s -= self.k[i * n + j] * y[j] + self.c[i * n + j] * v[j];
            }
            r[i] = s;
        }
        if self.frame == 0 {
            r[0] += self.aero_n + f_head[0];
        } else {
            r[self.frame] += self.aero_n;
            for (ri, fi) in r.iter_mut().zip(&f_head[..self.frame]) {
                *ri += fi;
            }
        }
        r[n - 1] += self.uplift_at(y[self.frame]);
        for i in 0..n {
            let mut s = 0.0;
            for j in 0..n {
                s += self.a_inv[i * n + j] * r[j];
            }
            a[i] = s;
        }
    }
}

impl Lumped {
    /// The receptance at the head, `X₀/F₀` in m/N, at angular frequency `omega_rad_s`: Eq. 16
    /// under a harmonic force `F₀ e^{iωt}` on the head, `(K_P − ω² M_P + iω C_P) x = F₀ e₀` (the
    /// chain's matrices are tridiagonal: solved by elimination from the roof up). `None` where
    /// the dynamic stiffness is singular (an undamped resonance hit exactly).
    pub fn receptance(&self, omega_rad_s: f64) -> Option<Complex<f64>> {
        if !self.strips.is_empty() {
            return self.receptance_of_strips(omega_rad_s);
        }
        let n = self.masses_kg.len();
        let w = omega_rad_s;
        // Element i joins mass i and i+1 (the last joins the roof): its dynamic stiffness.
        let z: Vec<Complex<f64>> = (0..n)
            .map(|i| Complex::new(self.stiffness_n_per_m[i], w * self.damping_ns_per_m[i]))
            .collect();
        // From the lowest mass up: the impedance of everything below mass i, seen from mass i
        // (the mass, its element to the next one down, and that one's own impedance in series).
        let mut below = Complex::new(0.0, 0.0);
        for i in (0..n).rev() {
            let own = Complex::new(-w * w * self.masses_kg[i], 0.0);
            let down = if i + 1 == n {
                z[i]
            } else {
                // Element i in series with the impedance below mass i+1.
                let d = z[i] + below;
                if d.norm() == 0.0 {
                    return None;
                }
                z[i] * below / d
            };
            below = own + down;
        }
        (below.norm() > 0.0).then(|| below.inv())
    }

    /// The receptance of a head of strips: the strips' mean displacement under a harmonic
    /// force shared equally between them, `(K_P − ω² M_P + iω C_P) x = F₀/S Σ e_s` (Eq. 16 in
    /// frequency, the strips' springs in `K_P` and `C_P`), by Gaussian elimination with partial
    /// pivoting. `None` where the dynamic stiffness is singular.
    fn receptance_of_strips(&self, w: f64) -> Option<Complex<f64>> {
        let (k, c) = self.matrices();
        let m = self.mass_vector();
        let (n, ns) = (m.len(), self.strips.len());
        let mut d: Vec<Complex<f64>> = (0..n * n)
            .map(|ij| Complex::new(k[ij], w * c[ij]))
            .collect();
        for i in 0..n {
            d[i * n + i] -= w * w * m[i];
        }
        let mut x: Vec<Complex<f64>> = (0..n)
            .map(|i| Complex::new(if i < ns { 1.0 / ns as f64 } else { 0.0 }, 0.0))
            .collect();
        for col in 0..n {
            let piv = (col..n)
                .max_by(|&a, &b| d[a * n + col].norm().total_cmp(&d[b * n + col].norm()))?;
            if d[piv * n + col].norm() == 0.0 {
                return None;
            }
            for j in 0..n {
                d.swap(col * n + j, piv * n + j);
            }
            x.swap(col, piv);
            for r in col + 1..n {
                let f = d[r * n + col] / d[col * n + col];
                for j in col..n {
                    let v = d[col * n + j];
                    d[r * n + j] -= f * v;
                }
                let xc = x[col];
                x[r] -= f * xc;
            }
        }
        for col in (0..n).rev() {
            let mut acc = x[col];
            for j in col + 1..n {
                acc -= d[col * n + j] * x[j];
            }
            x[col] = acc / d[col * n + col];
        }
        Some(x[..ns].iter().sum::<Complex<f64>>() / ns as f64)
    }

    /// Kinetic and spring energy of the chain (J) and the potential of its constant forces
    /// (−F·y), at speed `v_kmh`.
    pub fn energy(&self, y: &[f64], v: &[f64], v_kmh: f64) -> (f64, f64, f64) {
        let n = self.masses_kg.len();
        let (mut kin, mut pot) = (0.0, 0.0);
        for i in 0..n {
            kin += 0.5 * self.masses_kg[i] * v[i] * v[i];
            let stretch = if i + 1 < n { y[i] - y[i + 1] } else { y[i] };
            pot += 0.5 * self.stiffness_n_per_m[i] * stretch * stretch;
        }
        // With an uplift that depends on the height this is the work of the force at the head's
        // present height, not a potential (the table's force is not conservative on the frame).
        let uplift = match &self.uplift_by_height {
            Some(t) => t.at(y[0]),
            None => self.uplift_n,
        };
        let ext = -(aero_force_n(&self.aero_coeffs_kmh, v_kmh) * y[0] + uplift * y[n - 1]);
        (kin, pot, ext)
    }

    /// [`Self::energy`] over every degree of freedom, the strips' masses and springs included
    /// (`y`, `v` by degree of freedom: the strips, then the chain).
    pub fn energy_all(&self, y: &[f64], v: &[f64], v_kmh: f64) -> (f64, f64, f64) {
        let ns = self.strips.len();
        let (mut kin, mut pot, ext) = self.energy(&y[ns..], &v[ns..], v_kmh);
        for (s, st) in self.strips.iter().enumerate() {
            kin += 0.5 * st.mass_kg * v[s] * v[s];
            let stretch = y[s] - y[ns];
            pot += 0.5 * st.stiffness_n_per_m * stretch * stretch;
        }
        (kin, pot, ext)
    }

    /// [`Self::dissipation`] over every degree of freedom, the strips' dampers included.
    pub fn dissipation_all(&self, v: &[f64]) -> f64 {
        let ns = self.strips.len();
        let strips: f64 = (self.strips.iter().enumerate())
            .map(|(s, st)| st.damping_ns_per_m * (v[s] - v[ns]) * (v[s] - v[ns]))
            .sum();
        self.dissipation(&v[ns..]) + strips
    }

    /// Rate of energy dissipation in the chain's dampers, W.
    pub fn dissipation(&self, v: &[f64]) -> f64 {
        let n = self.masses_kg.len();
        (0..n)
            .map(|i| {
                let rel = if i + 1 < n { v[i] - v[i + 1] } else { v[i] };
                self.damping_ns_per_m[i] * rel * rel
            })
            .sum()
    }
}
