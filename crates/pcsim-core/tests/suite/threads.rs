//! One run on several threads (issue 23, item 4): the same output, bit for bit, with 1, 2 and 3
//! threads, on a line of ten tension lengths (where the run splits), and on models of one basis
//! group (a span-periodic preset, a line of one tension length), which stay on one thread.

use pcsim_core::analysis::record::{simulate, RunOutput};
use pcsim_core::compile::Setup;
use pcsim_core::{presets, Case};

/// A preset cut to `spans_travelled` spans of travel from its start (the analysis section one
/// span after the start, to the end).
fn short(preset: &str, spans_travelled: f64) -> Case {
    let (mut c, _) = presets::load(preset).unwrap();
    let s = c.catenary.span_m;
    c.run.end_m = c.run.start_m + spans_travelled * s;
    c.run.analysis_m = [c.run.start_m + s + 1.0, c.run.end_m];
    c
}

fn run(case: &Case, threads: usize) -> (RunOutput, usize) {
    let mut setup = Setup::from_case(case).unwrap();
    setup.options.threads = threads;
    let parts = setup.integrator().unwrap().threads();
    let mut out = simulate(&setup, &mut |_| true).unwrap();
    assert_eq!(out.threads, parts);
    out.threads = 0;
    (out, parts)
}

/// Every value printed in full (`Debug` of an `f64` is its shortest exact decimal, and tells
/// −0 from +0): equal strings are equal bits.
fn bits(o: &RunOutput) -> String {
    format!("{o:?}")
}

#[test]
fn a_line_gives_the_same_bytes_on_one_two_and_three_threads() {
    for preset in ["line-10km-2002"] {
        let case = short(preset, 3.0);
        let (one, p1) = run(&case, 1);
        assert_eq!(p1, 1);
        for threads in [2, 3] {
            let (many, parts) = run(&case, threads);
            assert_eq!(
                parts, threads,
                "{preset}: a line of several tension lengths splits into {threads} parts"
            );
            assert!(one.time_s.len() > 100);
            assert_eq!(
                bits(&one),
                bits(&many),
                "{preset}: {threads} threads changed the output"
            );
        }
    }
}

#[test]
fn a_model_of_one_basis_group_stays_on_one_thread_with_the_same_bytes() {
    for preset in ["stitched-2018-like", "line-structure-2002"] {
        let case = short(preset, 1.5);
        let (one, _) = run(&case, 1);
        let (two, parts) = run(&case, 2);
        assert_eq!(parts, 1, "{preset}: one basis group, nothing to split");
        assert_eq!(bits(&one), bits(&two));
    }
}

/// Issue 39, item 9: `--threads N` on a machine whose cores are busy. The team's threads spin
/// between the stages of a step, so a thread without an idle core stalls every stage: the rule
/// takes the threads the idle cores can carry (within half a core), and says why; on idle cores,
/// or for one thread, it changes nothing.
#[test]
fn issue_39_9_threads_fall_back_to_the_idle_cores_and_say_why() {
    use pcsim_core::solve::team::{idle_cores, threads_for_idle};
    assert_eq!(threads_for_idle(2, Some(1.9)), (2, None));
    assert_eq!(threads_for_idle(2, Some(1.6)), (2, None));
    let (n, why) = threads_for_idle(2, Some(0.9));
    assert_eq!(n, 1);
    assert!(why
        .unwrap()
        .contains("0.9 of this machine's cores were idle"));
    assert_eq!(threads_for_idle(4, Some(2.2)).0, 2);
    assert_eq!(threads_for_idle(4, Some(0.1)).0, 1, "never fewer than one");
    assert_eq!(threads_for_idle(1, Some(0.0)), (1, None));
    assert_eq!(threads_for_idle(3, None), (3, None), "unknown: as asked");
    // The measurement itself: a fraction of the cores this process may use.
    if let Some(idle) = idle_cores(std::time::Duration::from_millis(50)) {
        let cores = std::thread::available_parallelism().unwrap().get() as f64;
        assert!((0.0..=cores).contains(&idle), "{idle} of {cores}");
    }
}
