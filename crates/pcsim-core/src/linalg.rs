//! Small dense kernels used by every layer: dot products, `axpy`, and the small matrices of the
//! pantographs and the implicit point terms.
//!
//! Written by hand: the matrices are a handful of rows (a pantograph's masses) or a few dozen (the
//! capacitance matrix of the implicit point terms) and are factorised once; a linear-algebra
//! crate would cost more build time on a 2-core CI than these 100 lines.

/// Dot product with four explicit partial sums (vectorises without reassociating behind our
/// back; the summation order is fixed, so results are reproducible).
#[inline]
pub fn dot(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len().min(b.len());
    let (a, b) = (&a[..n], &b[..n]);
    let mut acc = [0.0f64; 4];
    let chunks = n / 4;
    for c in 0..chunks {
        for l in 0..4 {
            acc[l] += a[4 * c + l] * b[4 * c + l];
        }
    }
    let mut s = (acc[0] + acc[1]) + (acc[2] + acc[3]);
    for i in 4 * chunks..n {
        s += a[i] * b[i];
    }
    s
}

/// `y += alpha * x`.
#[inline]
pub fn axpy(alpha: f64, x: &[f64], y: &mut [f64]) {
    for (yi, xi) in y.iter_mut().zip(x) {
        *yi += alpha * xi;
    }
}

/// A matrix that is not positive definite where it must be.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NotPositiveDefinite {
    /// The row whose pivot was not positive.
    pub row: usize,
    /// The pivot found.
    pub pivot: f64,
}

/// Inverse of a small dense matrix (row-major `n × n`) by Gauss–Jordan with partial pivoting.
/// `None` when a pivot vanishes (singular matrix).
pub fn invert_small(a: &[f64], n: usize) -> Option<Vec<f64>> {
    let mut m = a.to_vec();
    let mut inv = vec![0.0; n * n];
    for i in 0..n {
        inv[i * n + i] = 1.0;
    }
    for col in 0..n {
        let piv = (col..n)
            .max_by(|&i, &j| m[i * n + col].abs().total_cmp(&m[j * n + col].abs()))
            .unwrap_or(col);
        if piv != col {
            for j in 0..n {
                m.swap(col * n + j, piv * n + j);
                inv.swap(col * n + j, piv * n + j);
            }
        }
        let d = m[col * n + col];
        if d == 0.0 || !d.is_finite() {
            return None;
        }
        for j in 0..n {
            m[col * n + j] /= d;
            inv[col * n + j] /= d;
        }
        for i in 0..n {
            if i != col {
                let f = m[i * n + col];
                if f != 0.0 {
                    for j in 0..n {
                        m[i * n + j] -= f * m[col * n + j];
                        inv[i * n + j] -= f * inv[col * n + j];
                    }
                }
            }
        }
    }
    Some(inv)
}

/// `y = A x` for a small row-major `n × n` matrix.
pub fn mat_vec(a: &[f64], n: usize, x: &[f64]) -> Vec<f64> {
    (0..n)
        .map(|i| (0..n).map(|j| a[i * n + j] * x[j]).sum())
        .collect()
}

/// In-place Cholesky of a symmetric positive definite row-major `n × n` matrix; the lower
/// triangle holds `L` afterwards, and the upper its transpose (so that both substitutions of
/// `solve::kernels::cholesky_solve` read rows). A pivot that is not positive is an error, never
/// clamped.
pub fn cholesky_in_place(a: &mut [f64], n: usize) -> Result<(), NotPositiveDefinite> {
    for j in 0..n {
        let mut d = a[j * n + j];
        for k in 0..j {
            d -= a[j * n + k] * a[j * n + k];
        }
        if !(d > 0.0 && d.is_finite()) {
            return Err(NotPositiveDefinite { row: j, pivot: d });
        }
        let d = d.sqrt();
        a[j * n + j] = d;
        for i in j + 1..n {
            let mut s = a[i * n + j];
            for k in 0..j {
                s -= a[i * n + k] * a[j * n + k];
            }
            a[i * n + j] = s / d;
        }
    }
    for i in 0..n {
        for j in 0..i {
            a[j * n + i] = a[i * n + j];
        }
    }
    Ok(())
}
