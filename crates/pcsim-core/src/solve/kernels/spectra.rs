//! The periodic sampler's spectra: its pack and unpack of the bins in four lanes.

use super::*;

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
