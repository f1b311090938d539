//! The window's saved state ([`Snapshot`]): save and restore without allocating, and its bytes
//! (the session's state format, `session.rs`).

use super::RealtimeCatenary;
use crate::solve::state::State;
use crate::solve::workspace::ExternalInput;

/// A saved state of a [`RealtimeCatenary`], for rolling a step back. Allocate once with
/// [`RealtimeCatenary::snapshot`], then [`RealtimeCatenary::save`] and
/// [`RealtimeCatenary::restore`] copy without allocating.
#[derive(Debug, Clone)]
pub struct Snapshot {
    /// The state of each of the window's positions (one on a span-periodic catenary); the
    /// current one's is saved.
    st: Vec<State>,
    /// The current position.
    cur: usize,
    moves: u64,
    input: ExternalInput,
}

impl Snapshot {
    /// Append the snapshot to `out` (on a line, the position first; the state, the window
    /// moves, the last input).
    pub fn write_bytes(&self, out: &mut Vec<u8>) {
        if self.st.len() > 1 {
            out.extend_from_slice(&(self.cur as u64).to_le_bytes());
        }
        self.st[self.cur].write_bytes(out);
        out.extend_from_slice(&self.moves.to_le_bytes());
        out.extend_from_slice(&self.input.position_m.to_le_bytes());
        out.extend_from_slice(&self.input.force_n.to_le_bytes());
    }
}

impl RealtimeCatenary {
    /// A snapshot buffer holding the current state.
    pub fn snapshot(&self) -> Snapshot {
        Snapshot {
            st: self.frames.iter().map(|f| f.st.clone()).collect(),
            cur: self.cur,
            moves: self.moves() as u64,
            input: self.input,
        }
    }

    /// Copy the current state into `s` (no allocation).
    pub fn save(&self, s: &mut Snapshot) {
        s.st[self.cur].copy_from(&self.frames[self.cur].st);
        s.cur = self.cur;
        s.moves = self.moves() as u64;
        s.input = self.input;
    }

    /// Return to the state saved in `s` (no allocation), at its position on a line.
    pub fn restore(&mut self, s: &Snapshot) {
        self.cur = s.cur;
        self.frames[self.cur].st.copy_from(&s.st[s.cur]);
        self.mover.moves = s.moves;
        self.input = s.input;
    }

    /// The length of [`Snapshot::write_bytes`] at the current position and the largest over
    /// the window's positions (they differ on a line, whose positions carry different wires),
    /// bytes (allocates).
    pub fn snapshot_len(&self) -> (usize, usize) {
        let s = self.snapshot();
        let mut buf = Vec::new();
        s.write_bytes(&mut buf);
        let header = buf.len() - {
            let mut b = Vec::new();
            s.st[s.cur].write_bytes(&mut b);
            b.len()
        };
        let most = (s.st.iter())
            .map(|st| {
                let mut b = Vec::new();
                st.write_bytes(&mut b);
                b.len()
            })
            .max()
            .unwrap_or(0);
        (buf.len(), header + most)
    }

    /// A snapshot read from bytes written by [`Snapshot::write_bytes`] for this window (the same
    /// case, window length and step); an error says what does not match.
    pub fn snapshot_from_bytes(
        &self,
        r: &mut crate::solve::state::ByteReader,
    ) -> Result<Snapshot, String> {
        let mut s = self.snapshot();
        if self.line.is_some() {
            let k = r.u64()?;
            if k >= self.frames.len() as u64 {
                return Err(format!(
                    "the window's position {k} does not exist: the line has {} positions",
                    self.frames.len()
                ));
            }
            s.cur = k as usize;
        }
        let st = &mut s.st[s.cur];
        st.read_bytes(r)?;
        s.moves = r.u64()?;
        s.input = ExternalInput {
            position_m: r.f64()?,
            force_n: r.f64()?,
        };
        if self.line.is_some() && s.moves != s.cur as u64 {
            return Err(format!(
                "the window's moves ({}) do not match its position ({}) on the line",
                s.moves, s.cur
            ));
        }
        let st = &s.st[s.cur];
        if !(st.is_finite()
            && st.x0_m.is_finite()
            && st.track_origin_m.is_finite()
            && s.input.position_m.is_finite()
            && s.input.force_n.is_finite())
        {
            return Err("the serialised state holds non-finite numbers".into());
        }
        Ok(s)
    }
}
