//! The two instruction sets of the hot loops (portable, and x86-64-v3 with fused multiply-add
//! where the CPU has it) give the same statistics within 1e-6 relative on the zoo and the
//! presets (docs/performance.md states the bound; `PCSIM_PORTABLE=1` forces the portable path).
//! `benchmark-55m` is left out: it is chaotic (docs/validation.md), so any change of rounding
//! moves its statistics by up to 1e-2.

use pcsim_core::compile::Setup;
use pcsim_core::solve::Isa;
use pcsim_core::{presets, simulate, zoo};

fn stats_agree(name: &str, setup: &Setup) {
    let best = Isa::best_available();
    let run = |isa: Isa| {
        let mut s = setup.clone();
        s.options.isa = isa;
        simulate(&s, &mut |_| true).unwrap()
    };
    let (a, b) = (run(Isa::Portable), run(best));
    for (pa, pb) in a.pantographs.iter().zip(&b.pantographs) {
        let (sa, sb) = (pa.stats.unwrap(), pb.stats.unwrap());
        for (x, y, what) in [
            (sa.mean_n, sb.mean_n, "mean"),
            (sa.std_n, sb.std_n, "σ"),
            (sa.actual_max_n, sb.actual_max_n, "max"),
            (sa.actual_min_n, sb.actual_min_n, "min"),
            (
                sa.max_uplift_at_support_mm,
                sb.max_uplift_at_support_mm,
                "uplift",
            ),
        ] {
            assert!(
                (x - y).abs() <= 1e-6 * x.abs().max(1e-9),
                "{name}, {}: {what} {x} (portable) vs {y} ({})",
                pa.name,
                best.name()
            );
        }
    }
}

#[test]
fn the_instruction_sets_agree_on_the_zoo() {
    for name in zoo::NAMES {
        stats_agree(name, &zoo::model(name).unwrap());
    }
}

#[test]
fn the_instruction_sets_agree_on_the_presets() {
    let cases: Vec<_> = [
        ("en50318-2002", 250.0),
        ("en50318-2002", 300.0),
        ("stitched-2018-like", 320.0),
        ("syt-7.0-9.8", 222.0),
    ]
    .into_iter()
    .map(|(p, v)| {
        let (mut c, _) = presets::load(p).unwrap();
        c.run.speed_kmh = v;
        (format!("{p} at {v}"), Setup::from_case(&c).unwrap())
    })
    .collect();
    std::thread::scope(|s| {
        for (name, setup) in &cases {
            s.spawn(move || stats_agree(name, setup));
        }
    });
}
