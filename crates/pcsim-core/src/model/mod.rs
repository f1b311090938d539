//! The problem: wires in sine coordinates (one series per modelled direction), point elements,
//! nodes, pantographs and the static shape. No run settings: the speed, the start, the duration
//! and the time step belong to `solve::Plan` and `solve::Options`.
//!
//! | file | what it holds |
//! |---|---|
//! | `basis.rs` | the sine trial functions (Eqs. 5–8) |
//! | `dof.rs` | directions, blocks keyed by (wire, direction), basis groups |
//! | `wire.rs` | wires, section data, energy coefficients (Eqs. 1–4), modal series (Eqs. 11–14) |
//! | `elements/` | point elements behind one interface: dropper (Eq. 15), support, steady arm, stitch, contact (Eq. 19) |
//! | `pantograph.rs` | lumped pantographs (Eq. 16), the aerodynamic force (Eq. 17) |
//! | `statics.rs` | the static shape from the design geometry (paper §2.1) |
//! | `build.rs` | a case becomes a model; a builder for hand-made models |
//! | `window.rs` | a window of a model (the real-time catenary) |
//! | `line.rs` | a tension length of spans that need not repeat, and its static shape (issue 21) |
//! | `lateral.rs` | stagger: the static lateral shape (issue 12) |
//! | `wind.rs`, `wind_field.rs` | crosswind loads and the turbulent wind field (issue 12) |

pub mod basis;
pub mod build;
pub mod dof;
pub mod elements;
pub mod irregularity;
pub mod lateral;
pub mod line;
pub mod pantograph;
pub mod statics;
pub mod wind;
pub mod wind_field;
pub mod window;
pub mod wire;

pub use build::ModelBuilder;
pub use dof::{BlockKey, Direction, Layout};
pub use elements::{Attach, PointElement};
pub use pantograph::{Lumped, Pantograph, PantographKind};
pub use statics::StaticSolution;
pub use wire::{Wire, WireRole};

/// A lumped mass with its own degree of freedom (a stitch clamp with half its stitch wire).
#[derive(Debug, Clone, PartialEq)]
pub struct Node {
    /// Position along the track (model coordinates), m.
    pub x_m: f64,
    /// Mass, kg.
    pub mass_kg: f64,
    /// Direction of its motion.
    pub dir: Direction,
}

/// The static shape the dynamics deviate from.
#[derive(Debug, Clone, PartialEq)]
pub enum StaticShape {
    /// Straight wires at height 0 (analytic single-wire checks).
    Flat,
    /// The catenary's static solution from its design (the initial condition of Eqs. 9–10).
    Catenary(Box<StaticSolution>),
    /// A line: tension lengths of spans that need not repeat, overlapping (`line.rs`).
    Line(Box<line::LineStatics>),
}

impl StaticShape {
    /// Static height of wire `wire`, of role `role`, at model coordinate `x`, m (0 at the
    /// contact-wire design height at the supports).
    pub fn height(&self, wire: usize, role: WireRole, x: f64) -> f64 {
        match (self, role) {
            (StaticShape::Flat, _) => 0.0,
            (StaticShape::Catenary(s), WireRole::Contact) => s.contact_height(x),
            (StaticShape::Catenary(s), _) => s.messenger_height(x),
            (StaticShape::Line(s), _) => s.height(wire, role, x),
        }
    }

    /// The system height (messenger above contact wire) at `x`, m; `None` for flat wires.
    pub fn system_height(&self, x: f64) -> Option<f64> {
        match self {
            StaticShape::Flat => None,
            StaticShape::Catenary(s) => Some(s.messenger_height(x) - s.contact_height(x)),
            StaticShape::Line(s) => Some(s.system_height(x)),
        }
    }
}

/// What a hard spot of a line is (issue 55).
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize, schemars::JsonSchema,
)]
#[serde(rename_all = "snake_case")]
pub enum HardSpotKind {
    /// A section insulator in the contact wire (its extent).
    SectionInsulator,
    /// A neutral section's dead length (between two insulators).
    NeutralSection,
}

/// A hard spot of a line: what it is, where (track coordinates) and on which contact wire.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HardSpot {
    /// What it is.
    pub kind: HardSpotKind,
    /// Its extent along the track, m.
    pub section_m: [f64; 2],
    /// The contact wire it lies on (index into `Model::wires`).
    pub wire: usize,
}

