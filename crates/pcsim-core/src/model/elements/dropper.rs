//! Droppers: tension-only springs between an upper attachment (the messenger, or a stitch node)
//! and the contact wire (Eq. 15 with the static preload, reference README §2.8), and, when
//! lateral motion is modelled, pendulums between the two wires.
//!
//! # The three-dimensional law (issue 12)
//! The clamp on the contact wire sits `e_d` above the wire's axis, so a rotation φ of the wire
//! moves it laterally by `e_d φ` and down by `e_d φ²/2` (to second order). A dropper of static
//! length `L` whose top is offset laterally by `δ = z_top − z_wire − e_d φ` from its clamp is
//! then stretched by
//!
//! ```text
//! s = e + δ²/2L + e_d φ²/2,     e the vertical elongation (top minus bottom)
//! ```
//!
//! and its potential, counted from the static state, is `V = f0 (s − e) + D(s)`, `D` the
//! tension-only spring energy of Eq. 15 (`dropper_energy`). So
//! - the vertical force change is Eq. 15 at the stretched length;
//! - the lateral force is the pendulum's `T δ / L` with the current tension `T` (zero when
//!   slack), as issue 12 asks;
//! - the moment on the wire is `e_d T δ / L − T e_d φ`: the lateral force at the eccentric clamp,
//!   and the restoring moment of the tension hanging the wire from a point above its axis. The
//!   latter is what holds the wire against rolling about its clamps (a rotation that moves the
//!   axis but not the clamps): without it the lateral and torsional statics under wind are
//!   singular in practice.
//!
//! Without lateral motion the lateral and torsional attachments are the ground, `δ = φ = 0`, and
//! the law is exactly the vertical one.

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
    /// Static length, m (the pendulum's length).
    pub length_m: f64,
    /// The messenger's lateral motion at `x_m` (the ground when lateral motion is not modelled;
    /// a stitch dropper's top moves laterally with the messenger).
    pub top_lateral: Attach,
    /// The contact wire's lateral motion at `x_m` (or the ground).
    pub bottom_lateral: Attach,
    /// The contact wire's rotation at `x_m` (or the ground).
    pub bottom_twist: Attach,
    /// Height of the clamp above the contact wire's axis, m.
    pub eccentricity_m: f64,
}

/// Number of attachments of a dropper: top, bottom (vertical), top, bottom (lateral), bottom
/// rotation.
pub const ARITY: usize = 5;

/// The geometry of a dropper in three dimensions: stretch beyond the vertical elongation, from
/// the lateral offset `δ` of its top (length `len`) and the rotation `φ` of a clamp `ecc` above
/// the wire's axis: `δ²/2L + e_d φ²/2`.
#[inline]
pub fn dropper_extra_stretch(len: f64, delta: f64, ecc: f64, phi: f64) -> f64 {
    delta * delta / (2.0 * len) + 0.5 * ecc * phi * phi
}

/// Eq. 15 with preload in three dimensions (see the module): for the vertical elongation `e`,
/// the lateral offset `δ` of the top from the clamp and the rotation `φ` of the contact wire,
/// returns the vertical force change on the clamp (as [`dropper_force_change`] at the stretched
/// length), the lateral force on the clamp `T δ / L`, the moment on the wire
/// `e_d (T δ / L − T φ)`, and whether the dropper is slack.
#[inline]
pub fn dropper_force_3d(
    f0: f64,
    k: f64,
    len: f64,
    ecc: f64,
    e: f64,
    delta: f64,
    phi: f64,
) -> (f64, f64, f64, bool) {
    let stretch = e + dropper_extra_stretch(len, delta, ecc, phi);
    let (df, slack) = dropper_force_change(f0, k, stretch);
    let t = f0 + df;
    let lat = t * delta / len;
    (df, lat, ecc * (lat - t * phi), slack)
}

