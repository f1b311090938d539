//! Pantograph–wire contact (Eq. 19): a penalty spring that acts only in compression, per pair of
//! pantograph and contact wire, at the point under the pantograph. A prescribed load (a constant
//! moving force, or the measured force of a hardware-in-the-loop rig) takes its place where the
//! pantograph is not modelled.
//!
//! **The running face.** A new contact wire's running face is round: its lowest point stays
//! under the axis whatever the rotation, so the contact force has no moment about the axis and
//! the contact point does not move sideways as the wire turns (`e_c = 0`, the default and the
//! presets'). A contact point fixed to the section `e_c` below the axis (a worn, flat running
//! face; `catenary.lateral.contact_point_eccentricity_m`) is modelled too: a rotation φ lifts it
//! by `e_c φ²/2`, so the penetration is `d = y_head − y_wire − e_c φ²/2`, and the contact force
//! twists the wire with `F e_c φ` (it pushes up below the axis: the moment turns the wire
//! further, a negative torsional stiffness `−F e_c`); its lateral position is `z − e_c φ`
//! (`solve::Integrator`). Contact exists only on the head: where that
//! lateral position lies beyond the pantograph's half-width (`head_half_width_m`), the wire has
//! left the head and the contact force is zero (`Io::off_head`). Nor is there contact where the
//! pantograph is beyond the wire's ends (`Io::absent`: a line's tension lengths end, issue 21):
//! a pantograph has one contact per contact wire, and in an overlap it touches one, both or the
//! other.

use super::{Attach, Io, PointElement, Slot, WindowMap};
use crate::model::dof::Direction;

/// How the contact force arises.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ContactLaw {
    /// Eq. 19: `F = k_n d_r` while the strip presses on the wire (`d_r ≥ 0`), else 0.
    Penalty {
        /// Penalty stiffness k_n, N/m.
        stiffness_n_per_m: f64,
    },
    /// A prescribed load: `Io::loads[load]` (the vertical loads of the pantographs first, then
    /// their lateral ones).
    Prescribed {
        /// Index into `Io::loads`.
        load: usize,
    },
}

/// One contact head of a pantograph (its head, or one of its collector strips) on one contact
/// wire.
#[derive(Debug, Clone, PartialEq)]
pub struct Contact {
    /// Index of the pantograph.
    pub pantograph: usize,
    /// The contact head: the collector strip's index (0 for a head without strips).
    pub head: usize,
    /// Where the contact point is ahead of the pantograph's position, m (a strip's place).
    pub along_m: f64,
    /// Index of the contact wire.
    pub wire: usize,
    /// Direction of the contact (vertical).
    pub dir: Direction,
    /// How the force arises.
    pub law: ContactLaw,
    /// Depth of the contact point below the wire's axis, m (used when the wire's rotation is
    /// modelled: `twist`).
    pub eccentricity_m: f64,
    /// Whether the wire's rotation under the pantograph enters (torsion modelled).
    pub twist: bool,
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

impl ContactLaw {
    /// The prescribed law of pantograph `pantograph`'s contact in direction `dir`, among
    /// `n_pantographs`: `Io::loads` holds the vertical loads of the pantographs first, then
    /// their lateral ones.
    pub fn prescribed(dir: Direction, pantograph: usize, n_pantographs: usize) -> Self {
        ContactLaw::Prescribed {
            load: match dir {
                Direction::Vertical => pantograph,
                _ => n_pantographs + pantograph,
            },
        }
    }
}

/// All contacts of a model.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Contacts(pub Vec<Contact>);

impl Contacts {
    /// Whether the contact whose wire point is slot `w` carries prescribed load `load`: a
    /// measured (or constant moving) force is the total on the head, so where a pantograph runs
    /// under two contact wires (an overlap) it acts on one, the lowest present wire, which a
    /// rigid strip meets first (the first of equal heights; in the other directions the first
    /// present one). Without a second wire under the head it is the only one.
    fn carries(&self, slots: &[Slot], io: &Io, load: usize, w: usize) -> bool {
        let mut best: Option<(usize, f64)> = None;
        for (c, s) in self.0.iter().zip(slots.chunks_exact(3)) {
            let k = s[0].u as usize;
            if c.law != (ContactLaw::Prescribed { load }) || io.absent[k] {
                continue;
            }
            let h = if c.dir == Direction::Vertical {
                io.u[k]
            } else {
                0.0
            };
            if best.is_none_or(|(_, hb)| h < hb) {
                best = Some((k, h));
            }
        }
        best.is_some_and(|(k, _)| k == w)
    }
}

impl PointElement for Contacts {
    fn kind(&self) -> &'static str {
        "contact"
    }
    fn len(&self) -> usize {
        self.0.len()
    }
    fn arity(&self) -> usize {
        3
    }
    fn attachment(&self, i: usize, a: usize) -> Attach {
        let c = &self.0[i];
        match a {
            0 => Attach::Moving {
                wire: c.wire,
                dir: c.dir,
                pantograph: c.pantograph,
                head: c.head,
                along_m: c.along_m,
            },
            1 => Attach::Head {
                pantograph: c.pantograph,
                head: c.head,
            },
            _ if c.twist => Attach::Moving {
                wire: c.wire,
                dir: Direction::Torsional,
                pantograph: c.pantograph,
                head: c.head,
                along_m: c.along_m,
            },
            _ => Attach::Ground,
        }
    }
    fn stiffness(&self, i: usize) -> f64 {
        match self.0[i].law {
            ContactLaw::Penalty { stiffness_n_per_m } => stiffness_n_per_m,
            ContactLaw::Prescribed { .. } => 0.0,
        }
    }
    fn add_forces(&self, slots: &[Slot], io: &mut Io) {
        for (c, s) in self.0.iter().zip(slots.chunks_exact(3)) {
            let (w, h, t) = (s[0].u as usize, s[1].u as usize, s[2].u as usize);
            let phi = io.u[t];
            let lift = 0.5 * c.eccentricity_m * phi * phi;
            let f = match c.law {
                // Contact exists only on the head: beyond it the wire has left the pantograph.
                _ if io.off_head[w] || io.absent[w] => 0.0,
                ContactLaw::Penalty { stiffness_n_per_m } => {
                    penalty_force(stiffness_n_per_m, io.u[h] - io.u[w] - lift)
                }
                ContactLaw::Prescribed { load } if self.carries(slots, io, load, w) => {
                    io.loads[load]
                }
                ContactLaw::Prescribed { .. } => 0.0,
            };
            io.f[w] += f;
            io.f[h] += -f;
            io.f[t] += f * c.eccentricity_m * phi;
        }
    }
    fn energy(&self, slots: &[Slot], io: &Io) -> f64 {
        let mut e = 0.0;
        for (c, s) in self.0.iter().zip(slots.chunks_exact(3)) {
            let (w, h, t) = (s[0].u as usize, s[1].u as usize, s[2].u as usize);
            if let (ContactLaw::Penalty { stiffness_n_per_m }, false) =
                (c.law, io.off_head[w] || io.absent[w])
            {
                let lift = 0.5 * c.eccentricity_m * io.u[t] * io.u[t];
                e += penalty_energy(stiffness_n_per_m, io.u[h] - io.u[w] - lift);
            }
        }
        e
    }
    fn restrict(&self, w: &WindowMap) -> Box<dyn PointElement> {
        // Contact with the wires that reach into the window (a line's tension lengths end).
        Box::new(Contacts(
            self.0
                .iter()
                .filter_map(|c| {
                    Some(Contact {
                        wire: w.wire_map[c.wire]?,
                        ..c.clone()
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
