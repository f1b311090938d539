//! Progress bar on stderr, only when it is a terminal and not `--quiet`.

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;

/// A bar of `len` units drawn with `template` (hidden when stderr is not a terminal or `quiet`).
pub fn styled(len: u64, template: &str, quiet: bool) -> ProgressBar {
    let pb = ProgressBar::new(len);
    if quiet || !std::io::stderr().is_terminal() {
        pb.set_draw_target(ProgressDrawTarget::hidden());
    }
    pb.set_style(
        ProgressStyle::with_template(template)
            .unwrap_or_else(|_| ProgressStyle::default_bar())
            .progress_chars("=> "),
    );
    pb
}

/// A run's progress bar in per-mille (hidden when stderr is not a terminal or `quiet`).
pub fn bar(label: &str, quiet: bool) -> ProgressBar {
    let pb = styled(
        1000,
        "{prefix:>14} [{bar:40}] {percent:>3}% {elapsed_precise} eta {eta}",
        quiet,
    );
    pb.set_prefix(label.to_string());
    pb
}
