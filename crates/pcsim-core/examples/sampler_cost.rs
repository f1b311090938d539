//! Issue 21, item 4: what a gather and a scatter cost on points that repeat every span (the
//! folded path), on the same number of points over spans of different lengths (the
//! non-uniform transform), and by dense rows. Runs `ROUNDS` gathers and scatters of two blocks
//! (the vertical series of messenger and contact wire) on the path named by the first argument;
//! count instructions with callgrind and divide by `ROUNDS`:
//!
//! ```sh
//! cargo build --release -p pcsim-core --example sampler_cost
//! for p in folded spread dense; do
//!   valgrind --tool=callgrind --callgrind-out-file=/tmp/cg.$p target/release/examples/sampler_cost $p 2>&1 | grep refs
//! done
//! ```

use pcsim_core::model::basis::SineBasis;
use pcsim_core::solve::kernels::{self, Isa};
use pcsim_core::solve::sampler::PointSampler;
use std::hint::black_box;

fn main() {
    let path = std::env::args().nth(1).unwrap_or_else(|| "folded".into());
    let rounds: usize = std::env::args()
        .nth(2)
        .and_then(|r| r.parse().ok())
        .unwrap_or(1000);
    // 40 modes per span, 9 droppers per span on each wire (the stitched preset's layout), two
    // blocks.
    let spans: usize = std::env::args()
        .nth(3)
        .and_then(|r| r.parse().ok())
        .unwrap_or(30);
    let n = 40 * spans;
    let offsets = [2.5, 9.0, 16.0, 23.0, 30.0, 37.0, 44.0, 51.0, 57.5];
    // Uniform: 60 m spans. Non-uniform: spans of 52–68 m, the same total, the dropper layout
    // scaled to each span.
    let lengths: Vec<f64> = if path == "folded" {
        vec![60.0; spans]
    } else {
        (0..spans)
            .map(|s| 60.0 + 8.0 * (((s * 7) % 5) as f64 - 2.0) / 2.0)
            .collect()
    };
    let total: f64 = lengths.iter().sum();
    let scale = 60.0 * spans as f64 / total;
    let mut xs = Vec::new();
    let mut x0 = 0.0;
    for &len in &lengths {
        let len = len * scale;
        for d in offsets {
            xs.push(x0 + d * len / 60.0);
        }
        x0 += len;
    }
    let basis = SineBasis::new(60.0 * spans as f64, n);
    let isa = Isa::best_available();
    let q: Vec<f64> = (0..2 * n).map(|k| 1e-3 / (1.0 + k as f64)).collect();
    let f: Vec<f64> = (0..2 * xs.len()).map(|i| (i % 7) as f64).collect();
    let mut u = vec![0.0; 2 * xs.len()];
    let mut a = vec![0.0; 2 * n];
    if path == "dense" {
        let np = xs.len();
        let mut rows = vec![0.0; np * n];
        for (r, &x) in rows.chunks_exact_mut(n).zip(&xs) {
            basis.fill_sines(x, r);
        }
        for _ in 0..rounds {
            for (j, r) in rows.chunks_exact(n).enumerate() {
                let (g1, g2) = kernels::dot2(isa, r, &q[..n], &q[n..]);
                u[j] = g1;
                u[np + j] = g2;
            }
            let (a1, a2) = a.split_at_mut(n);
            kernels::axpy2_rows(isa, &rows, &f[..np], &f[np..], a1, a2);
            black_box(&u);
        }
    } else {
        let span = (path == "folded").then_some(60.0);
        let p = PointSampler::new(&basis, &xs, span, isa);
        assert_eq!(p.n_spread() > 0, path == "spread");
        let mut sc = p.scratch();
        for _ in 0..rounds {
            p.gather(black_box(&q), 2, &mut u, &mut sc);
            p.scatter_add(black_box(&f), 2, &mut a, &mut sc);
        }
    }
    println!(
        "{path}: {} points, {n} modes, two blocks, {rounds} rounds; u[7] = {:.6e}, a[3] = {:.6e}",
        xs.len(),
        u[7],
        a[3]
    );
}
