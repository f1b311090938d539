//! The unfolds of the span-periodic sampler (`sampler.rs`): the bins' transforms spread back to
//! the modes (the scatter), scaled where the implicit terms ask.

use super::*;

/// The unfold of one block of bins of `G` groups (see [`unfold2`], [`unfold1`]): `o1[mP+r] +=
/// sc·(a1[r] s + b1[r] c)` for each group in turn (scaled when `SC`; the unscaled form is
/// `a s + (b c + o)`), and the same for `o2` with `a2`, `b2` when `TWO`.
///
/// # Safety
/// As for [`fold_block`], with `bins[g]` holding `4p` (`2p`); `scale` holds `n` values when
/// `SC` (and is not read otherwise).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
unsafe fn unfold_block<
    S: Lanes,
    const F: bool,
    const NL: usize,
    const TWO: bool,
    const G: usize,
    const SC: bool,
>(
    bins: [*const f64; G],
    s: [*const f64; G],
    c: [*const f64; G],
    scale: *const f64,
    n: usize,
    p: usize,
    r0: usize,
    o1: *mut f64,
    o2: *mut f64,
) {
    // SAFETY: the caller's contract (`unfold_body`'s checks): the reads of `bins[g]` (`nk·p`
    // values), `s[g]`, `c[g]` and `scale` stay below their checked lengths, the writes of `o1`, `o2`
    // below `n` (`r0 + 4·NL <= p`, outputs `o = m·p + r < n`).
    unsafe {
        let nk = if TWO { 4 } else { 2 };
        let mut r = [[[S::zero(); NL]; 4]; G];
        for (g, rg) in r.iter_mut().enumerate() {
            for (k, rk) in rg.iter_mut().enumerate().take(nk) {
                for (l, v) in rk.iter_mut().enumerate() {
                    *v = S::load(bins[g].add(k * p + r0 + 4 * l));
                }
            }
        }
        let mut base = r0;
        while base + 4 * NL <= n {
            for l in 0..NL {
                let o = base + 4 * l;
                let mut x = S::load(o1.add(o));
                let mut y = if TWO { S::load(o2.add(o)) } else { x };
                let sv = if SC { S::load(scale.add(o)) } else { x };
                for (g, rg) in r.iter().enumerate() {
                    let (ss, cc) = (S::load(s[g].add(o)), S::load(c[g].add(o)));
                    x = if SC {
                        S::mad(sv, S::mad(rg[0][l], ss, S::mul(rg[1][l], cc)), x)
                    } else {
                        S::mad(rg[0][l], ss, S::mad(rg[1][l], cc, x))
                    };
                    if TWO {
                        y = S::mad(rg[2][l], ss, S::mad(rg[3][l], cc, y));
                    }
                }
                x.store(o1.add(o));
                if TWO {
                    y.store(o2.add(o));
                }
            }
            base += p;
        }
        for i in 0..(4 * NL).min(n.saturating_sub(base)) {
            for g in 0..G {
                unfold_one::<F, TWO, SC>(bins[g], s[g], c[g], scale, p, r0 + i, base + i, o1, o2);
            }
        }
    }
}

/// One mode of an unfold (the scalar form of [`unfold_block`]).
///
/// # Safety
/// As for [`unfold_block`].
#[inline(always)]
#[allow(clippy::too_many_arguments)]
unsafe fn unfold_one<const F: bool, const TWO: bool, const SC: bool>(
    bins: *const f64,
    s: *const f64,
    c: *const f64,
    scale: *const f64,
    p: usize,
    r: usize,
    o: usize,
    o1: *mut f64,
    o2: *mut f64,
) {
    // SAFETY: the caller's contract (`unfold_block`'s): `o < n` indexes `s`, `c`, `scale`, `o1`,
    // `o2`; `r`, `p + r` (and `2p + r`, `3p + r` with `TWO`) index the bins, `r < p`.
    unsafe {
        let (ss, cc) = (*s.add(o), *c.add(o));
        let (a, b) = (*bins.add(r), *bins.add(p + r));
        *o1.add(o) = if SC {
            mad::<F>(*scale.add(o), mad::<F>(a, ss, b * cc), *o1.add(o))
        } else {
            mad::<F>(a, ss, mad::<F>(b, cc, *o1.add(o)))
        };
        if TWO {
            let (a, b) = (*bins.add(2 * p + r), *bins.add(3 * p + r));
            *o2.add(o) = mad::<F>(a, ss, mad::<F>(b, cc, *o2.add(o)));
        }
    }
}

