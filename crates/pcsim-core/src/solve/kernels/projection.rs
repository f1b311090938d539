//! The window move: a dense projection of two or four vectors.

use super::*;

// ---------------------------------------------------------------------------------------------
// The window move: a dense projection of two or four vectors.

/// Two rows of `P` at a time against `NV` vectors: `2·NV` accumulators stay in registers, and
/// each chunk of four columns costs `2 + NV` loads for `2·NV` multiply-adds.
///
/// # Safety
/// `S` must be usable on this CPU.
#[inline(always)]
unsafe fn project_rows<S: Lanes, const F: bool, const NV: usize>(
    p: &[f64],
    (n, m): (usize, usize),
    xs: [&[f64]; NV],
    out: &mut [f64],
) {
    // `n` rows of `m` columns: `out[v] (n) = P x_v (m)`.
    assert!(
        p.len() >= n * m && out.len() >= NV * n && xs.iter().all(|x| x.len() >= m),
        "project: operands too short"
    );
    let xp: [*const f64; NV] = xs.map(|x| x.as_ptr());
    let (pp, op) = (p.as_ptr(), out.as_mut_ptr());
    let tail = m / 4 * 4;
    // SAFETY: `S` is usable (this function's contract); the assert above gives `p` at least
    // `n·m` values, every `x_v` at least `m` and `out` at least `NV·n`: row `k < n` reads
    // `p[k·m..(k + 1)·m]` and `x_v[..m]` (four at a time below `tail <= m`), and writes `out[v·n + k]`.
    unsafe {
        let mut k = 0;
        while k < n {
            let two = k + 1 < n;
            let r0 = pp.add(k * m);
            let r1 = if two { pp.add((k + 1) * m) } else { r0 };
            let mut acc0 = [S::zero(); NV];
            let mut acc1 = [S::zero(); NV];
            let mut j = 0;
            while j < tail {
                let (a, b) = (S::load(r0.add(j)), S::load(r1.add(j)));
                for v in 0..NV {
                    let x = S::load(xp[v].add(j));
                    acc0[v] = S::mad(a, x, acc0[v]);
                    acc1[v] = S::mad(b, x, acc1[v]);
                }
                j += 4;
            }
            for v in 0..NV {
                let mut s0 = acc0[v].sum();
                let mut s1 = acc1[v].sum();
                for j in tail..m {
                    let x = *xp[v].add(j);
                    s0 = mad::<F>(*r0.add(j), x, s0);
                    s1 = mad::<F>(*r1.add(j), x, s1);
                }
                *op.add(v * n + k) = s0;
                if two {
                    *op.add(v * n + k + 1) = s1;
                }
            }
            k += 2;
        }
    }
}

/// # Safety
/// `S` must be usable on this CPU.
#[inline(always)]
unsafe fn project2_body<S: Lanes, const F: bool>(
    p: &[f64],
    n: usize,
    x0: &[f64],
    x1: &[f64],
    out: &mut [f64],
) {
    // SAFETY: `S` is usable (this function's contract); `project_rows` asserts every length.
    unsafe { project_rows::<S, F, 2>(p, (n, n), [x0, x1], out) }
}

/// # Safety
/// `S` must be usable on this CPU.
#[inline(always)]
unsafe fn project4_body<S: Lanes, const F: bool>(
    p: &[f64],
    n: usize,
    x: [&[f64]; 4],
    out: &mut [f64],
) {
    // SAFETY: as for `project2_body`.
    unsafe { project_rows::<S, F, 4>(p, (n, n), x, out) }
}

lanes_kernel! {
    /// `out[v] = P x_v` for two vectors (row-major `n × n` matrix `P`), every row of `P` read
    /// once for both.
    pub fn project2(p: &[f64], n: usize, x0: &[f64], x1: &[f64], out: &mut [f64]) = project2_body;
}

lanes_kernel! {
    /// `out[v] = P x_v` for four vectors, every row of `P` read once for all of them.
    pub fn project4(p: &[f64], n: usize, x: [&[f64]; 4], out: &mut [f64]) = project4_body;
}

/// # Safety
/// `S` must be usable on this CPU.
#[inline(always)]
unsafe fn project2_rect_body<S: Lanes, const F: bool>(
    p: &[f64],
    shape: (usize, usize),
    x0: &[f64],
    x1: &[f64],
    out: &mut [f64],
) {
    // SAFETY: as for `project2_body`.
    unsafe { project_rows::<S, F, 2>(p, shape, [x0, x1], out) }
}

lanes_kernel! {
    /// `out[v] = P x_v` for two vectors, `P` row-major of shape `(rows, columns)` (a line's
    /// window move: a wire's basis onto the next position's), every row read once for both.
    pub fn project2_rect(p: &[f64], shape: (usize, usize), x0: &[f64], x1: &[f64], out: &mut [f64]) = project2_rect_body;
}
