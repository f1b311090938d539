//! Droppers: tension-only springs between an upper attachment (the messenger, or a stitch node)
//! and the contact wire (Eq. 15 with the static preload, reference README §2.8).

use super::{Attach, Io, PointElement, Slot, WindowMap};

/// One dropper.
#[derive(Debug, Clone, PartialEq)]
pub struct Dropper {
    /// Position along the track (model coordinates), m.
    pub x_m: f64,
    /// Stiffness in tension, N/m (zero in compression).
    pub stiffness_n_per_m: f64,
    /// Static tension at the contact-wire clamp, N.
    pub preload_n: f64,
    /// The messenger at `x_m`, or the stitch node the dropper hangs from.
    pub top: Attach,
    /// The contact wire at `x_m`.
    pub bottom: Attach,
}

/// Eq. 15 with preload: the force change from the static state of a dropper of stiffness `k`,
/// preload `f0` and elongation `e` (top minus bottom deviation): `max(f0 + k e, 0) − f0`. Returns
/// the change and whether the dropper is slack.
#[inline]
pub fn dropper_force_change(f0: f64, k: f64, e: f64) -> (f64, bool) {
    let t = f0 + k * e;
    if t > 0.0 {
        (t - f0, false)
    } else {
        (-f0, true)
    }
}

/// Energy of the deviation from the static state stored in a dropper (the integral of Eq. 15):
/// `½ k e²` while taut, `−f0 e − f0²/2k` once slack.
#[inline]
pub fn dropper_energy(f0: f64, k: f64, e: f64) -> f64 {
    if f0 + k * e >= 0.0 {
        0.5 * k * e * e
    } else {
        -f0 * e - f0 * f0 / (2.0 * k)
    }
}

/// All droppers of a model.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Droppers(pub Vec<Dropper>);

impl Droppers {
    /// Tension of every dropper, N (`max(F0 + k·e, 0)`), from the slots of a step.
    pub fn tensions(&self, slots: &[Slot], u: &[f64], out: &mut [f64]) {
        for (i, d) in self.0.iter().enumerate() {
            let e = u[slots[2 * i].u as usize] - u[slots[2 * i + 1].u as usize];
            out[i] = (d.preload_n + d.stiffness_n_per_m * e).max(0.0);
        }
    }

    /// Elongation of every dropper from the static state (top minus bottom), m.
    pub fn elongations(&self, slots: &[Slot], u: &[f64], out: &mut [f64]) {
        for i in 0..self.0.len() {
            out[i] = u[slots[2 * i].u as usize] - u[slots[2 * i + 1].u as usize];
        }
    }
}

impl PointElement for Droppers {
    fn kind(&self) -> &'static str {
        "dropper"
    }
    fn len(&self) -> usize {
        self.0.len()
    }
    fn arity(&self) -> usize {
        2
    }
    fn attachment(&self, i: usize, a: usize) -> Attach {
        if a == 0 {
            self.0[i].top
        } else {
            self.0[i].bottom
        }
    }
    fn stiffness(&self, i: usize) -> f64 {
        self.0[i].stiffness_n_per_m
    }
    fn add_forces(&self, slots: &[Slot], io: &mut Io) {
        for (i, d) in self.0.iter().enumerate() {
            let (top, bot) = (slots[2 * i].u as usize, slots[2 * i + 1].u as usize);
            let (df, slack) =
                dropper_force_change(d.preload_n, d.stiffness_n_per_m, io.u[top] - io.u[bot]);
            io.slack += slack as usize;
            io.f[bot] += df;
            io.f[top] += -df;
        }
    }
    fn energy(&self, slots: &[Slot], io: &Io) -> f64 {
        let mut e = 0.0;
        for (i, d) in self.0.iter().enumerate() {
            let el = io.u[slots[2 * i].u as usize] - io.u[slots[2 * i + 1].u as usize];
            e += dropper_energy(d.preload_n, d.stiffness_n_per_m, el);
        }
        e
    }
    fn restrict(&self, w: &WindowMap) -> Box<dyn PointElement> {
        Box::new(Droppers(
            self.0
                .iter()
                .filter(|d| w.inside(d.x_m))
                .filter_map(|d| {
                    Some(Dropper {
                        x_m: d.x_m - w.origin_m,
                        top: w.map(d.top)?,
                        bottom: w.map(d.bottom)?,
                        ..d.clone()
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