/// # Safety
/// `S` must be usable on this CPU.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
unsafe fn unfold_body<S: Lanes, const F: bool, const TWO: bool, const G: usize>(
    bins: [&[f64]; G],
    s: [&[f64]; G],
    c: [&[f64]; G],
    p: usize,
    o1: &mut [f64],
    o2: &mut [f64],
    scale: &[f64],
) {
    // SAFETY: the caller's; the scaled form only with a scale (a constant per form, so that no
    // loop tests it per mode).
    unsafe {
        if scale.is_empty() {
            unfold_scaled::<S, F, TWO, G, false>(bins, s, c, p, o1, o2, scale)
        } else {
            unfold_scaled::<S, F, TWO, G, true>(bins, s, c, p, o1, o2, scale)
        }
    }
}

/// [`unfold_body`], scaled by `scale` when `SC`.
///
/// # Safety
/// `S` must be usable on this CPU.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
unsafe fn unfold_scaled<
    S: Lanes,
    const F: bool,
    const TWO: bool,
    const G: usize,
    const SC: bool,
>(
    bins: [&[f64]; G],
    s: [&[f64]; G],
    c: [&[f64]; G],
    p: usize,
    o1: &mut [f64],
    o2: &mut [f64],
    scale: &[f64],
) {
    let mut n = o1.len();
    if TWO {
        n = n.min(o2.len());
    }
    if SC {
        n = n.min(scale.len());
    }
    for t in s.iter().chain(&c) {
        n = n.min(t.len());
    }
    let nk = if TWO { 4 } else { 2 };
    assert!(
        p > 0 && bins.iter().all(|b| b.len() >= nk * p),
        "unfold: bins too short"
    );
    let sc = scale.as_ptr();
    let (bp, sp, cp) = (
        bins.map(|b| b.as_ptr()),
        s.map(|t| t.as_ptr()),
        c.map(|t| t.as_ptr()),
    );
    let (p1, p2) = (o1.as_mut_ptr(), o2.as_mut_ptr());
    // SAFETY: every mode index read or written is `< n` (the shortest table, output or scale);
    // every bin read is `< nk·p` of bins holding `nk·p`; `scale` is read only when `SC`.
    unsafe {
        let mut r0 = 0;
        if !(TWO && G == 2) {
            while r0 + 8 <= p {
                unfold_block::<S, F, 2, TWO, G, SC>(bp, sp, cp, sc, n, p, r0, p1, p2);
                r0 += 8;
            }
        }
        while r0 + 4 <= p {
            unfold_block::<S, F, 1, TWO, G, SC>(bp, sp, cp, sc, n, p, r0, p1, p2);
            r0 += 4;
        }
        for r in r0..p {
            let mut o = r;
            while o < n {
                for g in 0..G {
                    unfold_one::<F, TWO, SC>(bp[g], sp[g], cp[g], sc, p, r, o, p1, p2);
                }
                o += p;
            }
        }
    }
}

/// # Safety
/// `S` must be usable on this CPU.
#[inline(always)]
unsafe fn unfold2_body<S: Lanes, const F: bool>(
    bins: &[f64],
    s: &[f64],
    c: &[f64],
    p: usize,
    o1: &mut [f64],
    o2: &mut [f64],
) {
    // SAFETY: `S` is usable (this function's contract); `unfold_scaled` takes `n` as the
    // shortest table, output or scale and asserts that every bin array holds `nk·p` values
    // before it offsets a pointer.
    unsafe { unfold_body::<S, F, true, 1>([bins], [s], [c], p, o1, o2, &[]) }
}

