//! The hot loops of a step, in two instruction sets chosen at run time: an x86-64-v3 path (AVX2
//! and fused multiply-add) and a portable path (plain multiply and add, the same on every
//! machine). Each kernel is written once as a generic body; the two paths differ only in whether
//! `a·b + c` is fused (one rounding) or not (two roundings), so their results differ at the level
//! of rounding, not in method.
//!
//! The choice is made once per integrator ([`Isa::default`]): the x86-64-v3 path where the CPU
//! has AVX2 and FMA, unless the environment variable `PCSIM_PORTABLE=1` (or the `--portable`
//! flag) asks for the portable path, which gives the same bytes on every machine. The same
//! binary on the same machine gives the same bytes with either choice, with or without threads:
//! no kernel depends on the thread count or on data-dependent ordering.

use std::sync::OnceLock;

/// The instruction set of the hot loops.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Isa {
    /// Multiply, then add: the same bytes on every machine.
    Portable,
    /// AVX2 with fused multiply-add (x86-64-v3).
    X86V3,
}

impl Isa {
    /// The best instruction set of this CPU, unless `PCSIM_PORTABLE` is set (to anything but `0`
    /// or an empty string). Decided once per process.
    pub fn detect() -> Isa {
        static CHOICE: OnceLock<Isa> = OnceLock::new();
        *CHOICE.get_or_init(|| {
            let portable = std::env::var("PCSIM_PORTABLE")
                .map(|v| !v.is_empty() && v != "0")
                .unwrap_or(false);
            if portable {
                Isa::Portable
            } else {
                Isa::best_available()
            }
        })
    }

    /// The best instruction set the CPU offers, whatever the environment says.
    pub fn best_available() -> Isa {
        #[cfg(target_arch = "x86_64")]
        {
            if std::arch::is_x86_feature_detected!("avx2")
                && std::arch::is_x86_feature_detected!("fma")
            {
                return Isa::X86V3;
            }
        }
        Isa::Portable
    }

    /// A short name for reports.
    pub fn name(self) -> &'static str {
        match self {
            Isa::Portable => "portable",
            Isa::X86V3 => "x86-64-v3 (AVX2+FMA)",
        }
    }
}

impl Default for Isa {
    fn default() -> Self {
        Isa::detect()
    }
}

/// `a·b + c`, fused or not.
#[inline(always)]
fn mad<const F: bool>(a: f64, b: f64, c: f64) -> f64 {
    if F {
        a.mul_add(b, c)
    } else {
        a * b + c
    }
}

