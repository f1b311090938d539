//! Everything a step needs besides the state: scratch sized once up front (faer-style, nothing
//! allocated behind the caller's back), the step's outputs (contact samples, slack droppers) and
//! the inputs of hardware-in-the-loop pantographs.

use std::sync::Mutex;

use crate::solve::implicit::ImplicitScratch;
use crate::solve::sampler::SamplerScratch;
use crate::solve::state::Dofs;
use crate::solve::team::{Part, MAX_THREADS};

/// What one step saw at each pantograph.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ContactSample {
    /// Position (model coordinates), m.
    pub position_m: f64,
    /// Contact force (Eq. 19), N; for a prescribed load, the load itself.
    pub force_n: f64,
    /// Contact-wire height at the contact point (static profile + deviation), m.
    pub wire_height_m: f64,
    /// Contact-wire vertical velocity at the contact point, m/s.
    pub wire_velocity_m_s: f64,
    /// Lateral position of the contact point from the track's centre line, m (0 when lateral
    /// motion is not modelled): the stagger, the contact wire's lateral deviation, and its
    /// rotation times the depth of the contact point below its axis.
    pub lateral_m: f64,
    /// The wire's static height at the contact point (its design and static shape), m: the
    /// reference of the blow-up test.
    pub static_height_m: f64,
    /// The wire's static lateral position at the contact point from the track's centre line,
    /// m (the stagger and a curve's bow; 0 without lateral motion).
    pub static_lateral_m: f64,
    /// Rotation of the contact wire about its axis at the contact point, rad (0 when torsion is
    /// not modelled).
    pub twist_rad: f64,
}

/// Largest plausible deviation of the contact wire from its design height (when the model has no
/// messenger to bound it, see [`crate::solve::CompiledModel::max_wire_deviation_m`]) and of the
/// contact point from the track's centre line, m: beyond it a run is treated as blown up.
pub const MAX_PLAUSIBLE_HEIGHT_M: f64 = 2.0;
/// Largest plausible contact force, N.
pub const MAX_PLAUSIBLE_FORCE_N: f64 = 1e6;

impl ContactSample {
    /// What is implausible about this sample, for a blow-up message (`None` when sound).
    pub fn fault(&self, pantograph: usize, max_height_m: f64) -> Option<String> {
        if !(self.force_n.is_finite()
            && self.wire_height_m.is_finite()
            && self.wire_velocity_m_s.is_finite()
            && self.lateral_m.is_finite())
        {
            Some(format!(
                "a non-finite value at pantograph {pantograph} (contact force {} N, wire height {} m, velocity {} m/s, lateral position {} m)",
                self.force_n, self.wire_height_m, self.wire_velocity_m_s, self.lateral_m
            ))
        } else if (self.lateral_m - self.static_lateral_m).abs() >= MAX_PLAUSIBLE_HEIGHT_M {
            Some(format!(
                "the contact point under pantograph {pantograph} is {:.3} m from the wire's static lateral position (more than {MAX_PLAUSIBLE_HEIGHT_M} m)",
                self.lateral_m - self.static_lateral_m
            ))
        } else if (self.wire_height_m - self.static_height_m).abs() >= max_height_m {
            Some(format!(
                "the contact wire under pantograph {pantograph} is {:.3} m from its static height (more than {max_height_m:.3} m, the system height: it would have passed the messenger)",
                self.wire_height_m - self.static_height_m
            ))
        } else if self.force_n.abs() >= MAX_PLAUSIBLE_FORCE_N {
            Some(format!(
                "the contact force at pantograph {pantograph} reached {:.3e} N (more than 1 MN)",
                self.force_n
            ))
        } else {
            None
        }
    }

    /// Finite and physically plausible (the blow-up test of every run loop): the contact wire
    /// within `max_height_m` of its static height (the model's
    /// [`crate::solve::CompiledModel::max_wire_deviation_m`]) and the contact point within
    /// [`MAX_PLAUSIBLE_HEIGHT_M`] of the wire's static lateral position. Measured from the
    /// wire's own static place, not from the nominal height or the track's centre line: a line
    /// designed high, or a curve's bow, is a design, not a blow-up.
    pub fn is_sound(&self, max_height_m: f64) -> bool {
        self.force_n.is_finite()
            && self.wire_height_m.is_finite()
            && self.wire_velocity_m_s.is_finite()
            && self.force_n.abs() < MAX_PLAUSIBLE_FORCE_N
            && (self.wire_height_m - self.static_height_m).abs() < max_height_m
            && (self.lateral_m - self.static_lateral_m).abs() < MAX_PLAUSIBLE_HEIGHT_M
    }
}

/// What an external pantograph (hardware in the loop) applies during a step: where it is and how
/// hard it pushes. Named, in the one place it is defined, so that no caller can swap the two
/// numbers (every front end takes them as force, then position).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ExternalInput {
    /// Position of the contact point, m (model coordinates in the workspace, track coordinates
    /// in the real-time window's last input).
    pub position_m: f64,
    /// Upward contact force on the wire, N.
    pub force_n: f64,
}