lanes_kernel! {
    /// The transpose of [`fold2`]: `o[mP+r] += a[r] s[mP+r] + b[r] c[mP+r]` for both vectors,
    /// `bins = [a1 | b1 | a2 | b2]`.
    pub fn unfold2(bins: &[f64], s: &[f64], c: &[f64], p: usize, o1: &mut [f64], o2: &mut [f64]) = unfold2_body;
}

/// # Safety
/// `S` must be usable on this CPU.
#[inline(always)]
unsafe fn unfold2x2_body<S: Lanes, const F: bool>(
    bins: [&[f64]; 2],
    tabs: [&[f64]; 4],
    p: usize,
    o1: &mut [f64],
    o2: &mut [f64],
) {
    let [s1, c1, s2, c2] = tabs;
    // SAFETY: as for `unfold2_body`, two groups.
    unsafe { unfold_body::<S, F, true, 2>(bins, [s1, s2], [c1, c2], p, o1, o2, &[]) }
}

lanes_kernel! {
    /// [`unfold2`] of two groups in one pass over the modes (`bins[g] = [a1 | b1 | a2 | b2]`
    /// of group `g`, `tabs = [s₁, c₁, s₂, c₂]`): each mode of `o1`, `o2` is loaded and stored
    /// once for both. Every mode takes group 1's terms, then group 2's, as two [`unfold2`]
    /// calls in that order do (the same bytes).
    pub fn unfold2x2(bins: [&[f64]; 2], tabs: [&[f64]; 4], p: usize, o1: &mut [f64], o2: &mut [f64]) = unfold2x2_body;
}

/// # Safety
/// `S` must be usable on this CPU.
#[inline(always)]
unsafe fn unfold1_body<S: Lanes, const F: bool>(
    bins: &[f64],
    s: &[f64],
    c: &[f64],
    p: usize,
    o: &mut [f64],
    scale: &[f64],
) {
    // SAFETY: as for `unfold2_body` (one output: `o2` empty and unwritten when not `TWO`).
    unsafe { unfold_body::<S, F, false, 1>([bins], [s], [c], p, o, &mut [], scale) }
}

lanes_kernel! {
    /// The transpose of [`fold1`], optionally scaled per mode: `o[m] += scale[m] (a[r] s[m] +
    /// b[r] c[m])` (`scale` empty: 1). The scaled form fuses the Woodbury correction
    /// `a −= D⁻¹ Φᵀ g` into the scatter.
    pub fn unfold1(bins: &[f64], s: &[f64], c: &[f64], p: usize, o: &mut [f64], scale: &[f64]) = unfold1_body;
}

/// # Safety
/// `S` must be usable on this CPU.
#[inline(always)]
unsafe fn unfold1x2_body<S: Lanes, const F: bool>(
    bins: [&[f64]; 2],
    tabs: [&[f64]; 4],
    p: usize,
    o: &mut [f64],
    scale: &[f64],
) {
    let [s1, c1, s2, c2] = tabs;
    // SAFETY: as for `unfold1_body`, two groups.
    unsafe { unfold_body::<S, F, false, 2>(bins, [s1, s2], [c1, c2], p, o, &mut [], scale) }
}

lanes_kernel! {
    /// [`unfold1`] of two groups in one pass over the modes (`bins[g] = [a | b]` of group `g`,
    /// `tabs = [s₁, c₁, s₂, c₂]`), optionally scaled per mode: each mode of `o` is loaded and
    /// stored once for both, and takes group 1's term, then group 2's, as two [`unfold1`] calls
    /// in that order do (the same bytes).
    pub fn unfold1x2(bins: [&[f64]; 2], tabs: [&[f64]; 4], p: usize, o: &mut [f64], scale: &[f64]) = unfold1x2_body;
}
