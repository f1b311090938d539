//! Zero-phase Butterworth filtering of the contact force (README §4; EN 50318).
//!
//! Filters are designed like `scipy.signal.butter(order, Wn, btype, output="sos", fs=fs)`
//! (analogue prototype, frequency pre-warping, bilinear transform, second-order sections) and
//! applied like `scipy.signal.sosfiltfilt` (odd extension of `3·(2·n_sections + 1)` samples,
//! steady-state initial conditions, forward then backward). The golden test compares with SciPy
//! output committed in `data/golden/`.
//!
//! Written by hand (≈150 lines) with that stated reason: the Rust crates that offer `butter` and
//! `sosfiltfilt` (sci-rs) pull in nalgebra and a Kalman-filter crate, and the exact SciPy padding
//! convention matters for matching the golden files.
//!
//! The statistics use order 4 (applied forward and backward: zero phase, 8th-order magnitude
//! roll-off, −6 dB at the cut-off).

use std::f64::consts::PI;

/// Order of the Butterworth designs used for the EN 50318 statistics.
pub const STATS_ORDER: usize = 4;

#[derive(Clone, Copy, Debug, PartialEq)]
struct C64 {
    re: f64,
    im: f64,
}

impl C64 {
    fn new(re: f64, im: f64) -> Self {
        Self { re, im }
    }
    fn add(self, o: Self) -> Self {
        Self::new(self.re + o.re, self.im + o.im)
    }
    fn sub(self, o: Self) -> Self {
        Self::new(self.re - o.re, self.im - o.im)
    }
    fn mul(self, o: Self) -> Self {
        Self::new(
            self.re * o.re - self.im * o.im,
            self.re * o.im + self.im * o.re,
        )
    }
    fn div(self, o: Self) -> Self {
        let d = o.re * o.re + o.im * o.im;
        Self::new(
            (self.re * o.re + self.im * o.im) / d,
            (self.im * o.re - self.re * o.im) / d,
        )
    }
    fn scale(self, s: f64) -> Self {
        Self::new(self.re * s, self.im * s)
    }
    fn sqrt(self) -> Self {
        let r = (self.re * self.re + self.im * self.im).sqrt();
        let re = ((r + self.re) / 2.0).max(0.0).sqrt();
        let im = ((r - self.re) / 2.0)
            .max(0.0)
            .sqrt()
            .copysign(if self.im == 0.0 { 1.0 } else { self.im });
        Self::new(re, im)
    }
}

/// Second-order sections `[b0, b1, b2, a0(=1), a1, a2]`.
#[derive(Debug, Clone, PartialEq)]
pub struct Sos(pub Vec<[f64; 6]>);

/// Filter band.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Band {
    /// Low-pass below the cut-off, Hz.
    Lowpass(f64),
    /// Band-pass between the two cut-offs, Hz.
    Bandpass(f64, f64),
}

/// Digital Butterworth design, as `scipy.signal.butter(order, …, output="sos", fs=fs)`.
pub fn butter(order: usize, band: Band, fs: f64) -> Sos {
    assert!(order >= 1);
    // Analogue prototype poles (unit cut-off).
    let proto: Vec<C64> = (0..order)
        .map(|k| {
            let m = -(order as f64) + 1.0 + 2.0 * k as f64;
            let th = PI * m / (2.0 * order as f64);
            C64::new(-th.cos(), -th.sin()).scale(1.0) // -exp(iπm/2n)
        })
        .collect();
    let warp = |f: f64| 2.0 * fs * (PI * f / fs).tan();
    let fs2 = 2.0 * fs;
    let (zeros_a, poles_a, mut k): (Vec<Option<C64>>, Vec<C64>, f64) = match band {
        Band::Lowpass(fc) => {
            let w = warp(fc);
            (
                vec![],
                proto.iter().map(|p| p.scale(w)).collect(),
                w.powi(order as i32),
            )
        }
        Band::Bandpass(f1, f2) => {
            let (w1, w2) = (warp(f1), warp(f2));
            let bw = w2 - w1;
            let w0 = (w1 * w2).sqrt();
            let mut poles = Vec::new();
            for p in &proto {
                let pl = p.scale(bw / 2.0);
                let disc = pl.mul(pl).sub(C64::new(w0 * w0, 0.0)).sqrt();
                poles.push(pl.add(disc));
                poles.push(pl.sub(disc));
            }
            (
                vec![Some(C64::new(0.0, 0.0)); order],
                poles,
                bw.powi(order as i32),
            )
        }
    };
    // Bilinear transform.
    let two = C64::new(fs2, 0.0);
    let zd: Vec<C64> = zeros_a
        .iter()
        .map(|z| z.map(|z| two.add(z).div(two.sub(z))).unwrap())
        .collect();
    let pd: Vec<C64> = poles_a
        .iter()
        .map(|&p| two.add(p).div(two.sub(p)))
        .collect();
    let mut num = C64::new(1.0, 0.0);
    for z in zeros_a.iter().flatten() {
        num = num.mul(two.sub(*z));
    }
    let mut den = C64::new(1.0, 0.0);
    for &p in &poles_a {
        den = den.mul(two.sub(p));
    }
    k *= num.div(den).re;
    let n_inf = pd.len() - zd.len();
    let mut zeros: Vec<C64> = zd;
    zeros.extend(std::iter::repeat_n(C64::new(-1.0, 0.0), n_inf));
    // Pair poles: conjugate pairs (upper half plane) plus a lone real pole if odd.
    let mut upper: Vec<C64> = pd.iter().copied().filter(|p| p.im > 1e-14).collect();
    let mut real: Vec<f64> = pd
        .iter()
        .filter(|p| p.im.abs() <= 1e-14)
        .map(|p| p.re)
        .collect();
    upper.sort_by(|a, b| {
        (1.0 - (a.re * a.re + a.im * a.im).sqrt())
            .total_cmp(&(1.0 - (b.re * b.re + b.im * b.im).sqrt()))
            .reverse()
    });
    real.sort_by(|a, b| a.total_cmp(b));
    let mut zr: Vec<f64> = zeros.iter().map(|z| z.re).collect();
    zr.sort_by(|a, b| a.total_cmp(b));
    let mut sections = Vec::new();
    for p in &upper {
        let a1 = -2.0 * p.re;
        let a2 = p.re * p.re + p.im * p.im;
        let z1 = zr.pop().unwrap_or(0.0);
        let z2 = zr.remove(0);
        sections.push([1.0, -(z1 + z2), z1 * z2, 1.0, a1, a2]);
    }
    while real.len() >= 2 {
        let (p1, p2) = (real.pop().unwrap_or(0.0), real.pop().unwrap_or(0.0));
        let z1 = zr.pop().unwrap_or(0.0);
        let z2 = zr.pop().unwrap_or(0.0);
        sections.push([1.0, -(z1 + z2), z1 * z2, 1.0, -(p1 + p2), p1 * p2]);
    }
    if let Some(p) = real.pop() {
        let z = zr.pop().unwrap_or(-1.0);
        sections.push([1.0, -z, 0.0, 1.0, -p, 0.0]);
    }
    for v in &mut sections[0][..3] {
        *v *= k;
    }
    Sos(sections)
}

