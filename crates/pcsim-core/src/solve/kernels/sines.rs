//! The row of sines of a moving point (Eq. 5), by rotation recurrences in four lanes, and its
//! dot product with the modal coordinates as the row is made.

use super::*;

// ---------------------------------------------------------------------------------------------
// Sines of a moving point's row.

/// # Safety
/// `S` must be usable on this CPU.
#[inline(always)]
unsafe fn fill_sines_body<S: Lanes, const F: bool>(theta: f64, out: &mut [f64]) {
    // SAFETY: the caller's.
    unsafe { fill_sines_dot_body::<S, F, false>(theta, out, &[]) };
}

/// The rows' sines and, with `DOT`, `Σ q_i out_i` taken as they are made: the lanes of
/// [`dot_body`] in its order (each 16 modes' four chunks into lanes 0–3 of its accumulators,
/// the chunks past the last whole 16 into lane 0, the lanes summed, then the last modes one by
/// one), so the same bytes as filling, then calling [`dot`].
///
/// # Safety
/// `S` must be usable on this CPU.
#[inline(always)]
unsafe fn fill_sines_dot_body<S: Lanes, const F: bool, const DOT: bool>(
    theta: f64,
    out: &mut [f64],
    q: &[f64],
) -> f64 {
    use crate::model::basis::{block_turn, chain_seeds, RESEED};
    let n = out.len();
    assert!(
        !DOT || q.len() >= n,
        "fill_sines_dot: q shorter than the row"
    );
    let n16 = n - n % 16;
    let (s0, c0) = chain_seeds(theta);
    let (s4, c4) = (s0[3], c0[3]);
    let qp = q.as_ptr();
    // SAFETY: every load reads a local array of four, or four modes `i..i + 4 <= n` of `q`
    // (`DOT` only, `q` at least `n` long); every store writes four values inside `block`
    // (`4 (j + 1) <= block.len()`), or a local array.
    unsafe {
        let vs4 = splat::<S>(s4);
        let vc4 = splat::<S>(c4);
        let vns4 = splat::<S>(-s4);
        let (vs0, vc0) = (S::load(s0.as_ptr()), S::load(c0.as_ptr()));
        let mut acc = [S::zero(); 4];
        for (b, block) in out.chunks_mut(4 * RESEED).enumerate() {
            let base = b * 4 * RESEED;
            let (mut vs, mut vc) = (vs0, vc0);
            if b > 0 {
                // The seeds turned to block b: s c_b + c s_b, c c_b + s (−s_b).
                let (sb, cb) = block_turn(theta, b);
                let (vsb, vcb, vnsb) = (splat::<S>(sb), splat::<S>(cb), splat::<S>(-sb));
                vs = S::add(S::mul(vs0, vcb), S::mul(vc0, vsb));
                vc = S::add(S::mul(vc0, vcb), S::mul(vs0, vnsb));
            }
            let full = block.len() / 4;
            let p = block.as_mut_ptr();
            // Chunk `j`: stored, with `DOT` added into lane `l` of the sums, turned by 4θ
            // (s' = s c4 + c s4, c' = c c4 − s s4, as c c4 + s (−s4): the same rounding).
            let mut chunk = |j: usize, l: usize, acc: &mut [S; 4]| {
                vs.store(p.add(4 * j));
                if DOT {
                    acc[l] = S::mad(S::load(qp.add(base + 4 * j)), vs, acc[l]);
                }
                let sn = S::add(S::mul(vs, vc4), S::mul(vc, vs4));
                vc = S::add(S::mul(vc, vc4), S::mul(vs, vns4));
                vs = sn;
            };
            let mut j = 0;
            // Whole 16s (blocks start at multiples of 16): four chunks, four lanes.
            while DOT && j + 4 <= full && base + 4 * j + 16 <= n16 {
                for l in 0..4 {
                    chunk(j + l, l, &mut acc);
                }
                j += 4;
            }
            while j < full {
                chunk(j, 0, &mut acc);
                j += 1;
            }
            let rem = block.len() - 4 * full;
            if rem > 0 {
                let mut t = [0.0f64; 4];
                vs.store(t.as_mut_ptr());
                block[4 * full..].copy_from_slice(&t[..rem]);
            }
        }
        if !DOT {
            return 0.0;
        }
        let mut s = S::add(S::add(acc[0], acc[1]), S::add(acc[2], acc[3])).sum();
        for i in n - n % 4..n {
            s = mad::<F>(*qp.add(i), out[i], s);
        }
        s
    }
}

lanes_kernel! {
    /// `out[i] = sin((i + 1) θ)` by the four-chain rotation of
    /// [`crate::model::basis::SineBasis::fill_sines`] (re-seeded at the same modes from the same
    /// seeds and turns), four lanes at a time with a multiply and an add per term, never fused:
    /// the same bytes as the scalar recurrence on both paths.
    pub fn fill_sines(theta: f64, out: &mut [f64]) = fill_sines_body;
}

/// # Safety
/// `S` must be usable on this CPU.
#[inline(always)]
unsafe fn fill_sines_dot_q<S: Lanes, const F: bool>(theta: f64, out: &mut [f64], q: &[f64]) -> f64 {
    // SAFETY: the caller's.
    unsafe { fill_sines_dot_body::<S, F, true>(theta, out, q) }
}

lanes_kernel! {
    /// [`fill_sines`], and `Σ q_i out_i` in the same pass: the bytes of [`dot`]`(q, out)` after
    /// it (the moving contact point's deviation, Eq. 5, as its row is made).
    pub fn fill_sines_dot(theta: f64, out: &mut [f64], q: &[f64]) -> f64 = fill_sines_dot_q;
}
