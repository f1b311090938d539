//! Steady (registration) arms: a lumped mass `m_BT` on the contact wire (paper §2.1) with a
//! spring to ground. The mass is exact: it enters the wire's mass matrix as an implicit point
//! term (explicit point masses suffer from added-mass instability, reference README §5).

use super::{Attach, Io, PointElement, Slot, Weight, WindowMap};

/// One steady arm.
#[derive(Debug, Clone, PartialEq)]
pub struct SteadyArm {
    /// The registration point on the contact wire.
    pub at: Attach,
    /// Mass of the arm, kg.
    pub mass_kg: f64,
    /// Vertical stiffness of the arm, N/m.
    pub stiffness_n_per_m: f64,
}

/// All steady arms of a model.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct SteadyArms(pub Vec<SteadyArm>);

impl PointElement for SteadyArms {
    fn kind(&self) -> &'static str {
        "steady_arm"
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
    fn implicit(&self, i: usize) -> Option<(usize, Weight)> {
        let m = self.0[i].mass_kg;
        (m > 0.0).then_some((0, Weight::Mass(m)))
    }
    fn stiffness(&self, i: usize) -> f64 {
        self.0[i].stiffness_n_per_m
    }
    fn add_forces(&self, slots: &[Slot], io: &mut Io) {
        for (a, sl) in self.0.iter().zip(slots) {
            io.f[sl.u as usize] += -a.stiffness_n_per_m * io.u[sl.u as usize];
        }
    }
    fn energy(&self, slots: &[Slot], io: &Io) -> f64 {
        self.0
            .iter()
            .zip(slots)
            .map(|(a, sl)| {
                0.5 * a.stiffness_n_per_m * io.u[sl.u as usize].powi(2)
                    + 0.5 * a.mass_kg * io.v[sl.v as usize].powi(2)
            })
            .sum()
    }
    fn monitors(&self) -> Vec<Attach> {
        self.0.iter().map(|a| a.at).collect()
    }
    fn restrict(&self, w: &WindowMap) -> Box<dyn PointElement> {
        Box::new(SteadyArms(
            self.0
                .iter()
                .filter_map(|a| {
                    Some(SteadyArm {
                        at: w.map(a.at)?,
                        ..a.clone()
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
