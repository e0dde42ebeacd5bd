//! Tidy checks on the source tree (rust-analyzer's xtask/tidy idea): module
//! docs everywhere, and the layering the codemap in src/lib.rs promises.

use crate::util::root;

fn rust_files(dir: &std::path::Path, out: &mut Vec<std::path::PathBuf>) {
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

pub fn every_module_starts_with_a_doc_comment() {
    let mut files = Vec::new();
    rust_files(&root().join("src"), &mut files);
    for f in files {
        let text = std::fs::read_to_string(&f).unwrap();
        let is_tests = f.file_name().is_some_and(|n| n == "tests.rs");
        assert!(is_tests || text.starts_with("//!"), "{} has no //! module doc", f.display());
    }
}

pub fn layering_holds() {
    // (directory, modules of the crate it must not use)
    let rules: &[(&str, &[&str])] = &[
        (
            "src/interp",
            &["crate::scene", "crate::render", "crate::image", "crate::geometry", "crate::shell"],
        ),
        ("src/geometry", &["crate::interp", "crate::scene", "crate::render", "crate::shell"]),
        ("src/scene", &["crate::interp", "crate::render", "crate::shell"]),
        ("src/render", &["crate::interp", "crate::shell"]),
        ("src/image", &["crate::interp", "crate::scene", "crate::shell"]),
    ];
    for (dir, banned) in rules {
        let mut files = Vec::new();
        rust_files(&root().join(dir), &mut files);
        for f in files.iter().filter(|f| !f.ends_with("tests.rs")) {
            let text = std::fs::read_to_string(f).unwrap();
            for b in *banned {
                assert!(!text.contains(b), "{} uses {b}", f.display());
            }
        }
    }
}

/// Every `pub fn NAME()` in a test module is listed in `main.rs`'s
/// `tests!`, so no test is silently left out of the run.
pub fn every_test_is_registered() {
    let dir = crate::util::root().join("tests/it");
    let main = std::fs::read_to_string(dir.join("main.rs")).unwrap();
    let mut missing = Vec::new();
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        let module = path.file_stem().unwrap().to_string_lossy().into_owned();
        if module == "main" || module == "util" {
            continue;
        }
        let src = std::fs::read_to_string(&path).unwrap();
        for line in src.lines() {
            if let Some(rest) = line.strip_prefix("pub fn ")
                && let Some(name) = rest.strip_suffix("() {")
            {
                let entry = format!("        {module}::{name},");
                if !main.contains(&entry) {
                    missing.push(format!("{module}::{name}"));
                }
            }
        }
    }
    assert!(missing.is_empty(), "not in tests/it/main.rs: {missing:?}");
}