/// Dispatch a kernel body to the chosen instruction set.
macro_rules! kernel {
    ($(#[$m:meta])* pub fn $name:ident($($arg:ident: $ty:ty),*) $(-> $ret:ty)? = $body:ident;) => {
        $(#[$m])*
        #[inline]
        pub fn $name(isa: Isa, $($arg: $ty),*) $(-> $ret)? {
            #[cfg(target_arch = "x86_64")]
            {
                #[target_feature(enable = "avx2,fma")]
                unsafe fn v3($($arg: $ty),*) $(-> $ret)? {
                    $body::<true>($($arg),*)
                }
                if isa == Isa::X86V3 {
                    // SAFETY: `Isa::X86V3` is only chosen when the CPU has AVX2 and FMA.
                    return unsafe { v3($($arg),*) };
                }
            }
            let _ = isa;
            $body::<false>($($arg),*)
        }
    };
}

// ---------------------------------------------------------------------------------------------
// Dense products.

#[inline(always)]
fn dot_body<const F: bool>(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len().min(b.len());
    let (a, b) = (&a[..n], &b[..n]);
    let mut acc = [0.0f64; 8];
    let mut ca = a.chunks_exact(8);
    let mut cb = b.chunks_exact(8);
    for (x, y) in (&mut ca).zip(&mut cb) {
        for l in 0..8 {
            acc[l] = mad::<F>(x[l], y[l], acc[l]);
        }
    }
    let mut s = ((acc[0] + acc[4]) + (acc[1] + acc[5])) + ((acc[2] + acc[6]) + (acc[3] + acc[7]));
    for (x, y) in ca.remainder().iter().zip(cb.remainder()) {
        s = mad::<F>(*x, *y, s);
    }
    s
}

kernel! {
    /// `Σ a_i b_i`.
    pub fn dot(a: &[f64], b: &[f64]) -> f64 = dot_body;
}

#[inline(always)]
fn dot2_body<const F: bool>(row: &[f64], x: &[f64], y: &[f64]) -> (f64, f64) {
    let n = row.len().min(x.len()).min(y.len());
    let (row, x, y) = (&row[..n], &x[..n], &y[..n]);
    let mut ax = [0.0f64; 4];
    let mut ay = [0.0f64; 4];
    let mut cr = row.chunks_exact(4);
    let mut cx = x.chunks_exact(4);
    let mut cy = y.chunks_exact(4);
    for ((r, a), b) in (&mut cr).zip(&mut cx).zip(&mut cy) {
        for l in 0..4 {
            ax[l] = mad::<F>(r[l], a[l], ax[l]);
            ay[l] = mad::<F>(r[l], b[l], ay[l]);
        }
    }
    let mut sx = (ax[0] + ax[1]) + (ax[2] + ax[3]);
    let mut sy = (ay[0] + ay[1]) + (ay[2] + ay[3]);
    for ((r, a), b) in cr
        .remainder()
        .iter()
        .zip(cx.remainder())
        .zip(cy.remainder())
    {
        sx = mad::<F>(*r, *a, sx);
        sy = mad::<F>(*r, *b, sy);
    }
    (sx, sy)
}

kernel! {
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

#[inline(always)]
fn axpy2_body<const F: bool>(ax: f64, ay: f64, row: &[f64], x: &mut [f64], y: &mut [f64]) {
    for ((r, xi), yi) in row.iter().zip(x.iter_mut()).zip(y.iter_mut()) {
        *xi = mad::<F>(ax, *r, *xi);
        *yi = mad::<F>(ay, *r, *yi);
    }
}

kernel! {
    /// `x += α_x r`, `y += α_y r`: one row, read once, into two vectors.
    pub fn axpy2(ax: f64, ay: f64, row: &[f64], x: &mut [f64], y: &mut [f64]) = axpy2_body;
}

// ---------------------------------------------------------------------------------------------
// The modal parts of a step.

#[inline(always)]
fn kick_drift_body<const F: bool>(q: &mut [f64], v: &mut [f64], a: &[f64], h: f64, dt: f64) {
    for ((qi, vi), ai) in q.iter_mut().zip(v.iter_mut()).zip(a) {
        *vi = mad::<F>(h, *ai, *vi);
        *qi = mad::<F>(dt, *vi, *qi);
    }
}

kernel! {
    /// `v += h a; q += Δt v` (the first half of a velocity-Verlet step).
    pub fn kick_drift(q: &mut [f64], v: &mut [f64], a: &[f64], h: f64, dt: f64) = kick_drift_body;
}

#[inline(always)]
fn modal_rhs_body<const F: bool>(a: &mut [f64], q: &[f64], v: &[f64], k: &[f64], c: &[f64]) {
    for ((((ai, qi), vi), ki), ci) in a.iter_mut().zip(q).zip(v).zip(k).zip(c) {
        *ai = mad::<F>(-ki, *qi, -ci * vi);
    }
}

kernel! {
    /// `a = −K q − C v` (diagonal modal stiffness and damping).
    pub fn modal_rhs(a: &mut [f64], q: &[f64], v: &[f64], k: &[f64], c: &[f64]) = modal_rhs_body;
}

#[inline(always)]
fn scale_kick_body<const F: bool>(a: &mut [f64], d_inv: &[f64]) {
    for (ai, di) in a.iter_mut().zip(d_inv) {
        *ai *= di;
    }
}

kernel! {
    /// `a ⊙= d⁻¹`.
    pub fn scale(a: &mut [f64], d_inv: &[f64]) = scale_kick_body;
}

#[inline(always)]
fn kick_body<const F: bool>(v: &mut [f64], a: &[f64], h: f64) {
    for (vi, ai) in v.iter_mut().zip(a) {
        *vi = mad::<F>(h, *ai, *vi);
    }
}

kernel! {
    /// `v += h a`.
    pub fn kick(v: &mut [f64], a: &[f64], h: f64) = kick_body;
}

// ---------------------------------------------------------------------------------------------
// The folds of the span-periodic sampler (see `sampler.rs`): bins of period P.

/// Register block of the fold kernels.
const BLK: usize = 8;

#[inline(always)]
fn fold2_body<const F: bool>(
    q1: &[f64],
    q2: &[f64],
    s: &[f64],
    c: &[f64],
    p: usize,
    out: &mut [f64],
) {
    // out = [a1 | b1 | a2 | b2], each of length p.
    let n = q1.len().min(q2.len()).min(s.len()).min(c.len());
    let mut r0 = 0;
    while r0 < p {
        let w = BLK.min(p - r0);
        let mut acc = [[0.0f64; BLK]; 4];
        let mut base = r0;
        if w == BLK {
            while base + BLK <= n {
                let x: &[f64; BLK] = q1[base..base + BLK].try_into().expect("block");
                let y: &[f64; BLK] = q2[base..base + BLK].try_into().expect("block");
                let ss: &[f64; BLK] = s[base..base + BLK].try_into().expect("block");
                let cc: &[f64; BLK] = c[base..base + BLK].try_into().expect("block");
                for l in 0..BLK {
                    acc[0][l] = mad::<F>(x[l], ss[l], acc[0][l]);
                    acc[1][l] = mad::<F>(x[l], cc[l], acc[1][l]);
                    acc[2][l] = mad::<F>(y[l], ss[l], acc[2][l]);
                    acc[3][l] = mad::<F>(y[l], cc[l], acc[3][l]);
                }
                base += p;
            }
        }
        while base < n {
            for l in 0..w.min(n - base) {
                acc[0][l] = mad::<F>(q1[base + l], s[base + l], acc[0][l]);
                acc[1][l] = mad::<F>(q1[base + l], c[base + l], acc[1][l]);
                acc[2][l] = mad::<F>(q2[base + l], s[base + l], acc[2][l]);
                acc[3][l] = mad::<F>(q2[base + l], c[base + l], acc[3][l]);
            }
            base += p;
        }
        for (k, a) in acc.iter().enumerate() {
            out[k * p + r0..k * p + r0 + w].copy_from_slice(&a[..w]);
        }
        r0 += w;
    }
}

kernel! {
    /// The folds of two coefficient vectors sharing the tables `s = sin(κd)`, `c = cos(κd)`:
    /// `out = [a1 | b1 | a2 | b2]` with `a[r] = Σ_m q[mP+r] s[mP+r]`, `b[r] = Σ_m q[mP+r] c[mP+r]`.
    /// Blocks of 8 bins stay in registers while the loop walks down the modes.
    pub fn fold2(q1: &[f64], q2: &[f64], s: &[f64], c: &[f64], p: usize, out: &mut [f64]) = fold2_body;
}

#[inline(always)]
fn fold1_body<const F: bool>(q: &[f64], s: &[f64], c: &[f64], p: usize, out: &mut [f64]) {
    let n = q.len().min(s.len()).min(c.len());
    let mut r0 = 0;
    while r0 < p {
        let w = BLK.min(p - r0);
        let mut acc = [[0.0f64; BLK]; 2];
        let mut base = r0;
        if w == BLK {
            while base + BLK <= n {
                let x: &[f64; BLK] = q[base..base + BLK].try_into().expect("block");
                let ss: &[f64; BLK] = s[base..base + BLK].try_into().expect("block");
                let cc: &[f64; BLK] = c[base..base + BLK].try_into().expect("block");
                for l in 0..BLK {
                    acc[0][l] = mad::<F>(x[l], ss[l], acc[0][l]);
                    acc[1][l] = mad::<F>(x[l], cc[l], acc[1][l]);
                }
                base += p;
            }
        }
        while base < n {
            for l in 0..w.min(n - base) {
                acc[0][l] = mad::<F>(q[base + l], s[base + l], acc[0][l]);
                acc[1][l] = mad::<F>(q[base + l], c[base + l], acc[1][l]);
            }
            base += p;
        }
        out[r0..r0 + w].copy_from_slice(&acc[0][..w]);
        out[p + r0..p + r0 + w].copy_from_slice(&acc[1][..w]);
        r0 += w;
    }
}

kernel! {
    /// [`fold2`] for one vector: `out = [a | b]`.
    pub fn fold1(q: &[f64], s: &[f64], c: &[f64], p: usize, out: &mut [f64]) = fold1_body;
}

#[inline(always)]
fn unfold2_body<const F: bool>(
    bins: &[f64],
    s: &[f64],
    c: &[f64],
    p: usize,
    o1: &mut [f64],
    o2: &mut [f64],
) {
    // bins = [a1 | b1 | a2 | b2]; o1[mP+r] += a1[r] s + b1[r] c, o2 likewise.
    let n = o1.len().min(o2.len()).min(s.len()).min(c.len());
    let mut r0 = 0;
    while r0 < p {
        let w = BLK.min(p - r0);
        let mut base = r0;
        if w == BLK {
            let mut r = [[0.0f64; BLK]; 4];
            for (k, rk) in r.iter_mut().enumerate() {
                rk.copy_from_slice(&bins[k * p + r0..k * p + r0 + BLK]);
            }
            while base + BLK <= n {
                let ss: &[f64; BLK] = s[base..base + BLK].try_into().expect("block");
                let cc: &[f64; BLK] = c[base..base + BLK].try_into().expect("block");
                let x: &mut [f64; BLK] = (&mut o1[base..base + BLK]).try_into().expect("block");
                for l in 0..BLK {
                    x[l] = mad::<F>(r[0][l], ss[l], mad::<F>(r[1][l], cc[l], x[l]));
                }
                let y: &mut [f64; BLK] = (&mut o2[base..base + BLK]).try_into().expect("block");
                for l in 0..BLK {
                    y[l] = mad::<F>(r[2][l], ss[l], mad::<F>(r[3][l], cc[l], y[l]));
                }
                base += p;
            }
        }
        while base < n {
            for l in 0..w.min(n - base) {
                let (ss, cc) = (s[base + l], c[base + l]);
                o1[base + l] = mad::<F>(
                    bins[r0 + l],
                    ss,
                    mad::<F>(bins[p + r0 + l], cc, o1[base + l]),
                );
                o2[base + l] = mad::<F>(
                    bins[2 * p + r0 + l],
                    ss,
                    mad::<F>(bins[3 * p + r0 + l], cc, o2[base + l]),
                );
            }
            base += p;
        }
        r0 += w;
    }
}

kernel! {
    /// The transpose of [`fold2`]: `o[mP+r] += a[r] s[mP+r] + b[r] c[mP+r]` for both vectors,
    /// `bins = [a1 | b1 | a2 | b2]`.
    pub fn unfold2(bins: &[f64], s: &[f64], c: &[f64], p: usize, o1: &mut [f64], o2: &mut [f64]) = unfold2_body;
}

#[inline(always)]
fn unfold1_body<const F: bool>(
    bins: &[f64],
    s: &[f64],
    c: &[f64],
    p: usize,
    o: &mut [f64],
    scale: &[f64],
) {
    // o[mP+r] += scale[mP+r] · (a[r] s + b[r] c); an empty `scale` means 1.
    let n = o.len().min(s.len()).min(c.len());
    let scaled = !scale.is_empty();
    let mut r0 = 0;
    while r0 < p {
        let w = BLK.min(p - r0);
        let mut base = r0;
        if w == BLK {
            let mut ra = [0.0f64; BLK];
            let mut rb = [0.0f64; BLK];
            ra.copy_from_slice(&bins[r0..r0 + BLK]);
            rb.copy_from_slice(&bins[p + r0..p + r0 + BLK]);
            while base + BLK <= n {
                let ss: &[f64; BLK] = s[base..base + BLK].try_into().expect("block");
                let cc: &[f64; BLK] = c[base..base + BLK].try_into().expect("block");
                let x: &mut [f64; BLK] = (&mut o[base..base + BLK]).try_into().expect("block");
                if scaled {
                    let sc: &[f64; BLK] = scale[base..base + BLK].try_into().expect("block");
                    for l in 0..BLK {
                        let val = mad::<F>(ra[l], ss[l], rb[l] * cc[l]);
                        x[l] = mad::<F>(sc[l], val, x[l]);
                    }
                } else {
                    for l in 0..BLK {
                        x[l] = mad::<F>(ra[l], ss[l], mad::<F>(rb[l], cc[l], x[l]));
                    }
                }
                base += p;
            }
        }
        while base < n {
            for l in 0..w.min(n - base) {
                let (ss, cc) = (s[base + l], c[base + l]);
                if scaled {
                    let val = mad::<F>(bins[r0 + l], ss, bins[p + r0 + l] * cc);
                    o[base + l] = mad::<F>(scale[base + l], val, o[base + l]);
                } else {
                    o[base + l] = mad::<F>(
                        bins[r0 + l],
                        ss,
                        mad::<F>(bins[p + r0 + l], cc, o[base + l]),
                    );
                }
            }
            base += p;
        }
        r0 += w;
    }
}

kernel! {
    /// The transpose of [`fold1`], optionally scaled per mode: `o[m] += scale[m] (a[r] s[m] +
    /// b[r] c[m])` (`scale` empty: 1). The scaled form fuses the Woodbury correction
    /// `a −= D⁻¹ Φᵀ g` into the scatter.
    pub fn unfold1(bins: &[f64], s: &[f64], c: &[f64], p: usize, o: &mut [f64], scale: &[f64]) = unfold1_body;
}

// ---------------------------------------------------------------------------------------------
// The window move: a dense projection of up to four vectors.

#[inline(always)]
fn project_body<const F: bool>(p: &[f64], n: usize, xs: &[&[f64]], out: &mut [f64]) {
    // out[v n + k] = Σ_j P[k n + j] x_v[j], each row of P read once for every vector.
    let nv = xs.len().min(4);
    let chunks = n / 4;
    for k in 0..n {
        let row = &p[k * n..(k + 1) * n];
        let mut acc = [[0.0f64; 4]; 4];
        for cidx in 0..chunks {
            let r: &[f64; 4] = row[4 * cidx..4 * cidx + 4].try_into().expect("block");
            for (a, x) in acc.iter_mut().zip(xs.iter()).take(nv) {
                let x: &[f64; 4] = x[4 * cidx..4 * cidx + 4].try_into().expect("block");
                for l in 0..4 {
                    a[l] = mad::<F>(r[l], x[l], a[l]);
                }
            }
        }
        for (v, (a, x)) in acc.iter().zip(xs.iter()).enumerate().take(nv) {
            let mut sum = (a[0] + a[1]) + (a[2] + a[3]);
            for j in 4 * chunks..n {
                sum = mad::<F>(row[j], x[j], sum);
            }
            out[v * n + k] = sum;
        }
    }
}

kernel! {
    /// `out[v] = P x_v` for up to four vectors (row-major `n × n` matrix `P`), every row of `P`
    /// read once for all of them.
    pub fn project(p: &[f64], n: usize, xs: &[&[f64]], out: &mut [f64]) = project_body;
}

#[cfg(test)]
mod tests {
    use super::*;

    fn data(n: usize, seed: u64) -> Vec<f64> {
        let mut x = seed;
        (0..n)
            .map(|_| {
                x = x
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                ((x >> 11) as f64 / (1u64 << 53) as f64) - 0.5
            })
            .collect()
    }

    #[test]
    fn both_instruction_sets_agree_to_rounding() {
        let best = Isa::best_available();
        let (a, b, c) = (data(1203, 1), data(1203, 2), data(1203, 3));
        let d0 = dot(Isa::Portable, &a, &b);
        let d1 = dot(best, &a, &b);
        let exact: f64 = a.iter().zip(&b).map(|(x, y)| x * y).sum();
        assert!((d0 - exact).abs() < 1e-12 && (d1 - exact).abs() < 1e-12);
        let (x0, y0) = dot2(Isa::Portable, &c, &a, &b);
        let (x1, y1) = dot2(best, &c, &a, &b);
        assert!((x0 - x1).abs() < 1e-12 && (y0 - y1).abs() < 1e-12);
        for p in [4usize, 12, 60, 62, 120] {
            let mut o0 = vec![0.0; 4 * p];
            let mut o1 = vec![0.0; 4 * p];
            fold2(Isa::Portable, &a, &b, &c, &a, p, &mut o0);
            fold2(best, &a, &b, &c, &a, p, &mut o1);
            for (u, v) in o0.iter().zip(&o1) {
                assert!((u - v).abs() < 1e-12, "fold2 p={p}");
            }
            let mut s0 = vec![0.0; 2 * p];
            fold1(Isa::Portable, &b, &c, &a, p, &mut s0);
            for r in 0..p {
                assert!(
                    (s0[r] - o0[2 * p + r]).abs() < 1e-12
                        && (s0[p + r] - o0[3 * p + r]).abs() < 1e-12
                );
            }
            let (mut u0, mut v0) = (b.clone(), c.clone());
            let (mut u1, mut v1) = (b.clone(), c.clone());
            unfold2(Isa::Portable, &o0, &a, &c, p, &mut u0, &mut v0);
            unfold2(best, &o0, &a, &c, p, &mut u1, &mut v1);
            for k in 0..a.len() {
                assert!((u0[k] - u1[k]).abs() < 1e-12 && (v0[k] - v1[k]).abs() < 1e-12);
            }
            // unfold1 with a scale equals unfold1 into zeros, then a scaled add.
            let mut w = vec![0.0; a.len()];
            unfold1(best, &o0, &a, &c, p, &mut w, &[]);
            let mut ws = b.clone();
            unfold1(best, &o0, &a, &c, p, &mut ws, &c);
            for k in 0..a.len() {
                assert!((ws[k] - (b[k] + c[k] * w[k])).abs() < 1e-12);
            }
        }
        let n = 37;
        let pm = data(n * n, 9);
        let (x, y) = (data(n, 10), data(n, 11));
        let mut o0 = vec![0.0; 2 * n];
        let mut o1 = vec![0.0; 2 * n];
        project(Isa::Portable, &pm, n, &[&x, &y], &mut o0);
        project(best, &pm, n, &[&x, &y], &mut o1);
        for k in 0..n {
            let e: f64 = (0..n).map(|j| pm[k * n + j] * y[j]).sum();
            assert!((o0[n + k] - e).abs() < 1e-12 && (o1[n + k] - e).abs() < 1e-12);
        }
    }
}
