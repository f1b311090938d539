//! Dense products: dot products, the Cholesky substitutions of the implicit point terms, the
//! finiteness check, and the dense rows' gather and scatter.

use super::*;

// ---------------------------------------------------------------------------------------------
// Dense products.

/// # Safety
/// `S` must be usable on this CPU.
#[inline(always)]
unsafe fn dot_body<S: Lanes, const F: bool>(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len().min(b.len());
    let (pa, pb) = (a.as_ptr(), b.as_ptr());
    // SAFETY: `S` is usable (this function's contract); every read is of four values at
    // `i..i + 4 <= n`, or one at `i < n`, with `n` the shorter slice's length.
    unsafe {
        let mut acc = [S::zero(); 4];
        let mut i = 0;
        while i + 16 <= n {
            for (l, c) in acc.iter_mut().enumerate() {
                *c = S::mad(S::load(pa.add(i + 4 * l)), S::load(pb.add(i + 4 * l)), *c);
            }
            i += 16;
        }
        while i + 4 <= n {
            acc[0] = S::mad(S::load(pa.add(i)), S::load(pb.add(i)), acc[0]);
            i += 4;
        }
        let mut s = S::add(S::add(acc[0], acc[1]), S::add(acc[2], acc[3])).sum();
        while i < n {
            s = mad::<F>(*pa.add(i), *pb.add(i), s);
            i += 1;
        }
        s
    }
}

lanes_kernel! {
    /// `Σ a_i b_i`.
    pub fn dot(a: &[f64], b: &[f64]) -> f64 = dot_body;
}

/// # Safety
/// `S` must be usable on this CPU.
#[inline(always)]
unsafe fn cholesky_solve_body<S: Lanes, const F: bool>(
    l: &[f64],
    n: usize,
    b: &mut [f64],
    tmp: &mut [f64],
) {
    assert!(
        l.len() >= n * n && b.len() >= n && tmp.len() >= n,
        "cholesky_solve: slices too short"
    );
    for i in 0..n {
        // SAFETY: `dot_body` reads only the shorter of its two slices, both checked by slicing.
        let d = unsafe { dot_body::<S, F>(&l[i * n..i * n + i], &tmp[..i]) };
        tmp[i] = (b[i] - d) / l[i * n + i];
    }
    for i in (0..n).rev() {
        // Row i of Lᵀ (the upper triangle) holds column i of L.
        // SAFETY: as above.
        let d = unsafe { dot_body::<S, F>(&l[i * n + i + 1..(i + 1) * n], &b[i + 1..n]) };
        b[i] = (tmp[i] - d) / l[i * n + i];
    }
}

lanes_kernel! {
    /// Solve `L Lᵀ x = b` in place in `b` (`tmp`: scratch of length `n`), `l` as
    /// [`crate::linalg::cholesky_in_place`] leaves it (`L` below the diagonal, `Lᵀ` above): each
    /// substitution takes one contiguous row's product, of `L` forwards and of `Lᵀ` backwards,
    /// by [`dot`]'s sum (inlined: the same sums in the same order as calling it per row).
    pub fn cholesky_solve(l: &[f64], n: usize, b: &mut [f64], tmp: &mut [f64]) = cholesky_solve_body;
}

/// # Safety
/// None beyond the macro's: the body is safe code (`S` only picks the instruction set the
/// compiler may vectorise it with).
#[inline(always)]
unsafe fn capacitance_body<S: Lanes, const F: bool>(
    rows_t: &[f64],
    np: usize,
    d: &[f64],
    cap: &mut [f64],
) {
    assert!(
        rows_t.len() >= d.len() * np && cap.len() >= np * np,
        "capacitance: slices too short"
    );
    cap[..np * np].fill(0.0);
    for (r, &dk) in rows_t.chunks_exact(np).zip(d) {
        for (i, &a) in r.iter().enumerate() {
            let row = &mut cap[i * np..i * np + i + 1];
            for (c, &b) in row.iter_mut().zip(&r[..=i]) {
                *c += a * b / dk;
            }
        }
    }
}

