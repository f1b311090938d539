//! Degrees of freedom: the motion directions, and the layout of the modal coordinates in blocks
//! keyed by (wire, direction).
//!
//! Blocks over the same sine basis (same origin, length and mode count) form a *basis group* and
//! sit next to each other in the state vector, so that the point sampler reads each sine table
//! once for all the blocks of the group.

use serde::{Deserialize, Serialize};

use crate::model::basis::SineBasis;

/// A motion direction of a wire (the paper's y, z and φ; Eqs. 1–8).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Direction {
    /// Vertical displacement y (up positive), m.
    Vertical,
    /// Lateral displacement z (across the track), m.
    Lateral,
    /// Torsional rotation φ about the wire axis, rad.
    Torsional,
}

impl Direction {
    /// Every direction, in block order.
    pub const ALL: [Direction; 3] = [
        Direction::Vertical,
        Direction::Lateral,
        Direction::Torsional,
    ];

    /// Lower-case name.
    pub fn name(self) -> &'static str {
        match self {
            Direction::Vertical => "vertical",
            Direction::Lateral => "lateral",
            Direction::Torsional => "torsional",
        }
    }
}

/// The key of a block of modal coordinates.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct BlockKey {
    /// Index into `Model::wires`.
    pub wire: usize,
    /// The direction of motion.
    pub dir: Direction,
}

/// One block of modal coordinates.
#[derive(Debug, Clone, PartialEq)]
pub struct Block {
    /// Which wire and direction.
    pub key: BlockKey,
    /// Start of the block in the modal state vector.
    pub offset: usize,
    /// Number of modes.
    pub n_modes: usize,
    /// Index of its basis group.
    pub group: usize,
}

/// Blocks sharing one sine basis, contiguous in the state vector.
#[derive(Debug, Clone, PartialEq)]
pub struct BasisGroup {
    /// The sine basis the blocks share.
    pub basis: SineBasis,
    /// Model coordinate of the basis' x = 0, m.
    pub origin_m: f64,
    /// Block indices, in state order.
    pub blocks: Vec<usize>,
    /// Start of the group in the modal state vector.
    pub offset: usize,
}

/// The layout of all modal coordinates.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Layout {
    /// Every block, in state order.
    pub blocks: Vec<Block>,
    /// Blocks sharing one sine basis.
    pub groups: Vec<BasisGroup>,
    /// Total number of modal coordinates.
    pub len: usize,
}

impl Layout {
    /// Lay out the blocks `(key, origin, basis)`: blocks with an identical basis and origin are
    /// grouped, groups in order of first appearance, blocks in given order within a group.
    pub fn new(blocks: &[(BlockKey, f64, SineBasis)]) -> Self {
        let mut groups: Vec<BasisGroup> = Vec::new();
        let mut member: Vec<usize> = Vec::with_capacity(blocks.len());
        for (i, (_, origin, basis)) in blocks.iter().enumerate() {
            let g = match groups
                .iter()
                .position(|g| g.basis == *basis && g.origin_m == *origin)
            {
                Some(g) => g,
                None => {
                    groups.push(BasisGroup {
                        basis: basis.clone(),
                        origin_m: *origin,
                        blocks: vec![],
                        offset: 0,
                    });
                    groups.len() - 1
                }
            };
            groups[g].blocks.push(i);
            member.push(g);
        }
        let mut out = vec![None; blocks.len()];
        let mut offset = 0;
        for (gi, g) in groups.iter_mut().enumerate() {
            g.offset = offset;
            for &b in &g.blocks {
                let n = g.basis.n_modes();
                out[b] = Some(Block {
                    key: blocks[b].0,
                    offset,
                    n_modes: n,
                    group: gi,
                });
                offset += n;
            }
        }
        Layout {
            blocks: out
                .into_iter()
                .map(|b| b.expect("every block placed"))
                .collect(),
            groups,
            len: offset,
        }
    }

    /// The block of `(wire, dir)`, if that direction is modelled.
    pub fn find(&self, wire: usize, dir: Direction) -> Option<usize> {
        self.blocks
            .iter()
            .position(|b| b.key.wire == wire && b.key.dir == dir)
    }

    /// The index range of block `b` in the modal state vector.
    pub fn range(&self, b: usize) -> std::ops::Range<usize> {
        let bl = &self.blocks[b];
        bl.offset..bl.offset + bl.n_modes
    }

    /// The basis of block `b`.
    pub fn basis(&self, b: usize) -> &SineBasis {
        &self.groups[self.blocks[b].group].basis
    }
}
