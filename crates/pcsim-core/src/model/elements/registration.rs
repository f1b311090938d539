//! Lateral registration: a spring to ground at a clamp (issue 12). The contact wire's steady arm
//! holds the wire at its stagger with a lateral stiffness and carries the arm's mass in lateral
//! motion; the messenger's support (cantilever) holds the messenger laterally. The arm's clamp
//! sits `e_s` above the contact wire's axis, so the clamp moves by `z + e_s φ` and the spring's
//! force also twists the wire: `F = −k (z + e_s φ)` on `z`, `e_s F` on `φ`. A static upward force
//! `F_v` on the clamp (a simple catenary's steady arm holds the wire's weight there) restores the
//! rotation with `−F_v e_s φ`, as a dropper's tension does (`dropper.rs`), and the clamp itself
//! resists the rotation with a torsional stiffness `k_φ`. The mass is exact (an
//! implicit point mass, as for the vertical steady arm).

use super::{Attach, Io, PointElement, Slot, Weight, WindowMap};

/// One lateral registration.
#[derive(Debug, Clone, PartialEq)]
pub struct Registration {
    /// The wire's lateral motion at the registration point.
    pub at: Attach,
    /// The wire's rotation there (the ground when torsion is not modelled or the clamp is
    /// central).
    pub twist: Attach,
    /// Height of the clamp above the wire's axis, m.
    pub eccentricity_m: f64,
    /// Lateral stiffness of the registration, N/m.
    pub stiffness_n_per_m: f64,
    /// Mass moving with the wire laterally (the steady arm), kg.
    pub mass_kg: f64,
    /// Static upward force on the clamp, N.
    pub vertical_force_n: f64,
    /// The clamp's resistance to the wire's rotation, N·m/rad.
    pub torsional_stiffness_nm_per_rad: f64,
}

impl Registration {
    /// Torsional stiffness at the clamp: the clamp's own and the static force's `F_v e_s`.
    fn twist_stiffness(&self) -> f64 {
        self.torsional_stiffness_nm_per_rad + self.vertical_force_n * self.eccentricity_m
    }
}

/// All lateral registrations of a model.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Registrations(pub Vec<Registration>);

/// The clamp's displacement `z + e φ` and the spring force on it, `−k (z + e φ)`.
#[inline]
pub fn registration_force(k: f64, e: f64, z: f64, phi: f64) -> (f64, f64) {
    let d = z + e * phi;
    (d, -k * d)
}

impl PointElement for Registrations {
    fn kind(&self) -> &'static str {
        "registration"
    }
    fn len(&self) -> usize {
        self.0.len()
    }
    fn arity(&self) -> usize {
        2
    }
    fn attachment(&self, i: usize, a: usize) -> Attach {
        if a == 0 {
            self.0[i].at
        } else {
            self.0[i].twist
        }
    }
    fn implicit(&self, i: usize) -> Option<(usize, Weight)> {
        let m = self.0[i].mass_kg;
        (m > 0.0).then_some((0, Weight::Mass(m)))
    }
    fn stiffness(&self, i: usize) -> f64 {
        self.0[i].stiffness_n_per_m
    }
    fn add_forces(&self, slots: &[Slot], io: &mut Io) {
        for (r, s) in self.0.iter().zip(slots.chunks_exact(2)) {
            let (z, t) = (s[0].u as usize, s[1].u as usize);
            let (_, f) =
                registration_force(r.stiffness_n_per_m, r.eccentricity_m, io.u[z], io.u[t]);
            io.f[z] += f;
            io.f[t] += r.eccentricity_m * f - r.twist_stiffness() * io.u[t];
        }
    }
    fn energy(&self, slots: &[Slot], io: &Io) -> f64 {
        self.0
            .iter()
            .zip(slots.chunks_exact(2))
            .map(|(r, s)| {
                let (d, _) = registration_force(
                    r.stiffness_n_per_m,
                    r.eccentricity_m,
                    io.u[s[0].u as usize],
                    io.u[s[1].u as usize],
                );
                let phi = io.u[s[1].u as usize];
                0.5 * r.stiffness_n_per_m * d * d
                    + 0.5 * r.twist_stiffness() * phi * phi
                    + 0.5 * r.mass_kg * io.v[s[0].v as usize].powi(2)
            })
            .sum()
    }
    fn restrict(&self, w: &WindowMap) -> Box<dyn PointElement> {
        Box::new(Registrations(
            self.0
                .iter()
                .filter_map(|r| {
                    Some(Registration {
                        at: w.map(r.at)?,
                        twist: w.map(r.twist)?,
                        ..r.clone()
                    })
                })
                .collect(),
        ))
    }
    fn clone_box(&self) -> Box<dyn PointElement> {
        Box::new(self.clone())
    }
    fn as_any(&self) -> &dyn std::any::Any {
        self
    }
}
