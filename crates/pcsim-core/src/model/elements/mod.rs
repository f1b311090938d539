//! Point elements behind one interface: each kind is one file and one [`PointElement`] value
//! holding all its instances.
//!
//! An element states what it attaches to ([`Attach`]), its force law ([`PointElement::add_forces`]),
//! its stored energy and dissipation, its implicit weight if it has one, and how it restricts
//! itself to a window. The integrator resolves every attachment to a [`Slot`] once: an index into
//! the arrays of gathered displacements and velocities and of force accumulators. A force law
//! reads `io.u[slot.u]` and `io.v[slot.v]` and adds to `io.f[slot.u]`; it does not know whether
//! the slot is a point of a wire, a node or the ground.
//!
//! **Adding a kind:** write a file here with a struct implementing [`PointElement`], and register
//! it in `model::build` (where a case becomes a model). Nothing else changes.

pub mod contact;
pub mod dropper;
pub mod registration;
pub mod section_insulator;
pub mod steady_arm;
pub mod stitch;
pub mod support;

use crate::model::dof::Direction;

/// What an element attaches to.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Attach {
    /// A fixed point of a wire's series in one direction (model coordinate `x_m`).
    Wire {
        /// Index into `Model::wires`.
        wire: usize,
        /// The direction.
        dir: Direction,
        /// Model coordinate, m.
        x_m: f64,
    },
    /// A node of the model (a lumped mass with its own degree of freedom, `Model::nodes`).
    Node(usize),
    /// The ground: zero displacement and velocity; forces on it are dropped.
    Ground,
    /// The point of a wire under a pantograph's contact head: it moves with the pantograph,
    /// `along_m` ahead of it (a collector strip's place on the head), and the height it reads
    /// is the static profile plus the deviation.
    Moving {
        /// Index into `Model::wires`.
        wire: usize,
        /// The direction.
        dir: Direction,
        /// Index of the pantograph.
        pantograph: usize,
        /// The contact head: the strip's index (0 for a head without strips).
        head: usize,
        /// Where the point is ahead of the pantograph's position, m.
        along_m: f64,
    },
    /// A contact head of a pantograph: its running face (the head mass, or collector strip
    /// `head`). A prescribed load has none; its slot then reads zero.
    Head {
        /// Index of the pantograph.
        pantograph: usize,
        /// The strip's index (0 for a head without strips).
        head: usize,
    },
}

/// An attachment resolved by the integrator: the index of its displacement (and force) and of its
/// velocity in the arrays of [`Io`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Slot {
    /// Index in the displacement (and force) arrays.
    pub u: u32,
    /// Index in the velocity array.
    pub v: u32,
}

/// An element's term taken implicitly in the wire's system matrix (point mass, or point damper:
/// the integrator adds `mass` or `Δt/2 · damper` at the point).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Weight {
    /// A point mass, kg.
    Mass(f64),
    /// A point damper, N·s/m (the integrator takes Δt/2 of it).
    Damper(f64),
}

/// What the force laws read and write during a step or an energy evaluation.
pub struct Io<'a> {
    /// Displacements (heights for moving points), by `Slot::u`.
    pub u: &'a [f64],
    /// Velocities, by `Slot::v`.
    pub v: &'a [f64],
    /// Force accumulators (upward / positive along the direction), by `Slot::u`.
    pub f: &'a mut [f64],
    /// Prescribed loads per pantograph (moving forces, hardware-in-the-loop input), N.
    pub loads: &'a [f64],
    /// By displacement slot: a moving point whose contact point lies beyond its pantograph's
    /// head (the wire has left the head), so there is no contact with that wire (issue 20).
    pub off_head: &'a [bool],
    /// By displacement slot: a moving point that lies beyond its wire's ends (a pantograph
    /// outside a tension length), so there is no wire to touch there (issue 21).
    pub absent: &'a [bool],
    /// Droppers found slack in this evaluation.
    pub slack: usize,
}

