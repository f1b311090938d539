//! The core's layers import downward only: `input` ← `model` ← `solve` ← `analysis` (and the
//! bottom helpers `error` and `linalg` from anywhere). A `use crate::solve` inside `model/`, say,
//! fails here.

use std::path::Path;

const LAYERS: &[&str] = &["input", "model", "solve", "analysis"];

fn sources(dir: &Path, out: &mut Vec<std::path::PathBuf>) {
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            sources(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

#[test]
fn imports_point_downward_only() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut checked = 0;
    for (rank, layer) in LAYERS.iter().enumerate() {
        let mut files = Vec::new();
        sources(&src.join(layer), &mut files);
        assert!(!files.is_empty(), "{layer}/ has no sources");
        for f in files {
            let text = std::fs::read_to_string(&f).unwrap();
            for upper in &LAYERS[rank + 1..] {
                for pat in [format!("crate::{upper}"), format!("super::super::{upper}")] {
                    assert!(
                        !text.contains(&pat),
                        "{} (layer `{layer}`) refers to the layer above it: `{pat}`",
                        f.display()
                    );
                }
            }
            checked += 1;
        }
    }
    assert!(checked > 20, "only {checked} files checked");
}
