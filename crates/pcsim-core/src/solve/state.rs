//! The state of a run: modal coordinates in blocks (by `model::Layout`), node and pantograph
//! degrees of freedom, time, and where the model sits along the track.

use crate::model::Model;
use crate::solve::kernels::{self, Isa};

/// Displacements, velocities and accelerations of a set of degrees of freedom.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Dofs {
    /// Displacements.
    pub u: Vec<f64>,
    /// Velocities.
    pub v: Vec<f64>,
    /// Accelerations.
    pub a: Vec<f64>,
}

impl Dofs {
    /// `n` degrees of freedom at rest.
    pub fn zeros(n: usize) -> Self {
        Self {
            u: vec![0.0; n],
            v: vec![0.0; n],
            a: vec![0.0; n],
        }
    }

    /// Number of degrees of freedom.
    pub fn len(&self) -> usize {
        self.u.len()
    }

    /// True when empty.
    pub fn is_empty(&self) -> bool {
        self.u.is_empty()
    }

    fn copy_from(&mut self, o: &Dofs) {
        self.u.copy_from_slice(&o.u);
        self.v.copy_from_slice(&o.v);
        self.a.copy_from_slice(&o.a);
    }

    fn is_finite(&self) -> bool {
        all_finite(&self.u) && all_finite(&self.v) && all_finite(&self.a)
    }

    fn write(&self, out: &mut Vec<u8>) {
        out.extend_from_slice(&(self.u.len() as u64).to_le_bytes());
        for x in self.u.iter().chain(&self.v).chain(&self.a) {
            out.extend_from_slice(&x.to_le_bytes());
        }
    }

    fn read(&mut self, r: &mut ByteReader) -> Result<(), String> {
        let n = r.u64()? as usize;
        if n != self.u.len() {
            return Err(format!(
                "{n} degrees of freedom where the model has {}",
                self.u.len()
            ));
        }
        for v in [&mut self.u, &mut self.v, &mut self.a] {
            for x in v.iter_mut() {
                *x = r.f64()?;
            }
        }
        Ok(())
    }
}

/// Reads little-endian numbers from a byte slice, refusing to read past its end.
pub struct ByteReader<'a> {
    bytes: &'a [u8],
}

impl<'a> ByteReader<'a> {
    /// A reader at the start of `bytes`.
    pub fn new(bytes: &'a [u8]) -> Self {
        Self { bytes }
    }
    fn take(&mut self, n: usize) -> Result<&'a [u8], String> {
        if self.bytes.len() < n {
            return Err("the serialised state is truncated".into());
        }
        let (a, b) = self.bytes.split_at(n);
        self.bytes = b;
        Ok(a)
    }
    /// The next little-endian `u64`.
    pub fn u64(&mut self) -> Result<u64, String> {
        let b = self.take(8)?;
        Ok(u64::from_le_bytes(b.try_into().expect("8 bytes")))
    }
    /// The next `f64` (its little-endian bits).
    pub fn f64(&mut self) -> Result<f64, String> {
        Ok(f64::from_bits(self.u64()?))
    }
    /// The next `n` bytes.
    pub fn bytes(&mut self, n: usize) -> Result<&'a [u8], String> {
        self.take(n)
    }
    /// Whether every byte was read.
    pub fn is_done(&self) -> bool {
        self.bytes.is_empty()
    }
}

/// Whether every value is finite ([`kernels::all_finite`]: no branch per value; the real-time
/// session checks the whole state after every step). Both instruction sets give the same
/// answer, so the best one is taken without fixing the process's choice ([`Isa::detect`]).
#[doc(hidden)] // public for the unit tests in tests/suite/unit
pub fn all_finite(xs: &[f64]) -> bool {
    kernels::all_finite(Isa::best_available(), xs)
}

/// The state at time `t`.
#[derive(Debug, Clone, PartialEq)]
pub struct State {
    /// Time, s.
    pub t: f64,
    /// Position of the leading pantograph at t = 0 in model coordinates, m (a moving window
    /// lowers it by its shift at every move).
    pub x0_m: f64,
    /// Track position of the model's x = 0, m (zero for a full model).
    pub track_origin_m: f64,
    /// Modal coordinates of every block, by `Model::layout` (`u` holds the coordinates q).
    pub modal: Dofs,
    /// Node degrees of freedom (deviation from the static state).
    pub nodes: Dofs,
    /// Pantograph degrees of freedom (absolute heights), pantograph after pantograph.
    pub pantographs: Dofs,
}

impl State {
    /// Append the state to `out` (little-endian, with the sizes of its parts).
    pub fn write_bytes(&self, out: &mut Vec<u8>) {
        for x in [self.t, self.x0_m, self.track_origin_m] {
            out.extend_from_slice(&x.to_le_bytes());
        }
        self.modal.write(out);
        self.nodes.write(out);
        self.pantographs.write(out);
    }

    /// Read a state written by [`Self::write_bytes`] into this one, which must have the same
    /// sizes (the same model); an error says what does not match.
    pub fn read_bytes(&mut self, r: &mut ByteReader) -> Result<(), String> {
        self.t = r.f64()?;
        self.x0_m = r.f64()?;
        self.track_origin_m = r.f64()?;
        self.modal
            .read(r)
            .map_err(|e| format!("modal coordinates: {e}"))?;
        self.nodes.read(r).map_err(|e| format!("nodes: {e}"))?;
        self.pantographs
            .read(r)
            .map_err(|e| format!("pantographs: {e}"))?;
        Ok(())
    }