/// The potential of [`dropper_force_3d`], counted from the static state: `f0 (s − e) + D(s)`.
#[inline]
pub fn dropper_energy_3d(f0: f64, k: f64, len: f64, ecc: f64, e: f64, delta: f64, phi: f64) -> f64 {
    let extra = dropper_extra_stretch(len, delta, ecc, phi);
    f0 * extra + dropper_energy(f0, k, e + extra)
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
pub struct Droppers {
    list: Vec<Dropper>,
    /// No dropper has a lateral or torsional attachment (every one on the ground): the force
    /// loop takes the vertical law without asking each dropper.
    vertical: bool,
}

impl Droppers {
    /// The droppers of a model.
    pub fn new(list: Vec<Dropper>) -> Self {
        let vertical = list.iter().all(|d| {
            [&d.top_lateral, &d.bottom_lateral, &d.bottom_twist]
                .iter()
                .all(|a| matches!(a, Attach::Ground))
        });
        Droppers { list, vertical }
    }

    /// The droppers, in the order of their slots.
    pub fn list(&self) -> &[Dropper] {
        &self.list
    }

    /// Tension of every dropper, N (`max(F0 + k·e, 0)` at the stretched length), from the
    /// slots of a step.
    pub fn tensions(&self, slots: &[Slot], u: &[f64], out: &mut [f64]) {
        for (i, d) in self.list.iter().enumerate() {
            let (e, delta, phi) = Self::geometry(d, &slots[ARITY * i..ARITY * (i + 1)], u);
            let (df, _, _, _) = dropper_force_3d(
                d.preload_n,
                d.stiffness_n_per_m,
                d.length_m,
                d.eccentricity_m,
                e,
                delta,
                phi,
            );
            out[i] = d.preload_n + df;
        }
    }

    /// Vertical elongation of every dropper from the static state (top minus bottom), m.
    pub fn elongations(&self, slots: &[Slot], u: &[f64], out: &mut [f64]) {
        for (i, d) in self.list.iter().enumerate() {
            out[i] = Self::geometry(d, &slots[ARITY * i..ARITY * (i + 1)], u).0;
        }
    }

    /// A dropper with no lateral or torsional attachment (all on the ground, slot 0): δ = φ = 0
    /// and the law is the vertical Eq. 15, evaluated as `dropper_force_3d` evaluates it (the same
    /// operations on the same values, so the same bytes) without the pendulum's terms, which
    /// would add zeros to the ground's sink. Returns whether it is slack.
    #[inline(always)]
    fn add_vertical(d: &Dropper, s: &[Slot], io: &mut Io) -> bool {
        let e = io.u[s[0].u as usize] - io.u[s[1].u as usize];
        let (df, slack) = dropper_force_change(d.preload_n, d.stiffness_n_per_m, e);
        io.f[s[1].u as usize] += df;
        io.f[s[0].u as usize] += -df;
        slack
    }

    /// Vertical elongation, lateral offset of the top from the clamp, and the wire's rotation.
    #[inline(always)]
    fn geometry(d: &Dropper, s: &[Slot], u: &[f64]) -> (f64, f64, f64) {
        let e = u[s[0].u as usize] - u[s[1].u as usize];
        let phi = u[s[4].u as usize];
        let delta = u[s[2].u as usize] - u[s[3].u as usize] - d.eccentricity_m * phi;
        (e, delta, phi)
    }
}

impl PointElement for Droppers {
    fn kind(&self) -> &'static str {
        "dropper"
    }
    fn len(&self) -> usize {
        self.list.len()
    }
    fn arity(&self) -> usize {
        ARITY
    }
    fn attachment(&self, i: usize, a: usize) -> Attach {
        let d = &self.list[i];
        match a {
            0 => d.top,
            1 => d.bottom,
            2 => d.top_lateral,
            3 => d.bottom_lateral,
            _ => d.bottom_twist,
        }
    }
    fn stiffness(&self, i: usize) -> f64 {
        self.list[i].stiffness_n_per_m
    }
    fn add_forces(&self, slots: &[Slot], io: &mut Io) {
        // The slack count kept in a register, added once.
        let mut slack_n = 0;
        let droppers = self.list.iter().zip(slots.chunks_exact(ARITY));
        if self.vertical {
            for (d, s) in droppers {
                slack_n += Self::add_vertical(d, s, io) as usize;
            }
            io.slack += slack_n;
            return;
        }
        for (d, s) in droppers {
            if s[2].u | s[3].u | s[4].u == 0 {
                slack_n += Self::add_vertical(d, s, io) as usize;
                continue;
            }
            let (e, delta, phi) = Self::geometry(d, s, io.u);
            let (df, fl, m, slack) = dropper_force_3d(
                d.preload_n,
                d.stiffness_n_per_m,
                d.length_m,
                d.eccentricity_m,
                e,
                delta,
                phi,
            );
            slack_n += slack as usize;
            io.f[s[1].u as usize] += df;
            io.f[s[0].u as usize] += -df;
            io.f[s[3].u as usize] += fl;
            io.f[s[4].u as usize] += m;
            io.f[s[2].u as usize] += -fl;
        }
        io.slack += slack_n;
    }
    fn energy(&self, slots: &[Slot], io: &Io) -> f64 {
        let mut en = 0.0;
        for (d, s) in self.list.iter().zip(slots.chunks_exact(ARITY)) {
            let (e, delta, phi) = Self::geometry(d, s, io.u);
            en += dropper_energy_3d(
                d.preload_n,
                d.stiffness_n_per_m,
                d.length_m,
                d.eccentricity_m,
                e,
                delta,
                phi,
            );
        }
        en
    }
    fn restrict(&self, w: &WindowMap) -> Box<dyn PointElement> {
        Box::new(Droppers::new(
            self.list
                .iter()
                .filter(|d| w.inside(d.x_m))
                .filter_map(|d| {
                    Some(Dropper {
                        x_m: d.x_m - w.origin_m,
                        top: w.map(d.top)?,
                        bottom: w.map(d.bottom)?,
                        top_lateral: w.map(d.top_lateral)?,
                        bottom_lateral: w.map(d.bottom_lateral)?,
                        bottom_twist: w.map(d.bottom_twist)?,
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
