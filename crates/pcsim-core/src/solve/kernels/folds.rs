//! The folds of the span-periodic sampler (`sampler.rs`): the modes folded into bins of period P.

use super::*;

// ---------------------------------------------------------------------------------------------
// The folds of the span-periodic sampler (see `sampler.rs`): bins of period P.

// The blocked kernels below walk down the modes in steps of P with a block of 4·NL bins held
// in registers (NL = 2, then 1 for what is left; NL = 1 throughout for two vectors of two
// groups, whose sixteen accumulators would not fit twice); bins beyond a multiple of four, and
// the last partial row of modes, are done one at a time. Each is written once over `TWO` (one
// or two coefficient vectors) and `G` (one or two groups, each with its tables and bins): every
// bin is the same sum in the same order whichever form computes it, so a pass over two groups
// gives the bytes of two passes. Pointers are offset only inside `n` (checked).

/// The fold of one block of bins `r0..r0 + 4·NL` of `G` groups (see [`fold2`]).
///
/// # Safety
/// `S` usable; each `out[g]` holds `4p` values (`2p` when not `TWO`); `q*`, `s[g]`, `c[g]`
/// hold `n`.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
unsafe fn fold_block<S: Lanes, const F: bool, const NL: usize, const TWO: bool, const G: usize>(
    q1: *const f64,
    q2: *const f64,
    s: [*const f64; G],
    c: [*const f64; G],
    n: usize,
    p: usize,
    r0: usize,
    out: [*mut f64; G],
) {
    // SAFETY: the caller's contract (above): the reads of `q*`, `s[g]`, `c[g]` stay below `n`
    // (`base + 4·NL <= n`, then single modes `m < n`) and the writes of `out[g]` below its
    // `4p` (`2p`) values (`r0 + 4·NL <= p`).
    unsafe {
        let mut acc = [[[S::zero(); NL]; 4]; G];
        let mut base = r0;
        while base + 4 * NL <= n {
            for l in 0..NL {
                let o = base + 4 * l;
                let x = S::load(q1.add(o));
                let y = if TWO { S::load(q2.add(o)) } else { x };
                for g in 0..G {
                    let (ss, cc) = (S::load(s[g].add(o)), S::load(c[g].add(o)));
                    acc[g][0][l] = S::mad(x, ss, acc[g][0][l]);
                    acc[g][1][l] = S::mad(x, cc, acc[g][1][l]);
                    if TWO {
                        acc[g][2][l] = S::mad(y, ss, acc[g][2][l]);
                        acc[g][3][l] = S::mad(y, cc, acc[g][3][l]);
                    }
                }
            }
            base += p;
        }
        let nk = if TWO { 4 } else { 2 };
        for (g, ag) in acc.iter().enumerate() {
            for (k, a) in ag.iter().enumerate().take(nk) {
                for (l, v) in a.iter().enumerate() {
                    v.store(out[g].add(k * p + r0 + 4 * l));
                }
            }
        }
        for i in 0..(4 * NL).min(n.saturating_sub(base)) {
            let (m, r) = (base + i, r0 + i);
            for g in 0..G {
                fold_one::<F, TWO>(q1, q2, s[g], c[g], p, r, m, out[g]);
            }
        }
    }
}

/// One mode `m` of a fold into bin `r` (the scalar form of [`fold_block`]).
///
/// # Safety
/// As for [`fold_block`].
#[inline(always)]
#[allow(clippy::too_many_arguments)]
unsafe fn fold_one<const F: bool, const TWO: bool>(
    q1: *const f64,
    q2: *const f64,
    s: *const f64,
    c: *const f64,
    p: usize,
    r: usize,
    m: usize,
    out: *mut f64,
) {
    // SAFETY: the caller's contract (`fold_block`'s): `m < n` indexes `q*`, `s`, `c`; `r` and
    // `p + r` (`2p + r`, `3p + r` with `TWO`) index `out`'s `4p` (`2p`) values, `r < p`.
    unsafe {
        let (ss, cc, x) = (*s.add(m), *c.add(m), *q1.add(m));
        *out.add(r) = mad::<F>(x, ss, *out.add(r));
        *out.add(p + r) = mad::<F>(x, cc, *out.add(p + r));
        if TWO {
            let y = *q2.add(m);
            *out.add(2 * p + r) = mad::<F>(y, ss, *out.add(2 * p + r));
            *out.add(3 * p + r) = mad::<F>(y, cc, *out.add(3 * p + r));
        }
    }
}

