//! Pantograph–wire contact (Eq. 19): a penalty spring that acts only in compression, per pair of
//! pantograph and contact wire, at the point under the pantograph. A prescribed load (a constant
//! moving force, or the measured force of a hardware-in-the-loop rig) takes its place where the
//! pantograph is not modelled.

use super::{Attach, Io, PointElement, Slot, WindowMap};
use crate::model::dof::Direction;

/// How the contact force arises.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ContactLaw {
    /// Eq. 19: `F = k_n d_r` while the strip presses on the wire (`d_r ≥ 0`), else 0.
    Penalty { stiffness_n_per_m: f64 },
    /// The pantograph's prescribed load (`Io::loads`).
    Prescribed,
}

/// One pantograph on one contact wire.
#[derive(Debug, Clone, PartialEq)]
pub struct Contact {
    pub pantograph: usize,
    pub wire: usize,
    pub dir: Direction,
    pub law: ContactLaw,
}

/// Eq. 19: contact force of a penalty spring of stiffness `k_n` at penetration `d_r` (strip
/// height minus wire height), N.
#[inline]
pub fn penalty_force(k_n: f64, d_r: f64) -> f64 {
    k_n * d_r.max(0.0)
}

/// Energy stored in the penalty spring at penetration `d_r`, J.
#[inline]
pub fn penalty_energy(k_n: f64, d_r: f64) -> f64 {
    if d_r > 0.0 {
        0.5 * k_n * d_r * d_r
    } else {
        0.0
    }
}

/// All contacts of a model.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Contacts(pub Vec<Contact>);

impl PointElement for Contacts {
    fn kind(&self) -> &'static str {
        "contact"
    }
    fn len(&self) -> usize {
        self.0.len()
    }
    fn arity(&self) -> usize {
        2
    }
    fn attachment(&self, i: usize, a: usize) -> Attach {
        let c = &self.0[i];
        if a == 0 {
            Attach::Moving {
                wire: c.wire,
                dir: c.dir,
                pantograph: c.pantograph,
            }
        } else {
            Attach::Head(c.pantograph)
        }
    }
    fn stiffness(&self, i: usize) -> f64 {
        match self.0[i].law {
            ContactLaw::Penalty { stiffness_n_per_m } => stiffness_n_per_m,
            ContactLaw::Prescribed => 0.0,
        }
    }
    fn add_forces(&self, slots: &[Slot], io: &mut Io) {
        for (i, c) in self.0.iter().enumerate() {
            let (w, h) = (slots[2 * i].u as usize, slots[2 * i + 1].u as usize);
            let f = match c.law {
                ContactLaw::Penalty { stiffness_n_per_m } => {
                    penalty_force(stiffness_n_per_m, io.u[h] - io.u[w])
                }
                ContactLaw::Prescribed => io.loads[c.pantograph],
            };
            io.f[w] += f;
            io.f[h] += -f;
        }
    }
    fn energy(&self, slots: &[Slot], io: &Io) -> f64 {
        let mut e = 0.0;
        for (i, c) in self.0.iter().enumerate() {
            if let ContactLaw::Penalty { stiffness_n_per_m } = c.law {
                let (w, h) = (slots[2 * i].u as usize, slots[2 * i + 1].u as usize);
                e += penalty_energy(stiffness_n_per_m, io.u[h] - io.u[w]);
            }
        }
        e
    }
    fn restrict(&self, _w: &WindowMap) -> Box<dyn PointElement> {
        Box::new(self.clone())
    }
    fn clone_box(&self) -> Box<dyn PointElement> {
        Box::new(self.clone())
    }
    fn as_any(&self) -> &dyn std::any::Any {
        self
    }
}
