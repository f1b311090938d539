//! Messenger supports: a spring-damper from a wire to the ground at each mast (paper §2.1,
//! "spring-damper elements with stiffness K'_s and damping C'_s"). The damper is also taken
//! implicitly (a light messenger with many modes is unstable with an explicit 1000 N·s/m damper
//! at Δt = 1 ms).

use super::{Attach, Io, PointElement, Slot, Weight, WindowMap};

/// One support.
#[derive(Debug, Clone, PartialEq)]
pub struct Support {
    /// The supported wire point.
    pub at: Attach,
    /// Vertical stiffness, N/m.
    pub stiffness_n_per_m: f64,
    /// Vertical damping, N·s/m.
    pub damping_ns_per_m: f64,
}

/// All supports of a model.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Supports(pub Vec<Support>);

/// Force of a spring-damper to ground on a point with displacement `u` and velocity `v`, N.
#[inline]
pub fn spring_damper_force(k: f64, c: f64, u: f64, v: f64) -> f64 {
    -k * u - c * v
}

impl PointElement for Supports {
    fn kind(&self) -> &'static str {
        "support"
    }
    fn len(&self) -> usize {
        self.0.len()
    }
    fn arity(&self) -> usize {
        1
    }
    fn attachment(&self, i: usize, _a: usize) -> Attach {
        self.0[i].at
    }
    fn needs_velocity(&self, i: usize, _a: usize) -> bool {
        self.0[i].damping_ns_per_m != 0.0
    }
    fn implicit(&self, i: usize) -> Option<(usize, Weight)> {
        let c = self.0[i].damping_ns_per_m;
        (c > 0.0).then_some((0, Weight::Damper(c)))
    }
    fn stiffness(&self, i: usize) -> f64 {
        self.0[i].stiffness_n_per_m
    }
    fn add_forces(&self, slots: &[Slot], io: &mut Io) {
        for (s, sl) in self.0.iter().zip(slots) {
            io.f[sl.u as usize] += spring_damper_force(
                s.stiffness_n_per_m,
                s.damping_ns_per_m,
                io.u[sl.u as usize],
                io.v[sl.v as usize],
            );
        }
    }
    fn energy(&self, slots: &[Slot], io: &Io) -> f64 {
        self.0
            .iter()
            .zip(slots)
            .map(|(s, sl)| 0.5 * s.stiffness_n_per_m * io.u[sl.u as usize].powi(2))
            .sum()
    }
    fn dissipation(&self, slots: &[Slot], io: &Io) -> f64 {
        self.0
            .iter()
            .zip(slots)
            .map(|(s, sl)| s.damping_ns_per_m * io.v[sl.v as usize].powi(2))
            .sum()
    }
    fn restrict(&self, w: &WindowMap) -> Box<dyn PointElement> {
        Box::new(Supports(
            self.0
                .iter()
                .filter_map(|s| {
                    Some(Support {
                        at: w.map(s.at)?,
                        ..s.clone()
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