/// The whole model.
#[derive(Debug, Clone)]
pub struct Model {
    /// The wires, each with its modal series per direction.
    pub wires: Vec<Wire>,
    /// Blocks of modal coordinates keyed by (wire, direction), derived from `wires`.
    pub layout: Layout,
    /// Lumped masses with their own degree of freedom.
    pub nodes: Vec<Node>,
    /// Point elements, one value per kind, in the order their forces are evaluated.
    pub elements: Vec<Box<dyn PointElement>>,
    /// The pantographs, leading first.
    pub pantographs: Vec<Pantograph>,
    /// The static shape the dynamics deviate from.
    pub statics: StaticShape,
    /// Span length when the layout repeats every span (enables the fast point sampler).
    pub span_m: Option<f64>,
    /// Stagger and the lateral outputs' constants, when lateral motion is modelled.
    pub lateral: Option<lateral::LateralGeometry>,
    /// Crosswind, if any.
    pub wind: Option<wind::WindLoad>,
    /// Contact-wire irregularity, if any (added to the contact wire's static height), in track
    /// coordinates.
    pub irregularity: Option<irregularity::IrregularityProfile>,
    /// Every support of the line (ends included), model coordinates, m; empty for hand-made
    /// models.
    pub supports_m: Vec<f64>,
    /// A line's overlaps: `[first, last]` shared support of each, model coordinates, m.
    pub overlaps_m: Vec<[f64; 2]>,
    /// The line's hard spots (issue 55): each section insulator and neutral section, in track
    /// order of the case; a run reports its passage over each.
    pub hard_spots: Vec<HardSpot>,
    /// Track position of the model's x = 0 when it is built, m (0 for a full model; a window's
    /// origin). Stagger and irregularity are kept in track coordinates, because a window moves
    /// by whole spans but they need not repeat every span.
    pub track_origin_m: f64,
}

impl Model {
    /// Assemble a model; the block layout follows from the wires (directions in the order
    /// vertical, lateral, torsional within each wire).
    pub fn new(
        wires: Vec<Wire>,
        nodes: Vec<Node>,
        elements: Vec<Box<dyn PointElement>>,
        pantographs: Vec<Pantograph>,
        statics: StaticShape,
        span_m: Option<f64>,
    ) -> Self {
        let mut blocks = Vec::new();
        for (wi, w) in wires.iter().enumerate() {
            for d in Direction::ALL {
                if w.series.get(d).is_some() {
                    blocks.push((BlockKey { wire: wi, dir: d }, w.origin_m, w.basis.clone()));
                }
            }
        }
        Model {
            layout: Layout::new(&blocks),
            wires,
            nodes,
            elements,
            pantographs,
            statics,
            span_m,
            lateral: None,
            wind: None,
            irregularity: None,
            supports_m: Vec::new(),
            overlaps_m: Vec::new(),
            hard_spots: Vec::new(),
            track_origin_m: 0.0,
        }
    }

    /// The first wire with role `role`.
    pub fn wire_index(&self, role: WireRole) -> Option<usize> {
        self.wires.iter().position(|w| w.role == role)
    }

    /// Every contact wire's transverse wave speed √(T/ρA) ([`wire::Wire::wave_speed`]), in wire
    /// order (one per tension length of a line): `(wire index, m/s)`.
    pub fn contact_wave_speeds(&self) -> Vec<(usize, f64)> {
        self.wires
            .iter()
            .enumerate()
            .filter(|(_, w)| w.role == WireRole::Contact)
            .map(|(i, w)| (i, w.wave_speed()))
            .collect()
    }

    /// The slowest contact wire, `(wire index, wave speed m/s)`: the one that decides the speed
    /// check and the speed ratio on a line of several tension lengths.
    pub fn slowest_contact_wire(&self) -> Option<(usize, f64)> {
        self.contact_wave_speeds()
            .into_iter()
            .reduce(|a, b| if b.1 < a.1 { b } else { a })
    }

    /// The block of the first wire with role `role` in direction `dir`.
    pub fn block(&self, role: WireRole, dir: Direction) -> Option<usize> {
        self.layout.find(self.wire_index(role)?, dir)
    }

    /// The modal series of block `b`.
    pub fn series(&self, b: usize) -> &wire::ModalSeries {
        let k = self.layout.blocks[b].key;
        self.wires[k.wire]
            .series
            .get(k.dir)
            .expect("a block exists only for a modelled direction")
    }

    /// Length of the model along the track (the furthest wire end), m.
    pub fn length_m(&self) -> f64 {
        self.wires
            .iter()
            .map(|w| w.origin_m + w.basis.length_m())
            .fold(0.0, f64::max)
    }

    /// Modes per wire of the contact wire's vertical series (the figure reported with a run).
    pub fn n_modes(&self) -> usize {
        self.block(WireRole::Contact, Direction::Vertical)
            .map_or(0, |b| self.layout.blocks[b].n_modes)
    }

    /// The element kind of type `T`, if the model has one.
    pub fn element<T: 'static>(&self) -> Option<&T> {
        self.elements
            .iter()
            .find_map(|e| e.as_any().downcast_ref::<T>())
    }

    /// Static position of wire `wire` in direction `dir` at model coordinate `x` when the model's
    /// x = 0 lies at track position `track_origin_m` (the state's): the design height (with the
    /// contact wire's irregularity), the stagger line, or no rotation; m (rad).
    pub fn static_height(&self, wire: usize, dir: Direction, x: f64, track_origin_m: f64) -> f64 {
        let xt = x + track_origin_m;
        match dir {
            Direction::Vertical => {
                let role = self.wires[wire].role;
                let h = self.statics.height(wire, role, x);
                match (&self.irregularity, role) {
                    (Some(ir), WireRole::Contact) => h + ir.at(xt),
                    _ => h,
                }
            }
            Direction::Lateral => self
                .lateral
                .as_ref()
                .map_or(0.0, |l| l.stagger_at(wire, xt)),
            Direction::Torsional => 0.0,
        }
    }

    /// Whether any wire moves in direction `dir`.
    pub fn has(&self, dir: Direction) -> bool {
        self.layout.blocks.iter().any(|b| b.key.dir == dir)
    }
}