lanes_kernel! {
    /// The lower triangle of `Φ D⁻¹ Φᵀ` (row `i`, columns `0..=i`; the rest of `cap` zero):
    /// `cap[i·np + j] = Σ_k φ_ik φ_jk / d_k`, summed in `k` order from zero, with `rows_t` the
    /// `n × np` transpose of `Φ` (row `k` holds mode `k` at every point). Each entry is the
    /// same sequence of roundings as the sum taken entry by entry (a product, a quotient, an
    /// addition per mode; never fused), so both paths give the same bytes; the x86-64-v3 path
    /// lets the compiler update four entries at once. [`crate::solve::implicit`]'s capacitance
    /// matrix.
    pub fn capacitance(rows_t: &[f64], np: usize, d: &[f64], cap: &mut [f64]) = capacitance_body;
}

/// # Safety
/// `S` must be usable on this CPU.
#[inline(always)]
unsafe fn all_finite_body<S: Lanes, const F: bool>(xs: &[f64]) -> bool {
    let (n, p) = (xs.len(), xs.as_ptr());
    // SAFETY: every read is below `n`.
    unsafe {
        let zero = S::zero();
        let mut acc = [S::zero(); 2];
        let mut i = 0;
        while i + 8 <= n {
            for l in 0..2 {
                acc[l] = S::mad(S::load(p.add(i + 4 * l)), zero, acc[l]);
            }
            i += 8;
        }
        if i + 4 <= n {
            acc[0] = S::mad(S::load(p.add(i)), zero, acc[0]);
            i += 4;
        }
        let mut r = S::add(acc[0], acc[1]).sum();
        while i < n {
            r += *p.add(i) * 0.0;
            i += 1;
        }
        r == 0.0
    }
}

lanes_kernel! {
    /// Whether every value is finite, without a branch per value: `x·0 + s` is `s` (up to the
    /// sign of a zero) for a finite `x` and NaN otherwise, so the sum of `x·0` over the values is
    /// zero exactly when all are finite (the same answer on both paths: the product is exact).
    pub fn all_finite(xs: &[f64]) -> bool = all_finite_body;
}

/// # Safety
/// `S` must be usable on this CPU.
#[inline(always)]
unsafe fn dot2_body<S: Lanes, const F: bool>(row: &[f64], x: &[f64], y: &[f64]) -> (f64, f64) {
    let n = row.len().min(x.len()).min(y.len());
    let (pr, px, py) = (row.as_ptr(), x.as_ptr(), y.as_ptr());
    // SAFETY: `S` is usable (this function's contract); every read of `row`, `x`, `y` is at
    // `i..i + 4 <= n` or `i < n`, with `n` the shortest slice's length.
    unsafe {
        let mut ax = [S::zero(); 2];
        let mut ay = [S::zero(); 2];
        let mut i = 0;
        while i + 8 <= n {
            for l in 0..2 {
                let r = S::load(pr.add(i + 4 * l));
                ax[l] = S::mad(r, S::load(px.add(i + 4 * l)), ax[l]);
                ay[l] = S::mad(r, S::load(py.add(i + 4 * l)), ay[l]);
            }
            i += 8;
        }
        if i + 4 <= n {
            let r = S::load(pr.add(i));
            ax[0] = S::mad(r, S::load(px.add(i)), ax[0]);
            ay[0] = S::mad(r, S::load(py.add(i)), ay[0]);
            i += 4;
        }
        let mut sx = S::add(ax[0], ax[1]).sum();
        let mut sy = S::add(ay[0], ay[1]).sum();
        while i < n {
            let r = *pr.add(i);
            sx = mad::<F>(r, *px.add(i), sx);
            sy = mad::<F>(r, *py.add(i), sy);
            i += 1;
        }
        (sx, sy)
    }
}

lanes_kernel! {
    /// `(Σ r_i x_i, Σ r_i y_i)`: two vectors against one row, read once.
    pub fn dot2(row: &[f64], x: &[f64], y: &[f64]) -> (f64, f64) = dot2_body;
}