impl Sos {
    /// Steady-state initial conditions per section for a unit step (`scipy.signal.sosfilt_zi`).
    fn zi(&self) -> Vec<[f64; 2]> {
        let mut scale = 1.0;
        self.0
            .iter()
            .map(|s| {
                let (b, a) = (&s[..3], &s[3..]);
                // lfilter_zi for order 2: (I − Aᵀ_companion) zi = b[1:] − a[1:] b0
                let b1 = b[1] - a[1] * b[0];
                let b2 = b[2] - a[2] * b[0];
                // IminusA = [[1 + a1, -1], [a2, 1]]
                let det = (1.0 + a[1]) * 1.0 + a[2];
                let z0 = (b1 + b2) / det;
                let z1 = b2 - a[2] * z0;
                let out = [z0 * scale, z1 * scale];
                scale *= (b[0] + b[1] + b[2]) / (a[0] + a[1] + a[2]);
                out
            })
            .collect()
    }

    /// Direct-form-II-transposed cascade, in place, from initial conditions `zi`.
    fn filter_in_place(&self, x: &mut [f64], zi: &mut [[f64; 2]]) {
        for (s, z) in self.0.iter().zip(zi.iter_mut()) {
            let [b0, b1, b2, _, a1, a2] = *s;
            for v in x.iter_mut() {
                let xi = *v;
                let y = b0 * xi + z[0];
                z[0] = b1 * xi - a1 * y + z[1];
                z[1] = b2 * xi - a2 * y;
                *v = y;
            }
        }
    }

    /// Zero-phase filtering, as `scipy.signal.sosfiltfilt(sos, x)` with its default padding.
    /// Signals too short for the padding are padded as much as they allow.
    pub fn filtfilt(&self, x: &[f64]) -> Vec<f64> {
        if x.is_empty() {
            return vec![];
        }
        let nsec = self.0.len();
        let zeros_b2 = self.0.iter().filter(|s| s[2] == 0.0).count();
        let zeros_a2 = self.0.iter().filter(|s| s[5] == 0.0).count();
        let ntaps = 2 * nsec + 1 - zeros_b2.min(zeros_a2);
        let padlen = (3 * ntaps).min(x.len() - 1);
        let n = x.len();
        let mut ext = Vec::with_capacity(n + 2 * padlen);
        for i in (1..=padlen).rev() {
            ext.push(2.0 * x[0] - x[i]);
        }
        ext.extend_from_slice(x);
        for i in 1..=padlen {
            ext.push(2.0 * x[n - 1] - x[n - 1 - i]);
        }
        let zi = self.zi();
        let x0 = ext[0];
        let mut z: Vec<[f64; 2]> = zi.iter().map(|z| [z[0] * x0, z[1] * x0]).collect();
        self.filter_in_place(&mut ext, &mut z);
        ext.reverse();
        let y0 = ext[0];
        let mut z: Vec<[f64; 2]> = zi.iter().map(|z| [z[0] * y0, z[1] * y0]).collect();
        self.filter_in_place(&mut ext, &mut z);
        ext.reverse();
        ext[padlen..padlen + n].to_vec()
    }
}

/// Low-pass filter `x` (sampled at `fs`) with zero phase at `fc` Hz, order [`STATS_ORDER`].
pub fn lowpass_zero_phase(x: &[f64], fs: f64, fc: f64) -> Vec<f64> {
    butter(STATS_ORDER, Band::Lowpass(fc), fs).filtfilt(x)
}

/// Band-pass filter `x` with zero phase between `f1` and `f2` Hz, order [`STATS_ORDER`].
pub fn bandpass_zero_phase(x: &[f64], fs: f64, f1: f64, f2: f64) -> Vec<f64> {
    butter(STATS_ORDER, Band::Bandpass(f1, f2), fs).filtfilt(x)
}
