//! The projections that carry a window's state onto the next window's sine basis: a shift on one
//! basis ([`shift_projection`], closed form; its defining integrals for the tests) and one basis
//! onto another over their common part ([`basis_projection`], a line's wires).

/// `∫_0^A cos(ω x + φ) dx`.
fn int_cos(omega: f64, phi: f64, a: f64) -> f64 {
    if omega.abs() < 1e-12 {
        a * phi.cos()
    } else {
        ((omega * a + phi).sin() - phi.sin()) / omega
    }
}

/// The projection `P_kj` of a shift by `d` on a sine basis over `w` (row-major `n × n`), by its
/// defining integrals: `P_kj = (2/W) ∫_0^{W−d} sin(κ_k x) sin(κ_j (x + d)) dx`. The reference
/// for [`shift_projection`].
pub fn shift_projection_by_integrals(w: f64, n: usize, d: f64) -> Vec<f64> {
    let kap = |i: usize| (i + 1) as f64 * std::f64::consts::PI / w;
    let a = (w - d).max(0.0);
    let mut p = vec![0.0; n * n];
    for k in 0..n {
        for j in 0..n {
            let (kj, kk) = (kap(j), kap(k));
            let phi = kj * d;
            p[k * n + j] = (int_cos(kj - kk, phi, a) - int_cos(kj + kk, phi, a)) / w;
        }
    }
    p
}

/// The projection `P_kj` of a shift by `d` on a sine basis over `w` (row-major `n × n`), in its
/// closed Toeplitz + Hankel form (mode numbers `j, k ≥ 1`, `s_m = sin(mπd/W)`,
/// `σ_m = (−1)^m`):
///
/// ```text
/// P_kj = (σ_j σ_k s_k − s_j) / ((j − k) π) + (σ_j σ_k s_k + s_j) / ((j + k) π),   j ≠ k,
/// P_kk = (1 − d/W) cos(kπd/W) + s_k / (kπ).
/// ```
///
/// Tested against [`shift_projection_by_integrals`]. It needs one sine and one cosine per mode
/// instead of four per entry.
pub fn shift_projection(w: f64, n: usize, d: f64) -> Vec<f64> {
    use std::f64::consts::PI;
    let th = |m: usize| m as f64 * PI * d / w;
    let s: Vec<f64> = (0..=n).map(|m| th(m).sin()).collect();
    let sg = |m: usize| if m % 2 == 0 { 1.0 } else { -1.0 };
    let mut p = vec![0.0; n * n];
    for k in 1..=n {
        for j in 1..=n {
            let v = if j == k {
                (1.0 - d / w) * th(k).cos() + s[k] / (k as f64 * PI)
            } else {
                let ss = sg(j) * sg(k) * s[k];
                (ss - s[j]) / ((j as f64 - k as f64) * PI) + (ss + s[j]) / ((j + k) as f64 * PI)
            };
            p[(k - 1) * n + (j - 1)] = v;
        }
    }
    p
}

/// `∫_0^A cos(ω x + φ) dx = 2 cos(φ + ωA/2) sin(ωA/2) / ω`, in a form without cancellation
/// when ω is small (the wires' bases on a line differ a little in length).
fn int_cos_stable(omega: f64, phi: f64, a: f64) -> f64 {
    let half = 0.5 * omega * a;
    let sinc = if half.abs() < 1e-8 {
        1.0 - half * half / 6.0
    } else {
        half.sin() / half
    };
    a * (phi + half).cos() * sinc
}

/// The projection of a wire's modes from one sine basis onto another over the part they share
/// (row-major `n_to × n_from`): the bases cover `[a_from, a_from + l_from]` and
/// `[a_to, a_to + l_to]` (track coordinates), and
/// `P_kj = (2/l_to) ∫ sin(κ_j (x − a_from)) sin(κ'_k (x − a_to)) dx` over their common part.
/// On equal bases shifted by `d` it is [`shift_projection`].
pub fn basis_projection(
    (a_from, l_from, n_from): (f64, f64, usize),
    (a_to, l_to, n_to): (f64, f64, usize),
) -> Vec<f64> {
    use std::f64::consts::PI;
    let x0 = a_from.max(a_to);
    let len = ((a_from + l_from).min(a_to + l_to) - x0).max(0.0);
    let mut p = vec![0.0; n_to * n_from];
    for k in 0..n_to {
        let kk = (k + 1) as f64 * PI / l_to;
        let pk = kk * (x0 - a_to);
        for j in 0..n_from {
            let kj = (j + 1) as f64 * PI / l_from;
            let pj = kj * (x0 - a_from);
            p[k * n_from + j] = (int_cos_stable(kj - kk, pj - pk, len)
                - int_cos_stable(kj + kk, pj + pk, len))
                / l_to;
        }
    }
    p
}
