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

/// The process-wide choice (see [`Isa::detect`]).
static CHOICE: OnceLock<Isa> = OnceLock::new();

impl Isa {
    /// The best instruction set of this CPU, unless `PCSIM_PORTABLE` is set (to anything but `0`
    /// or an empty string) or [`Isa::force_portable`] was called first. Decided once per
    /// process.
    pub fn detect() -> Isa {
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

    /// Use the portable path for the rest of the process (the `--portable` flag). Returns
    /// false when the choice was already made otherwise.
    pub fn force_portable() -> bool {
        *CHOICE.get_or_init(|| Isa::Portable) == Isa::Portable
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
            Isa::X86V3 => "x86-64-v3",
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
// Four lanes: the unit of the reductions and blocked kernels. The portable lanes are four plain
// `f64`s (multiply, then add); the x86-64-v3 lanes are one AVX2 register with fused
// multiply-add. Both reduce in the same order, `(l0 + l1) + (l2 + l3)`, so the two paths differ
// only in rounding. Written with explicit lanes because the compiler's auto-vectoriser kept the
// reductions scalar or two-wide.

/// Four `f64` lanes. Every method is `unsafe`: the pointers must be valid for four reads or
/// writes, and the AVX2 lanes may only be used when the CPU has AVX2 and FMA.
trait Lanes: Copy {
    unsafe fn zero() -> Self;
    unsafe fn load(p: *const f64) -> Self;
    unsafe fn store(self, p: *mut f64);
    /// `a·b + c`.
    unsafe fn mad(a: Self, b: Self, c: Self) -> Self;
    unsafe fn mul(a: Self, b: Self) -> Self;
    unsafe fn add(a: Self, b: Self) -> Self;
    /// `a − b`.
    unsafe fn sub(a: Self, b: Self) -> Self;
    /// The lanes in reverse order (`[l3, l2, l1, l0]`).
    unsafe fn rev(self) -> Self;
    /// Four complex numbers `[re0, im0, …, re3, im3]` at `p` as `(re, im)`.
    unsafe fn load_split(p: *const f64) -> (Self, Self);
    /// `re`, `im` stored as four complex numbers `[re0, im0, …, re3, im3]` at `p`.
    unsafe fn store_joined(re: Self, im: Self, p: *mut f64);
    /// `(l0 + l1) + (l2 + l3)`.
    unsafe fn sum(self) -> f64;
}

#[derive(Clone, Copy)]
struct Plain([f64; 4]);

impl Lanes for Plain {
    #[inline(always)]
    unsafe fn zero() -> Self {
        Plain([0.0; 4])
    }
    #[inline(always)]
    unsafe fn load(p: *const f64) -> Self {
        // SAFETY: the trait's contract: `p` is valid for four reads (read unaligned).
        Plain(unsafe { p.cast::<[f64; 4]>().read_unaligned() })
    }
    #[inline(always)]
    unsafe fn store(self, p: *mut f64) {
        // SAFETY: the trait's contract: `p` is valid for four writes (written unaligned).
        unsafe { p.cast::<[f64; 4]>().write_unaligned(self.0) }
    }
    #[inline(always)]
    unsafe fn mad(a: Self, b: Self, c: Self) -> Self {
        Plain(std::array::from_fn(|l| a.0[l] * b.0[l] + c.0[l]))
    }
    #[inline(always)]
    unsafe fn mul(a: Self, b: Self) -> Self {
        Plain(std::array::from_fn(|l| a.0[l] * b.0[l]))
    }
    #[inline(always)]
    unsafe fn add(a: Self, b: Self) -> Self {
        Plain(std::array::from_fn(|l| a.0[l] + b.0[l]))
    }
    #[inline(always)]
    unsafe fn sub(a: Self, b: Self) -> Self {
        Plain(std::array::from_fn(|l| a.0[l] - b.0[l]))
    }
    #[inline(always)]
    unsafe fn rev(self) -> Self {
        Plain([self.0[3], self.0[2], self.0[1], self.0[0]])
    }
    #[inline(always)]
    unsafe fn load_split(p: *const f64) -> (Self, Self) {
        // SAFETY: the trait's contract: `p` is valid for eight reads (four complex numbers).
        let v = unsafe { p.cast::<[f64; 8]>().read_unaligned() };
        (
            Plain([v[0], v[2], v[4], v[6]]),
            Plain([v[1], v[3], v[5], v[7]]),
        )
    }
    #[inline(always)]
    unsafe fn store_joined(re: Self, im: Self, p: *mut f64) {
        let (r, i) = (re.0, im.0);
        // SAFETY: the trait's contract: `p` is valid for eight writes (four complex numbers).
        unsafe {
            p.cast::<[f64; 8]>()
                .write_unaligned([r[0], i[0], r[1], i[1], r[2], i[2], r[3], i[3]])
        }
    }
    #[inline(always)]
    unsafe fn sum(self) -> f64 {
        (self.0[0] + self.0[1]) + (self.0[2] + self.0[3])
    }
}

#[cfg(target_arch = "x86_64")]
mod avx {
    use std::arch::x86_64::*;

    #[derive(Clone, Copy)]
    pub(super) struct Avx(__m256d);

    impl super::Lanes for Avx {
        #[inline]
        #[target_feature(enable = "avx2,fma")]
        unsafe fn zero() -> Self {
            Avx(_mm256_setzero_pd())
        }
        #[inline]
        #[target_feature(enable = "avx2,fma")]
        unsafe fn load(p: *const f64) -> Self {
            // SAFETY: the trait's contract (`p` valid for four reads); this impl is only reached on a
            // CPU with AVX2 and FMA (`lanes_kernel!` dispatches on `Isa::detect`).
            Avx(unsafe { _mm256_loadu_pd(p) })
        }
        #[inline]
        #[target_feature(enable = "avx2,fma")]
        unsafe fn store(self, p: *mut f64) {
            // SAFETY: the trait's contract (`p` valid for four writes); AVX2 checked as for `load`.
            unsafe { _mm256_storeu_pd(p, self.0) }
        }
        #[inline]
        #[target_feature(enable = "avx2,fma")]
        unsafe fn mad(a: Self, b: Self, c: Self) -> Self {
            Avx(_mm256_fmadd_pd(a.0, b.0, c.0))
        }
        #[inline]
        #[target_feature(enable = "avx2,fma")]
        unsafe fn mul(a: Self, b: Self) -> Self {
            Avx(_mm256_mul_pd(a.0, b.0))
        }
        #[inline]
        #[target_feature(enable = "avx2,fma")]
        unsafe fn add(a: Self, b: Self) -> Self {
            Avx(_mm256_add_pd(a.0, b.0))
        }
        #[inline]
        #[target_feature(enable = "avx2,fma")]
        unsafe fn sub(a: Self, b: Self) -> Self {
            Avx(_mm256_sub_pd(a.0, b.0))
        }
        #[inline]
        #[target_feature(enable = "avx2,fma")]
        unsafe fn rev(self) -> Self {
            Avx(_mm256_permute4x64_pd::<0x1B>(self.0))
        }
        #[inline]
        #[target_feature(enable = "avx2,fma")]
        unsafe fn load_split(p: *const f64) -> (Self, Self) {
            // [r0 i0 r1 i1], [r2 i2 r3 i3] → [r0 i0 r2 i2], [r1 i1 r3 i3] → [r0..r3], [i0..i3].
            // SAFETY: the trait's contract (`p` valid for eight reads: both halves); AVX2 as for `load`.
            let (a, b) = unsafe { (_mm256_loadu_pd(p), _mm256_loadu_pd(p.add(4))) };
            let t0 = _mm256_permute2f128_pd::<0x20>(a, b);
            let t1 = _mm256_permute2f128_pd::<0x31>(a, b);
            (
                Avx(_mm256_unpacklo_pd(t0, t1)),
                Avx(_mm256_unpackhi_pd(t0, t1)),
            )
        }
        #[inline]
        #[target_feature(enable = "avx2,fma")]
        unsafe fn store_joined(re: Self, im: Self, p: *mut f64) {
            // [re0 im0 re2 im2], [re1 im1 re3 im3] → [re0 im0 re1 im1], [re2 im2 re3 im3].
            let lo = _mm256_unpacklo_pd(re.0, im.0);
            let hi = _mm256_unpackhi_pd(re.0, im.0);
            // SAFETY: the trait's contract (`p` valid for eight writes: both halves); AVX2 as for `load`.
            unsafe {
                _mm256_storeu_pd(p, _mm256_permute2f128_pd::<0x20>(lo, hi));
                _mm256_storeu_pd(p.add(4), _mm256_permute2f128_pd::<0x31>(lo, hi));
            }
        }
        #[inline]
        #[target_feature(enable = "avx2,fma")]
        unsafe fn sum(self) -> f64 {
            let lo = _mm256_castpd256_pd128(self.0);
            let hi = _mm256_extractf128_pd::<1>(self.0);
            let l01 = _mm_add_sd(lo, _mm_unpackhi_pd(lo, lo));
            let l23 = _mm_add_sd(hi, _mm_unpackhi_pd(hi, hi));
            _mm_cvtsd_f64(_mm_add_sd(l01, l23))
        }
    }
}

/// Dispatch a kernel written over [`Lanes`] to the chosen instruction set.
macro_rules! lanes_kernel {
    ($(#[$m:meta])* pub fn $name:ident($($arg:ident: $ty:ty),*) $(-> $ret:ty)? = $body:ident;) => {
        $(#[$m])*
        #[inline]
        pub fn $name(isa: Isa, $($arg: $ty),*) $(-> $ret)? {
            #[cfg(target_arch = "x86_64")]
            {
                #[target_feature(enable = "avx2,fma")]
                unsafe fn v3($($arg: $ty),*) $(-> $ret)? {
                    // SAFETY: the caller checked the CPU; the body checks its own bounds.
                    unsafe { $body::<avx::Avx, true>($($arg),*) }
                }
                if isa == Isa::X86V3 {
                    // SAFETY: `Isa::X86V3` is only chosen when the CPU has AVX2 and FMA.
                    return unsafe { v3($($arg),*) };
                }
            }
            let _ = isa;
            // SAFETY: plain lanes need no CPU feature; the body checks its own bounds.
            unsafe { $body::<Plain, false>($($arg),*) }
        }
    };
}

// ---------------------------------------------------------------------------------------------
// Sines of a moving point's row.

/// `[v, v, v, v]`.
///
/// # Safety
/// `S` must be usable on this CPU.
#[inline(always)]
unsafe fn splat<S: Lanes>(v: f64) -> S {
    // SAFETY: reads a local array of four.
    unsafe { S::load([v; 4].as_ptr()) }
}

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

#[inline(always)]
fn quadratic_body<const F: bool>(out: &mut [f64], c0: &[f64], c1: &[f64], c2: &[f64], tau: f64) {
    for (((o, a), b), c) in out.iter_mut().zip(c0).zip(c1).zip(c2) {
        *o = mad::<F>(tau, mad::<F>(tau, *c, *b), *a);
    }
}

kernel! {
    /// `out = c0 + τ (c1 + τ c2)` (a quadratic in `τ` per value: the crosswind's generalised
    /// forces inside one interval of its field).
    pub fn quadratic(out: &mut [f64], c0: &[f64], c1: &[f64], c2: &[f64], tau: f64) = quadratic_body;
}

#[inline(always)]
fn flow_body<const F: bool>(q: &mut [f64], v: &mut [f64], m: &[[f64; 4]]) {
    for ((qi, vi), c) in q.iter_mut().zip(v.iter_mut()).zip(m) {
        let (q0, v0) = (*qi, *vi);
        *qi = mad::<F>(c[0], q0, c[1] * v0);
        *vi = mad::<F>(c[2], q0, c[3] * v0);
    }
}

kernel! {
    /// `(q, v) ← Φ (q, v)` per mode with `Φ = [[m0, m1], [m2, m3]]`: the exact flow of each
    /// damped modal oscillator over one step (the torsional series, see `integrator`).
    pub fn flow(q: &mut [f64], v: &mut [f64], m: &[[f64; 4]]) = flow_body;
}

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

// ---------------------------------------------------------------------------------------------
// The periodic sampler's spectra (`solve/sampler.rs`): its pack and unpack in four lanes. Each
// lane does the scalar form's operations in its order (multiplies and adds, never fused), so both
// instruction-set paths give the scalar form's bytes.

/// # Safety
/// `S` must be usable on this CPU.
#[inline(always)]
unsafe fn pack_bins_body<S: Lanes, const F: bool>(x: &[f64], y: &[f64], p: usize, buf: &mut [f64]) {
    let two = !y.is_empty();
    assert!(
        p >= 1 && x.len() >= 2 * p && (!two || y.len() >= 2 * p) && buf.len() >= 2 * p,
        "pack_bins: slices too short"
    );
    let m = p - 1;
    let (ax, bx) = x[..2 * p].split_at(p);
    let (ay, by) = if two {
        y[..2 * p].split_at(p)
    } else {
        (&[][..], &[][..])
    };
    buf[0] = ax[m];
    buf[1] = if two { ay[m] } else { 0.0 };
    let mut i = 0;
    // SAFETY: a chunk reads `i..i + 4` and `m − 4 − i..m − i` of each bin array (`i + 4 ≤ m`,
    // so both inside `0..m`) and writes complex numbers `i + 1..i + 5 ≤ p` of `buf`.
    unsafe {
        let (h, nh) = (splat::<S>(0.5), splat::<S>(-0.5));
        let o = buf.as_mut_ptr();
        while i + 4 <= m {
            let j = m - 4 - i;
            // A chunk at `i` and its mirror at `j`, reversed.
            let ends = |v: &[f64]| (S::load(v.as_ptr().add(i)), S::load(v.as_ptr().add(j)).rev());
            let ((a, an), (b, bn)) = (ends(ax), ends(bx));
            let re_x = S::mul(h, S::add(a, an));
            let im_x = S::mul(nh, S::sub(b, bn));
            if two {
                let ((c, cn), (d, dn)) = (ends(ay), ends(by));
                let re_y = S::mul(h, S::add(c, cn));
                let im_y = S::mul(nh, S::sub(d, dn));
                S::store_joined(S::sub(re_x, im_y), S::add(im_x, re_y), o.add(2 * (i + 1)));
            } else {
                S::store_joined(re_x, im_x, o.add(2 * (i + 1)));
            }
            i += 4;
        }
    }
    for i in i..m {
        let n = m - 1 - i;
        let (re_x, im_x) = (0.5 * (ax[i] + ax[n]), -0.5 * (bx[i] - bx[n]));
        if two {
            let (re_y, im_y) = (0.5 * (ay[i] + ay[n]), -0.5 * (by[i] - by[n]));
            buf[2 * (i + 1)] = re_x - im_y;
            buf[2 * (i + 1) + 1] = im_x + re_y;
        } else {
            buf[2 * (i + 1)] = re_x;
            buf[2 * (i + 1) + 1] = im_x;
        }
    }
}

lanes_kernel! {
    /// The Hermitian spectrum of one or two units of bins (`x = [a_x | b_x]`, `y = [a_y | b_y]`
    /// or empty, each `2p`) as `p` complex numbers in `buf` (`[re, im, …]`): `buf_0 =
    /// (a_x[p−1], a_y[p−1])`, and for `ρ = i + 1`, with `n = p − 2 − i`, `re_x = ½(a_x[i] +
    /// a_x[n])`, `im_x = −½(b_x[i] − b_x[n])` (and `_y` alike), `buf_ρ = (re_x − im_y, im_x +
    /// re_y)` (see `PointSampler::pack`).
    pub fn pack_bins(x: &[f64], y: &[f64], p: usize, buf: &mut [f64]) = pack_bins_body;
}

/// # Safety
/// `S` must be usable on this CPU.
#[inline(always)]
unsafe fn unpack_bins_body<S: Lanes, const F: bool>(
    buf: &[f64],
    p: usize,
    x: &mut [f64],
    y: &mut [f64],
) {
    let two = !y.is_empty();
    assert!(
        p >= 1 && buf.len() >= 2 * p && x.len() >= 2 * p && (!two || y.len() >= 2 * p),
        "unpack_bins: slices too short"
    );
    let m = p - 1;
    let (xa, xb) = x[..2 * p].split_at_mut(p);
    let (ya, yb) = if two {
        y[..2 * p].split_at_mut(p)
    } else {
        (&mut [][..], &mut [][..])
    };
    xa[m] = buf[0];
    xb[m] = 0.0;
    if two {
        ya[m] = buf[1];
        yb[m] = 0.0;
    }
    let mut i = 0;
    // SAFETY: a chunk reads complex numbers `i + 1..i + 5` and `m − i − 3..m − i + 1` of `buf`
    // (`i + 4 ≤ m`, so both inside `1..p`) and writes bins `i..i + 4 < m` of each array.
    unsafe {
        let h = splat::<S>(0.5);
        let b = buf.as_ptr();
        while i + 4 <= m {
            let (rr, ri) = S::load_split(b.add(2 * (i + 1)));
            let (nr, ni) = S::load_split(b.add(2 * (m - i - 3)));
            let (nr, ni) = (nr.rev(), ni.rev());
            S::mul(h, S::add(rr, nr)).store(xa.as_mut_ptr().add(i));
            S::mul(h, S::sub(ri, ni)).store(xb.as_mut_ptr().add(i));
            if two {
                S::mul(h, S::add(ri, ni)).store(ya.as_mut_ptr().add(i));
                S::mul(h, S::sub(nr, rr)).store(yb.as_mut_ptr().add(i));
            }
            i += 4;
        }
    }
    for i in i..m {
        let (r, n) = (2 * (i + 1), 2 * (m - i));
        xa[i] = 0.5 * (buf[r] + buf[n]);
        xb[i] = 0.5 * (buf[r + 1] - buf[n + 1]);
        if two {
            ya[i] = 0.5 * (buf[r + 1] + buf[n + 1]);
            yb[i] = 0.5 * (buf[n] - buf[r]);
        }
    }
}

lanes_kernel! {
    /// The transpose of [`pack_bins`]: from the transform `Y` (`p` complex numbers in `buf`) of
    /// `F_x + i F_y`, the bins `[C | S]` of unit x (and of unit y when `y` is not empty): bin
    /// `i < p − 1` takes `Y_{i+1}` and `Y_{p−1−i}`, bin `p − 1` takes `Y_0` (see
    /// `PointSampler::unpack`).
    pub fn unpack_bins(buf: &[f64], p: usize, x: &mut [f64], y: &mut [f64]) = unpack_bins_body;
}

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
    fn the_four_lane_sines_are_the_scalar_recurrences_bytes() {
        for n in [
            1usize, 3, 4, 5, 15, 16, 17, 33, 255, 256, 257, 271, 1200, 1203,
        ] {
            let b = crate::model::basis::SineBasis::new(1834.7, n);
            for x in [0.0, 0.3, 17.25, 911.1, 1834.6, -2.5] {
                let mut want = vec![0.0; n];
                b.fill_sines(x, &mut want);
                for isa in [Isa::Portable, Isa::best_available()] {
                    let mut got = vec![9.0; n];
                    fill_sines(isa, b.theta(x), &mut got);
                    let same = got
                        .iter()
                        .zip(&want)
                        .all(|(g, w)| g.to_bits() == w.to_bits());
                    assert!(same, "n {n}, x {x}, {isa:?}");
                    // The fill with the row's sum against q: the same row, and dot's bytes.
                    let q = data(n, 7);
                    let mut row = vec![9.0; n];
                    let d = fill_sines_dot(isa, b.theta(x), &mut row, &q);
                    assert!(row
                        .iter()
                        .zip(&want)
                        .all(|(g, w)| g.to_bits() == w.to_bits()));
                    assert_eq!(d.to_bits(), dot(isa, &q, &want).to_bits(), "n {n}, x {x}");
                }
            }
        }
    }

    /// The substitutions solve `A x = b` for a factored `A = L Lᵀ`, and are the per-row
    /// [`dot`] substitutions' bytes on both paths (n = 23: the 16-wide, 4-wide and scalar parts).
    #[test]
    fn the_cholesky_substitutions_solve_and_keep_the_dot_kernels_bytes() {
        let n = 23;
        let g = data(n * n, 21);
        // A = G Gᵀ + n I: symmetric positive definite.
        let a: Vec<f64> = (0..n * n)
            .map(|ij| {
                let (i, j) = (ij / n, ij % n);
                let s: f64 = (0..n).map(|k| g[i * n + k] * g[j * n + k]).sum();
                s + if i == j { n as f64 } else { 0.0 }
            })
            .collect();
        let mut l = a.clone();
        crate::linalg::cholesky_in_place(&mut l, n).unwrap();
        let rhs = data(n, 22);
        for isa in [Isa::Portable, Isa::best_available()] {
            let (mut x, mut tmp) = (rhs.clone(), vec![0.0; n]);
            cholesky_solve(isa, &l, n, &mut x, &mut tmp);
            for i in 0..n {
                let ax: f64 = (0..n).map(|k| a[i * n + k] * x[k]).sum();
                assert!((ax - rhs[i]).abs() < 1e-12, "{isa:?} row {i}");
            }
            // The same substitutions, a call of the dot kernel per row.
            let (mut y, mut t) = (rhs.clone(), vec![0.0; n]);
            for i in 0..n {
                t[i] = (y[i] - dot(isa, &l[i * n..i * n + i], &t[..i])) / l[i * n + i];
            }
            for i in (0..n).rev() {
                y[i] =
                    (t[i] - dot(isa, &l[i * n + i + 1..(i + 1) * n], &y[i + 1..n])) / l[i * n + i];
            }
            assert!(
                x.iter().zip(&y).all(|(u, v)| u.to_bits() == v.to_bits()),
                "{isa:?}"
            );
        }
    }

    /// The rows' updates with sixteen outputs held in registers are a row at a time's bytes on
    /// both paths (`x_i ← α_j r_ji + x_i`, fused on the x86-64-v3 path, not on the portable
    /// one), for lengths with a 16-wide, a 4-wide and a scalar part, and for no rows at all.
    #[test]
    fn the_rows_updates_are_a_row_at_a_times_bytes() {
        for (n, m) in [(1, 3), (7, 1), (16, 5), (23, 9), (143, 36), (40, 0)] {
            let rows = data(m * n, 31);
            let (ax, ay) = (data(m, 32), data(m, 33));
            for isa in [Isa::Portable, Isa::best_available()] {
                let (mut x, mut y) = (data(n, 34), data(n, 35));
                let (mut x1, mut y1) = (x.clone(), y.clone());
                axpy2_rows(isa, &rows, &ax, &ay, &mut x, &mut y);
                for j in 0..m {
                    for i in 0..n {
                        let r = rows[j * n + i];
                        if isa == Isa::Portable {
                            x1[i] += ax[j] * r;
                            y1[i] += ay[j] * r;
                        } else {
                            x1[i] = ax[j].mul_add(r, x1[i]);
                            y1[i] = ay[j].mul_add(r, y1[i]);
                        }
                    }
                }
                let same =
                    |a: &[f64], b: &[f64]| a.iter().zip(b).all(|(u, v)| u.to_bits() == v.to_bits());
                assert!(same(&x, &x1) && same(&y, &y1), "{isa:?} n {n} m {m}");
            }
        }
    }

    /// A fold or unfold of two groups in one pass is two passes' bytes, on both paths, with
    /// and without a scale, for periods with and without 8- and 4-wide blocks of bins and mode
    /// counts with a partial last row.
    #[test]
    fn two_groups_in_one_pass_are_two_passes_bytes() {
        let same = |a: &[f64], b: &[f64]| a.iter().zip(b).all(|(u, v)| u.to_bits() == v.to_bits());
        for (n, p) in [(5, 2), (37, 6), (61, 13), (143, 8), (250, 60), (1203, 60)] {
            let (q1, q2) = (data(n, 41), data(n, 42));
            let t: Vec<Vec<f64>> = (0..4).map(|i| data(n, 43 + i)).collect();
            let tabs = [&t[0][..], &t[1], &t[2], &t[3]];
            let scale = data(n, 47);
            for isa in [Isa::Portable, Isa::best_available()] {
                let what = format!("{isa:?} n {n} p {p}");
                // Folds.
                let (mut a, mut b) = (vec![9.0; 2 * p], vec![9.0; 2 * p]);
                fold1x2(isa, &q1, tabs, p, [&mut a, &mut b]);
                let (mut a1, mut b1) = (vec![0.0; 2 * p], vec![0.0; 2 * p]);
                fold1(isa, &q1, &t[0], &t[1], p, &mut a1);
                fold1(isa, &q1, &t[2], &t[3], p, &mut b1);
                assert!(same(&a, &a1) && same(&b, &b1), "fold1x2 {what}");
                let (mut a, mut b) = (vec![9.0; 4 * p], vec![9.0; 4 * p]);
                fold2x2(isa, &q1, &q2, tabs, p, [&mut a, &mut b]);
                let (mut a2, mut b2) = (vec![0.0; 4 * p], vec![0.0; 4 * p]);
                fold2(isa, &q1, &q2, &t[0], &t[1], p, &mut a2);
                fold2(isa, &q1, &q2, &t[2], &t[3], p, &mut b2);
                assert!(same(&a, &a2) && same(&b, &b2), "fold2x2 {what}");
                // Unfolds of those bins, onto outputs that already hold values.
                for sc in [&[][..], &scale] {
                    let mut o = q2.clone();
                    unfold1x2(isa, [&a1, &b1], tabs, p, &mut o, sc);
                    let mut o1 = q2.clone();
                    unfold1(isa, &a1, &t[0], &t[1], p, &mut o1, sc);
                    unfold1(isa, &b1, &t[2], &t[3], p, &mut o1, sc);
                    assert!(same(&o, &o1), "unfold1x2 {what} scaled {}", !sc.is_empty());
                }
                let (mut x, mut y) = (q1.clone(), q2.clone());
                unfold2x2(isa, [&a2, &b2], tabs, p, &mut x, &mut y);
                let (mut x1, mut y1) = (q1.clone(), q2.clone());
                unfold2(isa, &a2, &t[0], &t[1], p, &mut x1, &mut y1);
                unfold2(isa, &b2, &t[2], &t[3], p, &mut x1, &mut y1);
                assert!(same(&x, &x1) && same(&y, &y1), "unfold2x2 {what}");
            }
        }
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
        project2(Isa::Portable, &pm, n, &x, &y, &mut o0);
        project2(best, &pm, n, &x, &y, &mut o1);
        let mut o4 = vec![0.0; 4 * n];
        project4(best, &pm, n, [&y, &x, &y, &x], &mut o4);
        // A rectangular P (rows × columns, both odd and not multiples of four) on both paths.
        let (rows, cols) = (23, 37);
        for isa in [Isa::Portable, best] {
            let mut o = vec![0.0; 2 * rows];
            project2_rect(isa, &pm, (rows, cols), &x, &y, &mut o);
            for k in 0..rows {
                let ex: f64 = (0..cols).map(|j| pm[k * cols + j] * x[j]).sum();
                let ey: f64 = (0..cols).map(|j| pm[k * cols + j] * y[j]).sum();
                assert!((o[k] - ex).abs() < 1e-12 && (o[rows + k] - ey).abs() < 1e-12);
            }
        }
        for k in 0..n {
            let e: f64 = (0..n).map(|j| pm[k * n + j] * y[j]).sum();
            assert!((o0[n + k] - e).abs() < 1e-12 && (o1[n + k] - e).abs() < 1e-12);
            assert!((o4[k] - e).abs() < 1e-12 && (o4[2 * n + k] - e).abs() < 1e-12);
        }
    }
}
