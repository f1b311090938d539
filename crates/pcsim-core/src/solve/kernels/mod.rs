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

/// `[v, v, v, v]`.
///
/// # Safety
/// `S` must be usable on this CPU.
#[inline(always)]
unsafe fn splat<S: Lanes>(v: f64) -> S {
    // SAFETY: reads a local array of four.
    unsafe { S::load([v; 4].as_ptr()) }
}

mod dense;
mod folds;
mod modal;
mod projection;
mod sines;
mod spectra;
mod unfolds;

pub use dense::*;
pub use folds::*;
pub use modal::*;
pub use projection::*;
pub use sines::*;
pub use spectra::*;
pub use unfolds::*;
