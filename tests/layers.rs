//! The layers lib.rs promises: `geometry` and `math` are plain functions over shapes,
//! poses and numbers, and import neither the data layer (`world`) nor the stages, so
//! they can be read and tested without the step. This reads their sources and fails on
//! an import that breaks that.

use std::path::Path;

fn sources(dir: &Path, out: &mut Vec<(String, String)>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            sources(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            let text = std::fs::read_to_string(&path).unwrap();
            out.push((path.display().to_string(), text));
        }
    }
}

#[test]
fn geometry_and_math_import_neither_the_data_layer_nor_the_stages() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    for layer in ["geometry", "math"] {
        sources(&root.join(layer), &mut files);
    }
    assert!(files.len() > 10, "found the layers' sources");
    let forbidden = ["crate::world", "crate::step", "crate::PhysicsWorld"];
    let mut broken = Vec::new();
    for (path, text) in &files {
        for (n, line) in text.lines().enumerate() {
            if forbidden.iter().any(|f| line.contains(f)) {
                broken.push(format!("{path}:{}: {}", n + 1, line.trim()));
            }
        }
    }
    assert!(broken.is_empty(), "layer imports:\n{}", broken.join("\n"));
}
