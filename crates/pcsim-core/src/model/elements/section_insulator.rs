//! Section insulators (issue 55): a concentrated element in the contact wire — its mass, its
//! bending stiffness over its length, and the runners the pantograph rides on (their height
//! profile is a geometric deviation of the running surface, [`runner_height_m`], which the
//! compile step adds to the contact wire's profile as an irregularity is: the pantograph sees
//! the wire at `y_static + r + w`).
//!
//! **The law.** An insulator of length `ℓ` centred at `x_c` stiffer than the wire it is inserted
//! in (`EI_si ≥ EI_wire`) adds the bending energy of the difference over its length at the
//! curvature of its three points `x_c − ℓ/2`, `x_c`, `x_c + ℓ/2` (spacing `h = ℓ/2`):
//! `E = ½ ΔEI ℓ κ²`, `κ = (u_a − 2u_c + u_b)/h²`, so `E = ½ c s²` with `s = u_a − 2u_c + u_b` and
//! `c = ΔEI ℓ / h⁴` ([`curvature_stiffness_n_per_m`]); the forces are `−c s`, `2c s`, `−c s`. Its
//! mass is a point mass at the centre, exact in the wire's mass matrix as a steady arm's is
//! (reference README §5). A very stiff insulator holds its three points on a line: the rigid-bar
//! limit. An insulator of zero mass and the wire's own stiffness adds nothing (`c = 0`).
//!
//! The same law acts in each modelled translation (vertical, lateral); the insulator's
//! rotational inertia about the wire's axis is not modelled (docs/hard-spots.md).

use super::{Attach, Io, PointElement, Slot, Weight, WindowMap};

/// One section insulator in one direction: its three points on the contact wire (the ends and
/// the centre), its mass at the centre and its curvature stiffness.
#[derive(Debug, Clone, PartialEq)]
pub struct SectionInsulator {
    /// The points on the wire: start, centre, end (model coordinates, one direction).
    pub at: [Attach; 3],
    /// Mass of the insulator, kg (at the centre).
    pub mass_kg: f64,
    /// `c = ΔEI ℓ / h⁴`, N/m ([`curvature_stiffness_n_per_m`]).
    pub curvature_n_per_m: f64,
}

/// The stiffness of the discrete curvature term of an insulator of length `length_m` that is
/// `added_ei_nm2` stiffer in bending than the wire (`ΔEI = EI_si − EI_wire ≥ 0`): `c = ΔEI ℓ/h⁴`
/// with `h = ℓ/2`, N/m (the bending energy `½ ΔEI κ² ℓ` at the three points' curvature).
pub fn curvature_stiffness_n_per_m(added_ei_nm2: f64, length_m: f64) -> f64 {
    let h = 0.5 * length_m;
    added_ei_nm2 * length_m / h.powi(4)
}

/// The runners' height above the wire's design height at `x` (track coordinates) of an insulator
/// of length `length_m` centred at `centre_m`, m, upward positive: zero outside it, `prelift_m`
/// over its length, reached by a linear ramp of `ramp_m` at each end (the runners' raised ends
/// that lead a pantograph on and off; `ramp_m` at most half the length).
pub fn runner_height_m(x: f64, centre_m: f64, length_m: f64, ramp_m: f64, prelift_m: f64) -> f64 {
    let d = (x - centre_m).abs();
    let half = 0.5 * length_m;
    if d >= half {
        0.0
    } else if ramp_m > 0.0 && d > half - ramp_m {
        prelift_m * (half - d) / ramp_m
    } else {
        prelift_m
    }
}

/// All section insulators of a model (one instance per insulator and direction).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct SectionInsulators(pub Vec<SectionInsulator>);

impl SectionInsulators {
    /// The curvature `s = u_a − 2u_c + u_b` of instance `i` whose slots are `sl`.
    #[inline]
    fn curvature(sl: &[Slot], u: &[f64]) -> f64 {
        u[sl[0].u as usize] - 2.0 * u[sl[1].u as usize] + u[sl[2].u as usize]
    }
}

impl PointElement for SectionInsulators {
    fn kind(&self) -> &'static str {
        "section_insulator"
    }
    fn len(&self) -> usize {
        self.0.len()
    }
    fn arity(&self) -> usize {
        3
    }
    fn attachment(&self, i: usize, a: usize) -> Attach {
        self.0[i].at[a]
    }
    fn implicit(&self, i: usize) -> Option<(usize, Weight)> {
        let m = self.0[i].mass_kg;
        (m > 0.0).then_some((1, Weight::Mass(m)))
    }
    fn stiffness(&self, i: usize) -> f64 {
        // The largest eigenvalue of c·(1, −2, 1)ᵀ(1, −2, 1).
        6.0 * self.0[i].curvature_n_per_m
    }
    fn add_forces(&self, slots: &[Slot], io: &mut Io) {
        for (e, sl) in self.0.iter().zip(slots.chunks_exact(3)) {
            if e.curvature_n_per_m == 0.0 {
                continue;
            }
            let f = e.curvature_n_per_m * Self::curvature(sl, io.u);
            io.f[sl[0].u as usize] -= f;
            io.f[sl[1].u as usize] += 2.0 * f;
            io.f[sl[2].u as usize] -= f;
        }
    }
    fn energy(&self, slots: &[Slot], io: &Io) -> f64 {
        self.0
            .iter()
            .zip(slots.chunks_exact(3))
            .map(|(e, sl)| {
                0.5 * e.curvature_n_per_m * Self::curvature(sl, io.u).powi(2)
                    + 0.5 * e.mass_kg * io.v[sl[1].v as usize].powi(2)
            })
            .sum()
    }
    fn restrict(&self, w: &WindowMap) -> Box<dyn PointElement> {
        Box::new(SectionInsulators(
            self.0
                .iter()
                .filter_map(|e| {
                    Some(SectionInsulator {
                        at: [w.map(e.at[0])?, w.map(e.at[1])?, w.map(e.at[2])?],
                        ..e.clone()
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