/// # Safety
/// `S` must be usable on this CPU.
#[inline(always)]
unsafe fn fold_body<S: Lanes, const F: bool, const TWO: bool, const G: usize>(
    q1: &[f64],
    q2: &[f64],
    s: [&[f64]; G],
    c: [&[f64]; G],
    p: usize,
    out: [&mut [f64]; G],
) {
    let mut n = q1.len();
    if TWO {
        n = n.min(q2.len());
    }
    for t in s.iter().chain(&c) {
        n = n.min(t.len());
    }
    let nk = if TWO { 4 } else { 2 };
    assert!(
        p > 0 && out.iter().all(|o| o.len() >= nk * p),
        "fold: output too short"
    );
    let (q1, q2) = (q1.as_ptr(), q2.as_ptr());
    let (s, c) = (s.map(|t| t.as_ptr()), c.map(|t| t.as_ptr()));
    let o = out.map(|o| o.as_mut_ptr());
    // SAFETY: every mode index read is `< n` (the shortest input); every bin written is `< p`
    // of an output holding `nk·p`.
    unsafe {
        let mut r0 = 0;
        if !(TWO && G == 2) {
            while r0 + 8 <= p {
                fold_block::<S, F, 2, TWO, G>(q1, q2, s, c, n, p, r0, o);
                r0 += 8;
            }
        }
        while r0 + 4 <= p {
            fold_block::<S, F, 1, TWO, G>(q1, q2, s, c, n, p, r0, o);
            r0 += 4;
        }
        for r in r0..p {
            for g in 0..G {
                for k in 0..nk {
                    *o[g].add(k * p + r) = 0.0;
                }
                let mut m = r;
                while m < n {
                    fold_one::<F, TWO>(q1, q2, s[g], c[g], p, r, m, o[g]);
                    m += p;
                }
            }
        }
    }
}

/// # Safety
/// `S` must be usable on this CPU.
#[inline(always)]
unsafe fn fold2_body<S: Lanes, const F: bool>(
    q1: &[f64],
    q2: &[f64],
    s: &[f64],
    c: &[f64],
    p: usize,
    out: &mut [f64],
) {
    // SAFETY: `S` is usable (this function's contract); `fold_body` takes `n` as the shortest
    // input and asserts that every output holds `nk·p` values before it offsets a pointer.
    unsafe { fold_body::<S, F, true, 1>(q1, q2, [s], [c], p, [out]) }
}

lanes_kernel! {
    /// The folds of two coefficient vectors sharing the tables `s = sin(κd)`, `c = cos(κd)`:
    /// `out = [a1 | b1 | a2 | b2]` with `a[r] = Σ_m q[mP+r] s[mP+r]`, `b[r] = Σ_m q[mP+r] c[mP+r]`.
    /// Blocks of 8 bins stay in registers while the loop walks down the modes.
    pub fn fold2(q1: &[f64], q2: &[f64], s: &[f64], c: &[f64], p: usize, out: &mut [f64]) = fold2_body;
}

/// # Safety
/// `S` must be usable on this CPU.
#[inline(always)]
unsafe fn fold1_body<S: Lanes, const F: bool>(
    q: &[f64],
    s: &[f64],
    c: &[f64],
    p: usize,
    out: &mut [f64],
) {
    // SAFETY: as for `fold2_body` (one vector: `q2` empty, unread when not `TWO`).
    unsafe { fold_body::<S, F, false, 1>(q, &[], [s], [c], p, [out]) }
}

lanes_kernel! {
    /// [`fold2`] for one vector: `out = [a | b]`.
    pub fn fold1(q: &[f64], s: &[f64], c: &[f64], p: usize, out: &mut [f64]) = fold1_body;
}

/// # Safety
/// `S` must be usable on this CPU.
#[inline(always)]
unsafe fn fold1x2_body<S: Lanes, const F: bool>(
    q: &[f64],
    tabs: [&[f64]; 4],
    p: usize,
    out: [&mut [f64]; 2],
) {
    let [s1, c1, s2, c2] = tabs;
    // SAFETY: as for `fold2_body`, two groups, each with its own tables and output.
    unsafe { fold_body::<S, F, false, 2>(q, &[], [s1, s2], [c1, c2], p, out) }
}

lanes_kernel! {
    /// [`fold1`] of two groups in one pass over the modes (`tabs = [s₁, c₁, s₂, c₂]`, `out[g] =
    /// [a | b]` of group `g`): each mode of `q` is loaded once for both groups. Every bin is
    /// the same sum, in the same order, as [`fold1`]'s (the same bytes).
    pub fn fold1x2(q: &[f64], tabs: [&[f64]; 4], p: usize, out: [&mut [f64]; 2]) = fold1x2_body;
}

/// # Safety
/// `S` must be usable on this CPU.
#[inline(always)]
unsafe fn fold2x2_body<S: Lanes, const F: bool>(
    q1: &[f64],
    q2: &[f64],
    tabs: [&[f64]; 4],
    p: usize,
    out: [&mut [f64]; 2],
) {
    let [s1, c1, s2, c2] = tabs;
    // SAFETY: as for `fold2_body`, two vectors of two groups.
    unsafe { fold_body::<S, F, true, 2>(q1, q2, [s1, s2], [c1, c2], p, out) }
}

lanes_kernel! {
    /// [`fold2`] of two groups in one pass over the modes (`tabs = [s₁, c₁, s₂, c₂]`, `out[g] =
    /// [a1 | b1 | a2 | b2]` of group `g`): each mode of `q1`, `q2` is loaded once for both
    /// groups. Every bin is the same sum, in the same order, as [`fold2`]'s (the same bytes).
    pub fn fold2x2(q1: &[f64], q2: &[f64], tabs: [&[f64]; 4], p: usize, out: [&mut [f64]; 2]) = fold2x2_body;
}
