//! The layer rule of `src/lib.rs` (`canctl::LAYERS`), checked on the source: every
//! `crate::` path in library code must name a module in a lower layer (or the module itself).
//! Test modules are exempt: they may build a simulator to drive the code under test.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

/// Imports that still go the wrong way, as `from -> to` between layer units. Empty it, do not
/// grow it: a new entry is a cycle in the making.
const ALLOWED: &[&str] = &[];

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// `src/bus/master.rs` -> `bus::master`; `src/bus/mod.rs` -> `bus`.
fn module_path(src: &Path, file: &Path) -> String {
    let rel = file.strip_prefix(src).unwrap().with_extension("");
    let parts: Vec<_> = rel.iter().map(|p| p.to_str().unwrap()).filter(|p| *p != "mod").collect();
    parts.join("::")
}

/// The layer unit a module path belongs to (the longest entry of `LAYERS` it starts with)
/// and that unit's layer, 0 being the top.
fn unit_of(path: &str) -> Option<(&'static str, usize)> {
    let mut best: Option<(&'static str, usize)> = None;
    for (depth, layer) in canctl::LAYERS.iter().enumerate() {
        for unit in *layer {
            let matches = path == *unit || path.starts_with(&format!("{unit}::"));
            if matches && best.is_none_or(|(b, _)| unit.len() > b.len()) {
                best = Some((unit, depth));
            }
        }
    }
    best
}

/// Library code of a file: comments dropped, and everything from a `#[cfg(test)]` module on.
fn library_code(text: &str) -> String {
    let mut out = String::new();
    let mut lines = text.lines().peekable();
    while let Some(line) = lines.next() {
        let trimmed = line.trim_start();
        if trimmed.starts_with("#[cfg(test)]") {
            let next = lines.peek().map(|l| l.trim_start()).unwrap_or("");
            if next.starts_with("mod ") || next.starts_with("pub(crate) mod ") {
                // Skip the test module: to the end of its braces, or its line if declared.
                let decl = lines.next().unwrap();
                if decl.contains('{') {
                    let mut depth = decl.matches('{').count() as i32 - decl.matches('}').count() as i32;
                    while depth > 0 {
                        let Some(l) = lines.next() else { break };
                        depth += l.matches('{').count() as i32 - l.matches('}').count() as i32;
                    }
                }
                continue;
            }
        }
        if trimmed.starts_with("//") {
            continue;
        }
        out.push_str(line);
        out.push('\n');
    }
    out
}

/// Every module path named after `crate::`, including each branch of `use crate::{a, b::c}`.
fn crate_paths(code: &str) -> BTreeSet<String> {
    let mut found = BTreeSet::new();
    let mut rest = code;
    while let Some(at) = rest.find("crate::") {
        let before = rest[..at].chars().last();
        rest = &rest[at + "crate::".len()..];
        if before.is_some_and(|c| c.is_alphanumeric() || c == '_' || c == '$') {
            continue; // `$crate::` or part of another name
        }
        if rest.starts_with('{') {
            // Top-level names of the group: split at depth-1 commas.
            let mut depth = 0;
            let mut name = String::new();
            for c in rest.chars() {
                match c {
                    '{' => depth += 1,
                    '}' => depth -= 1,
                    ',' if depth == 1 => {
                        found.insert(std::mem::take(&mut name));
                        continue;
                    }
                    _ => {}
                }
                if depth == 0 {
                    break;
                }
                if depth == 1 && (c.is_alphanumeric() || c == '_' || c == ':') {
                    name.push(c);
                }
            }
            found.insert(name);
        } else {
            let path: String = rest.chars().take_while(|c| c.is_alphanumeric() || *c == '_' || *c == ':').collect();
            found.insert(path);
        }
    }
    found
        .into_iter()
        .map(|p| p.trim().trim_end_matches("::").split("::{").next().unwrap().trim().to_string())
        .filter(|p| !p.is_empty() && p != "self")
        .collect()
}

#[test]
fn imports_only_go_down_the_layers() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let src = root.join("src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    files.sort();
    let mut wrong = BTreeSet::new();
    let mut unplaced = BTreeSet::new();
    for file in &files {
        let module = module_path(&src, file);
        if module == "lib" || module == "main" || module.ends_with("tests") {
            continue;
        }
        let Some((from, from_depth)) = unit_of(&module) else {
            unplaced.insert(module);
            continue;
        };
        let text = std::fs::read_to_string(file).unwrap();
        for path in crate_paths(&library_code(&text)) {
            // Re-exports of the crate root (`crate::Error`) are `error`'s.
            let path = match path.split("::").next().unwrap() {
                "Error" | "Result" => "error".to_string(),
                _ => path,
            };
            let Some((to, to_depth)) = unit_of(&path) else {
                unplaced.insert(path);
                continue;
            };
            if to != from && to_depth <= from_depth {
                wrong.insert(format!("{from} -> {to}"));
            }
        }
    }
    assert!(unplaced.is_empty(), "modules that lib.rs's LAYERS does not place: {unplaced:?}");
    let unexpected: Vec<_> = wrong.iter().filter(|w| !ALLOWED.contains(&w.as_str())).collect();
    assert!(unexpected.is_empty(), "imports that go up or sideways in lib.rs's LAYERS: {unexpected:?}");
    let fixed: Vec<_> = ALLOWED.iter().filter(|a| !wrong.contains(**a)).collect();
    assert!(fixed.is_empty(), "fixed, remove from ALLOWED: {fixed:?}");
}

#[test]
fn the_parser_sees_grouped_and_inline_paths() {
    let code = "use crate::{bus::{Bus, FrameLink}, error::Error};\nlet x = crate::sim::wall_ms();\n// crate::cli\n";
    let paths = crate_paths(&library_code(code));
    assert_eq!(paths.into_iter().collect::<Vec<_>>(), ["bus", "error::Error", "sim::wall_ms"]);
    let test_mod = "fn f() {}\n#[cfg(test)]\nmod tests {\n    use crate::sim::SimLink;\n}\nuse crate::od;\n";
    assert_eq!(crate_paths(&library_code(test_mod)).into_iter().collect::<Vec<_>>(), ["od"]);
}