/// Scratch, outputs and inputs of [`crate::solve::Integrator::step`]. Make it with
/// [`crate::solve::Integrator::workspace`].
#[derive(Debug, Clone)]
pub struct Workspace {
    /// Displacements at the slots (ground, gathered wire points, nodes, heads, moving points).
    pub(crate) u: Vec<f64>,
    /// Velocities at the velocity slots.
    pub(crate) vel: Vec<f64>,
    /// Force accumulators at the slots.
    pub(crate) f: Vec<f64>,
    /// Sine rows of the moving points, one after the other.
    pub(crate) rows: Vec<f64>,
    #[doc(hidden)]
    pub scr: SamplerScratch,
    pub(crate) imp: ImplicitScratch,
    /// Per part of a run on several threads: its sampler and implicit scratch (empty for one
    /// thread).
    pub(crate) lanes: Vec<(SamplerScratch, ImplicitScratch)>,
    /// Pantograph right-hand side (length: the most degrees of freedom of a pantograph).
    pub(crate) prhs: Vec<f64>,
    /// Prescribed loads per pantograph, N.
    pub(crate) loads: Vec<f64>,
    /// The input of each external pantograph (hardware in the loop).
    pub(crate) external: Vec<ExternalInput>,
    /// By displacement slot: a moving point whose contact point lies beyond its pantograph's
    /// head this step (no contact with that wire).
    pub(crate) off_head: Vec<bool>,
    /// By moving point: its contact point's lateral position this step, m, and the wire's
    /// rotation there where torsion is modelled, rad.
    pub(crate) moving_lateral: Vec<(f64, Option<f64>)>,
    /// Per moving point: the wire's static height and lateral position there (the blow-up
    /// test's reference).
    pub(crate) moving_static: Vec<(f64, f64)>,
    /// By displacement slot: a moving point beyond its wire's ends this step (no contact).
    pub(crate) absent: Vec<bool>,
    /// Per pantograph: the moving point its sample reads this step (the lowest wire present).
    pub(crate) sample_point: Vec<usize>,
    pub(crate) samples: Vec<ContactSample>,
    pub(crate) slack: usize,
    /// Energy evaluation: displacements and velocities at the displacement slots, forces.
    pub(crate) eu: Vec<f64>,
    pub(crate) ev: Vec<f64>,
    pub(crate) ef: Vec<f64>,
    /// Crosswind: the grid's pressures and their generalised forces per loaded wire (one
    /// block of modes per wire), the mean included; each part (basis group) at its offsets.
    pub(crate) wind_p: Vec<f64>,
    pub(crate) wind_q: Vec<f64>,
    /// Crosswind: the field interval whose forces `wind_c` holds (a pure function of it, so
    /// any step in the interval may fill it), and whether they are a quadratic in the
    /// interval's fraction, per part (false when the normal wind changes sign at one of its
    /// grid points: each step then scatters that part's own pressures).
    pub(crate) wind_interval: Option<usize>,
    pub(crate) wind_quadratic: Vec<bool>,
    /// `[A0 | A1 | A2]`, each `k·n`: the generalised forces `A0 + τ A1 + τ² A2` (the mean in
    /// `A0`).
    pub(crate) wind_c: Vec<f64>,
}

impl Workspace {
    /// Set what the external pantograph `p` applies during the next step (its position in model
    /// coordinates).
    pub fn set_external(&mut self, p: usize, input: ExternalInput) {
        self.external[p] = input;
    }

    /// Contact samples of the last step (one per pantograph).
    pub fn samples(&self) -> &[ContactSample] {
        &self.samples
    }

    /// Droppers slack in the last step.
    pub fn slack_droppers(&self) -> usize {
        self.slack
    }
}

/// One part's share of a stage split over threads ([`crate::solve::team`]): its modal
/// coordinates, its displacement and velocity slots, and its scratch.
pub(crate) struct Lane<'a> {
    pub(crate) q: &'a mut [f64],
    pub(crate) v: &'a mut [f64],
    pub(crate) a: &'a mut [f64],
    pub(crate) u: &'a mut [f64],
    pub(crate) vel: &'a mut [f64],
    pub(crate) scr: &'a mut (SamplerScratch, ImplicitScratch),
}

/// The lanes of a split stage, one slot per part, each taken once by the thread of its part.
pub(crate) type Lanes<'a> = [Mutex<Option<Lane<'a>>>; MAX_THREADS];

impl<'a> Lane<'a> {
    /// Cut the modal coordinates, the slots and the scratch into the parts' lanes (the parts
    /// are contiguous and cover each array; see `team::partition`). No allocation.
    pub(crate) fn split(
        parts: &[Part],
        m: &'a mut Dofs,
        u: &'a mut [f64],
        vel: &'a mut [f64],
        scr: &'a mut [(SamplerScratch, ImplicitScratch)],
    ) -> Lanes<'a> {
        let lanes: Lanes<'a> = std::array::from_fn(|_| Mutex::new(None));
        let (mut q, mut v, mut a) = (&mut m.u[..], &mut m.v[..], &mut m.a[..]);
        let (mut u, mut vel, mut scr) = (u, vel, scr);
        for (i, p) in parts.iter().enumerate().take(MAX_THREADS) {
            let nq = p.q.len();
            let (q0, q1) = std::mem::take(&mut q).split_at_mut(nq);
            let (v0, v1) = std::mem::take(&mut v).split_at_mut(nq);
            let (a0, a1) = std::mem::take(&mut a).split_at_mut(nq);
            let (u0, u1) = std::mem::take(&mut u).split_at_mut(p.u.len());
            let (w0, w1) = std::mem::take(&mut vel).split_at_mut(p.v.len());
            let Some((s0, s1)) = std::mem::take(&mut scr).split_first_mut() else {
                break;
            };
            (q, v, a, u, vel, scr) = (q1, v1, a1, u1, w1, s1);
            *lanes[i].lock().unwrap_or_else(|e| e.into_inner()) = Some(Lane {
                q: q0,
                v: v0,
                a: a0,
                u: u0,
                vel: w0,
                scr: s0,
            });
        }
        lanes
    }

    /// Take lane `i` (each once per stage).
    pub(crate) fn take(lanes: &Lanes<'a>, i: usize) -> Option<Lane<'a>> {
        lanes
            .get(i)?
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .take()
    }
}