/// The window a model is restricted to: `[origin, origin + length]` in model coordinates, and the
/// new index of each node (`None` when it falls outside).
#[derive(Debug, Clone)]
pub struct WindowMap {
    /// Start of the window, model coordinates, m.
    pub origin_m: f64,
    /// Length of the window, m.
    pub length_m: f64,
    /// For each node of the full model: its index in the window, or `None`.
    pub node_map: Vec<Option<usize>>,
    /// For each wire of the full model: its index in the window, or `None` when none of it lies
    /// inside (a line's tension lengths end).
    pub wire_map: Vec<Option<usize>>,
}

impl WindowMap {
    /// Strictly inside the window (the window's ends are pinned).
    pub fn inside(&self, x: f64) -> bool {
        x > self.origin_m + 1e-9 && x < self.origin_m + self.length_m - 1e-9
    }

    /// An attachment in window coordinates, or `None` when it falls outside.
    pub fn map(&self, a: Attach) -> Option<Attach> {
        match a {
            Attach::Wire { wire, dir, x_m } => match self.wire_map[wire] {
                Some(wire) if self.inside(x_m) => Some(Attach::Wire {
                    wire,
                    dir,
                    x_m: x_m - self.origin_m,
                }),
                _ => None,
            },
            Attach::Moving {
                wire,
                dir,
                pantograph,
                head,
                along_m,
            } => self.wire_map[wire].map(|wire| Attach::Moving {
                wire,
                dir,
                pantograph,
                head,
                along_m,
            }),
            Attach::Node(k) => self.node_map[k].map(Attach::Node),
            other => Some(other),
        }
    }
}

/// One kind of point element, holding all its instances.
pub trait PointElement: std::fmt::Debug + Send + Sync {
    /// Name of the kind ("dropper", "support", …).
    fn kind(&self) -> &'static str;
    /// Number of instances.
    fn len(&self) -> usize;
    /// True when there are no instances.
    fn is_empty(&self) -> bool {
        self.len() == 0
    }
    /// Attachments per instance (the same for every instance of a kind).
    fn arity(&self) -> usize;
    /// Attachment `a` of instance `i`.
    fn attachment(&self, i: usize, a: usize) -> Attach;
    /// Whether the force law of instance `i` reads the velocity at attachment `a` (a velocity
    /// point costs a gather per step: an undamped spring needs none).
    fn needs_velocity(&self, _i: usize, _a: usize) -> bool {
        false
    }
    /// Stiffness of instance `i` between its attachments (or to the ground), N/m: the
    /// integrator's explicit-stability check of nodes and pantograph heads adds these up.
    fn stiffness(&self, _i: usize) -> f64 {
        0.0
    }
    /// The implicit weight of instance `i`: (attachment index, weight).
    fn implicit(&self, _i: usize) -> Option<(usize, Weight)> {
        None
    }
    /// Add the explicit forces of every instance. `slots[i * arity + a]` is attachment `a` of
    /// instance `i`.
    fn add_forces(&self, slots: &[Slot], io: &mut Io);
    /// Energy stored in every instance (J), with `io.u`/`io.v` at the state.
    fn energy(&self, slots: &[Slot], io: &Io) -> f64;
    /// Rate of energy dissipation of every instance (W).
    fn dissipation(&self, _slots: &[Slot], _io: &Io) -> f64 {
        0.0
    }
    /// Attachments whose displacement is monitored for the statistics (the registration points of
    /// the steady arms give the uplift at the supports).
    fn monitors(&self) -> Vec<Attach> {
        Vec::new()
    }
    /// The instances inside a window, in window coordinates.
    fn restrict(&self, w: &WindowMap) -> Box<dyn PointElement>;
    /// A boxed copy.
    fn clone_box(&self) -> Box<dyn PointElement>;
    /// Downcast support (tests and statistics that need a kind's own data).
    fn as_any(&self) -> &dyn std::any::Any;
}

impl Clone for Box<dyn PointElement> {
    fn clone(&self) -> Self {
        self.clone_box()
    }
}