    /// The state of `model` at rest with zero deviation (the pantographs' heights are set by
    /// the integrator's initial state).
    pub fn at_rest(model: &Model, x0_m: f64) -> Self {
        let np: usize = model.pantographs.iter().map(|p| p.n_dof()).sum();
        State {
            t: 0.0,
            x0_m,
            track_origin_m: model.track_origin_m,
            modal: Dofs::zeros(model.layout.len),
            nodes: Dofs::zeros(model.nodes.len()),
            pantographs: Dofs::zeros(np),
        }
    }

    /// Modal coordinates of block `b`.
    pub fn q(&self, model: &Model, b: usize) -> &[f64] {
        &self.modal.u[model.layout.range(b)]
    }

    /// Mutable modal coordinates of block `b` (initial conditions in tests).
    pub fn q_mut(&mut self, model: &Model, b: usize) -> &mut [f64] {
        &mut self.modal.u[model.layout.range(b)]
    }

    /// Modal velocities of block `b`.
    pub fn qdot(&self, model: &Model, b: usize) -> &[f64] {
        &self.modal.v[model.layout.range(b)]
    }

    /// Mutable modal velocities of block `b`.
    pub fn qdot_mut(&mut self, model: &Model, b: usize) -> &mut [f64] {
        &mut self.modal.v[model.layout.range(b)]
    }

    /// Copy another state of the same model into this one, without allocating.
    pub fn copy_from(&mut self, o: &State) {
        self.t = o.t;
        self.x0_m = o.x0_m;
        self.track_origin_m = o.track_origin_m;
        self.modal.copy_from(&o.modal);
        self.nodes.copy_from(&o.nodes);
        self.pantographs.copy_from(&o.pantographs);
    }

    /// Every number finite.
    pub fn is_finite(&self) -> bool {
        self.t.is_finite()
            && self.modal.is_finite()
            && self.nodes.is_finite()
            && self.pantographs.is_finite()
    }

    /// Modal energy of the wires, ½ Σ (M_k q̇_k² + K_k q_k²) over every block, J.
    pub fn modal_energy(&self, model: &Model) -> f64 {
        let mut e = 0.0;
        for b in 0..model.layout.blocks.len() {
            let s = model.series(b);
            let r = model.layout.range(b);
            for (i, k) in r.enumerate() {
                let (q, v) = (self.modal.u[k], self.modal.v[k]);
                e += 0.5 * (s.mass[i] * v * v + s.stiffness[i] * q * q);
            }
        }
        e
    }

    /// Project every modal block of basis group `g` through the row-major `n × n` matrix `p`:
    /// the state carried over when a window moves. The next step's half-kicked velocity
    /// `v½ = v + h a` is projected with the coordinates (`q ← P q`, `v ← P v½`, `a ← 0`), so that
    /// the next step continues exactly as if v and a had been projected separately, with two
    /// vectors per block instead of three. `buf` is scratch of at least `2 · blocks · n` values.
    pub fn project_group(
        &mut self,
        model: &Model,
        g: usize,
        p: &[f64],
        h: f64,
        isa: crate::solve::kernels::Isa,
        buf: &mut [f64],
    ) {
        let grp = &model.layout.groups[g];
        let n = grp.basis.n_modes();
        for &b in &grp.blocks {
            let o = model.layout.blocks[b].offset;
            crate::solve::kernels::kick(
                isa,
                &mut self.modal.v[o..o + n],
                &self.modal.a[o..o + n],
                h,
            );
        }
        // Two blocks at a time: four vectors per pass over P.
        for pair in grp.blocks.chunks(2) {
            let o0 = model.layout.blocks[pair[0]].offset;
            match pair {
                [_, b1] => {
                    let o1 = model.layout.blocks[*b1].offset;
                    let xs: [&[f64]; 4] = [
                        &self.modal.u[o0..o0 + n],
                        &self.modal.v[o0..o0 + n],
                        &self.modal.u[o1..o1 + n],
                        &self.modal.v[o1..o1 + n],
                    ];
                    crate::solve::kernels::project4(isa, p, n, xs, &mut buf[..4 * n]);
                    self.modal.u[o0..o0 + n].copy_from_slice(&buf[..n]);
                    self.modal.v[o0..o0 + n].copy_from_slice(&buf[n..2 * n]);
                    self.modal.u[o1..o1 + n].copy_from_slice(&buf[2 * n..3 * n]);
                    self.modal.v[o1..o1 + n].copy_from_slice(&buf[3 * n..4 * n]);
                }
                _ => {
                    crate::solve::kernels::project2(
                        isa,
                        p,
                        n,
                        &self.modal.u[o0..o0 + n],
                        &self.modal.v[o0..o0 + n],
                        &mut buf[..2 * n],
                    );
                    self.modal.u[o0..o0 + n].copy_from_slice(&buf[..n]);
                    self.modal.v[o0..o0 + n].copy_from_slice(&buf[n..2 * n]);
                }
            }
        }
        for &b in &grp.blocks {
            let o = model.layout.blocks[b].offset;
            self.modal.a[o..o + n].fill(0.0);
        }
    }
}