#[inline(always)]
fn axpy_body<const F: bool>(alpha: f64, x: &[f64], y: &mut [f64]) {
    for (yi, xi) in y.iter_mut().zip(x) {
        *yi = mad::<F>(alpha, *xi, *yi);
    }
}

kernel! {
    /// `y += α x`.
    pub fn axpy(alpha: f64, x: &[f64], y: &mut [f64]) = axpy_body;
}

/// # Safety
/// `S` must be usable on this CPU.
#[inline(always)]
unsafe fn axpy2_rows_body<S: Lanes, const F: bool>(
    rows: &[f64],
    ax: &[f64],
    ay: &[f64],
    x: &mut [f64],
    y: &mut [f64],
) {
    let m = ax.len();
    let n = x.len();
    assert!(
        ay.len() == m && y.len() == n && rows.len() >= m * n,
        "axpy2_rows: {m} rows of {n} need {} values, {} given; {} and {} coefficients, {} and {} outputs",
        m * n,
        rows.len(),
        ax.len(),
        ay.len(),
        x.len(),
        y.len()
    );
    let (pr, px, py) = (rows.as_ptr(), x.as_mut_ptr(), y.as_mut_ptr());
    // SAFETY: every read of `rows` is below `m·n`, of `x`, `y` below `n`, all checked above;
    // `x` and `y` are distinct `&mut` slices.
    unsafe {
        let mut i = 0;
        // Sixteen modes of both outputs stay in registers while the rows pass.
        while i + 16 <= n {
            let mut sx: [S; 4] = std::array::from_fn(|l| S::load(px.add(i + 4 * l)));
            let mut sy: [S; 4] = std::array::from_fn(|l| S::load(py.add(i + 4 * l)));
            for j in 0..m {
                let (cx, cy) = (
                    splat::<S>(*ax.get_unchecked(j)),
                    splat::<S>(*ay.get_unchecked(j)),
                );
                let r = pr.add(j * n + i);
                for l in 0..4 {
                    let rl = S::load(r.add(4 * l));
                    sx[l] = S::mad(cx, rl, sx[l]);
                    sy[l] = S::mad(cy, rl, sy[l]);
                }
            }
            for l in 0..4 {
                sx[l].store(px.add(i + 4 * l));
                sy[l].store(py.add(i + 4 * l));
            }
            i += 16;
        }
        while i + 4 <= n {
            let (mut sx, mut sy) = (S::load(px.add(i)), S::load(py.add(i)));
            for j in 0..m {
                let (cx, cy) = (
                    splat::<S>(*ax.get_unchecked(j)),
                    splat::<S>(*ay.get_unchecked(j)),
                );
                let rl = S::load(pr.add(j * n + i));
                sx = S::mad(cx, rl, sx);
                sy = S::mad(cy, rl, sy);
            }
            sx.store(px.add(i));
            sy.store(py.add(i));
            i += 4;
        }
        while i < n {
            let (mut sx, mut sy) = (*px.add(i), *py.add(i));
            for j in 0..m {
                let r = *pr.add(j * n + i);
                sx = mad::<F>(*ax.get_unchecked(j), r, sx);
                sy = mad::<F>(*ay.get_unchecked(j), r, sy);
            }
            *px.add(i) = sx;
            *py.add(i) = sy;
            i += 1;
        }
    }
}

lanes_kernel! {
    /// `x += Σ_j α_j r_j`, `y += Σ_j β_j r_j` over the rows `r_j` (row `j` at `rows[j·n..]`,
    /// `n = x.len()`, `α = ax`, `β = ay`): every output updated row by row, in the rows' order,
    /// by one multiply-add each (the same operations as a row at a time, `x_i ← α_j r_ji +
    /// x_i`), with sixteen outputs of each held in registers while the rows pass, so that each
    /// output is loaded and stored once, not once per row.
    pub fn axpy2_rows(rows: &[f64], ax: &[f64], ay: &[f64], x: &mut [f64], y: &mut [f64]) = axpy2_rows_body;
}
