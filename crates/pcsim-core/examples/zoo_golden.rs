//! Write the golden time histories of the zoo models (`pcsim_core::zoo::trace`) as CSV.
//!
//! ```sh
//! cargo run --release -p pcsim-core --example zoo_golden -- data/golden/zoo
//! ```
//!
//! Values are written with 17 significant digits, so they read back bit for bit. The goldens
//! were made before the core restructure (issue 9) and guard it: `tests/suite/zoo.rs` compares every
//! value with them.

use std::fmt::Write as _;

fn main() {
    let dir = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "data/golden/zoo".into());
    std::fs::create_dir_all(&dir).expect("create the output directory");
    for name in pcsim_core::zoo::NAMES {
        let t = pcsim_core::zoo::trace(name).expect("zoo model");
        let mut s = t.columns.join(",");
        s.push('\n');
        for r in &t.rows {
            let cells: Vec<String> = r.iter().map(|v| format!("{v:.16e}")).collect();
            let _ = writeln!(s, "{}", cells.join(","));
        }
        let path = format!("{dir}/{name}.csv");
        std::fs::write(&path, s).expect("write the golden file");
        println!("{path}: {} rows", t.rows.len());
    }
}
