//! The step's cost against the model's length (issue 23, "cost against length"): the
//! `en50318-2002` catenary over `spans` spans with 40 modes per span (the benchmark's
//! resolution), two pantographs 200 m apart at 320 km/h, stepped `steps` times. Run under
//! callgrind and divide `Integrator::step`'s inclusive count by the steps:
//!
//! ```sh
//! cargo build --release -p pcsim-core --example length_cost
//! valgrind --tool=callgrind --callgrind-out-file=/tmp/cg30 target/release/examples/length_cost 30 2000
//! callgrind_annotate --inclusive=yes /tmp/cg30 | grep 'Integrator::step \['     # ÷ 2000
//! ```
//!
//! It prints the leading contact force at the end, so that two builds can be checked to step
//! the same model.

use pcsim_core::compile::Setup;
use pcsim_core::presets;

fn main() {
    let mut args = std::env::args().skip(1);
    let spans: usize = args.next().map_or(30, |s| s.parse().expect("spans"));
    let steps: usize = args.next().map_or(2000, |s| s.parse().expect("steps"));
    let c = presets::benchmark_case(320.0, 40 * spans, spans).expect("the benchmark case");
    let setup = Setup::from_case(&c).expect("the benchmark case");
    let integ = setup.integrator().expect("its integrator");
    let mut st = integ.initial_state(setup.plan.start_m);
    let mut ws = integ.workspace();
    for _ in 0..steps {
        integ.step(&mut st, &mut ws);
    }
    println!(
        "{spans} spans, {} modes per wire, {steps} steps: leading force {:.9} N",
        40 * spans,
        ws.samples()[0].force_n
    );
}
