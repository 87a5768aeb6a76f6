//! The layer rule of each crate's `lib.rs` (`canctl::LAYERS` over
//! `canctl_commission::LAYERS`, `canctl_bus::LAYERS`), checked on the source: every
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

/// The layer unit a module path belongs to (the longest entry of `layers` it starts with)
/// and that unit's layer, 0 being the top.
fn unit_of(layers: &[&'static [&'static str]], path: &str) -> Option<(&'static str, usize)> {
    let mut best: Option<(&'static str, usize)> = None;
    for (depth, layer) in layers.iter().enumerate() {
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
    paths_after(code, "crate::")
}

/// Every path named after `start` (`crate::`, `super::`, `self::`), as [`crate_paths`].
fn paths_after(code: &str, start: &str) -> BTreeSet<String> {
    let mut found = BTreeSet::new();
    let mut rest = code;
    while let Some(at) = rest.find(start) {
        let before = rest[..at].chars().last();
        rest = &rest[at + start.len()..];
        if before.is_some_and(|c| c.is_alphanumeric() || c == '_' || c == '$') {
            continue; // `$crate::`, `super::super::` or part of another name
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
            // A glob (`use super::*`) names the module it takes everything from.
            let path: String =
                rest.chars().take_while(|c| c.is_alphanumeric() || *c == '_' || *c == ':' || *c == '*').collect();
            found.insert(path);
        }
    }
    found
        .into_iter()
        .map(|p| p.trim().trim_end_matches("::").split("::{").next().unwrap().trim().to_string())
        .filter(|p| !p.is_empty() && p != "self")
        .collect()
}

/// Where the library's sources are: `src/` and each crate of `crates/`, with the prefix a
/// file's path is said with (`src/`, `crates/od/src/`).
fn source_dirs() -> Vec<(PathBuf, String)> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut dirs = vec![(root.join("src"), "src/".to_string())];
    let mut crates: Vec<_> = std::fs::read_dir(root.join("crates")).unwrap().map(|e| e.unwrap().path()).collect();
    crates.sort();
    for dir in crates {
        let name = dir.file_name().unwrap().to_str().unwrap().to_string();
        dirs.push((dir.join("src"), format!("crates/{name}/src/")));
    }
    dirs
}

/// The crates under the command line use only the ones below them: the protocol none, the
/// dictionaries the protocol, the bus both, the simulator all three, the commissioning
/// library all four. Cargo forbids a cycle; this holds the order.
#[test]
fn the_crates_are_the_layers_below_the_library() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let uses = |krate: &str| -> Vec<String> {
        let manifest = std::fs::read_to_string(root.join("crates").join(krate).join("Cargo.toml")).unwrap();
        let mut names: Vec<String> = manifest
            .lines()
            .filter_map(|l| l.split(['.', ' ', '=']).next())
            .filter(|name| name.starts_with("canctl"))
            .map(str::to_string)
            .collect();
        names.retain(|n| n != &format!("canctl-{krate}"));
        names.sort();
        names.dedup();
        names
    };
    assert_eq!(uses("canopen"), Vec::<String>::new());
    assert_eq!(uses("od"), ["canctl-canopen"]);
    assert_eq!(uses("bus"), ["canctl-canopen", "canctl-od"]);
    assert_eq!(uses("sim"), ["canctl-bus", "canctl-canopen", "canctl-od"]);
    assert_eq!(uses("commission"), ["canctl-bus", "canctl-canopen", "canctl-od", "canctl-sim"]);
    let crates: Vec<_> = source_dirs().into_iter().skip(1).map(|(_, prefix)| prefix).collect();
    let expected =
        ["crates/bus/src/", "crates/canopen/src/", "crates/commission/src/", "crates/od/src/", "crates/sim/src/"];
    assert_eq!(crates, expected, "a new crate: place it here");
}

/// The command line's modules (`canctl::LAYERS`, over the library's it re-exports), the
/// library's (`canctl_commission::LAYERS`) and those of the bus crate (`canctl_bus::LAYERS`).
#[test]
fn imports_only_go_down_the_layers() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let front_end: Vec<_> = canctl::LAYERS.iter().chain(canctl_commission::LAYERS).copied().collect();
    check_layers(&root.join("src"), &front_end);
    check_layers(&root.join("crates/commission/src"), canctl_commission::LAYERS);
    check_layers(&root.join("crates/bus/src"), canctl_bus::LAYERS);
}

fn check_layers(src: &Path, layers: &[&'static [&'static str]]) {
    let mut files = Vec::new();
    rust_files(src, &mut files);
    files.sort();
    let mut wrong = BTreeSet::new();
    let mut unplaced = BTreeSet::new();
    for file in &files {
        let module = module_path(src, file);
        if module == "lib" || module == "main" || module.ends_with("tests") || module.contains("::tests::") {
            continue;
        }
        let Some((from, from_depth)) = unit_of(layers, &module) else {
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
            let Some((to, to_depth)) = unit_of(layers, &path) else {
                unplaced.insert(path);
                continue;
            };
            if to != from && to_depth <= from_depth {
                wrong.insert(format!("{from} -> {to}"));
            }
        }
    }
    assert!(unplaced.is_empty(), "modules that {} LAYERS does not place: {unplaced:?}", src.display());
    let unexpected: Vec<_> = wrong.iter().filter(|w| !ALLOWED.contains(&w.as_str())).collect();
    assert!(unexpected.is_empty(), "imports that go up or sideways in lib.rs's LAYERS: {unexpected:?}");
    let fixed: Vec<_> = ALLOWED.iter().filter(|a| !wrong.contains(**a)).collect();
    assert!(fixed.is_empty(), "fixed, remove from ALLOWED: {fixed:?}");
}

/// The files of each crate import one another without a cycle (issue 40): two files that
/// need each other are one concept cut in two, or a type in the wrong room. A module and its
/// own submodules are one room (a parent declares its children and re-exports them), so
/// their imports of each other are not counted here (see the next test); `super::super::`
/// is not followed.
#[test]
fn no_two_files_of_a_crate_import_each_other() {
    let mut cycles = Vec::new();
    for (src, prefix) in source_dirs() {
        for cycle in cycles_of(&file_graph(&src, false)) {
            cycles.push(format!("{prefix}: {}", cycle.join(" -> ")));
        }
    }
    assert!(cycles.is_empty(), "files that import each other, directly or around a circle:\n{}", cycles.join("\n"));
}

/// Parents whose files and their children's still import each other: each uses what a child
/// defines (a re-export, a call, a type in its own signatures) and is used by a child. Empty
/// it, do not grow it.
const FAMILY_CYCLES: &[&str] = &[];

/// A module and its own submodules import each other only in the parents listed in
/// [`FAMILY_CYCLES`]: a parent either uses its children or is used by them (issue 40).
#[test]
fn a_parent_and_its_children_import_each_other_only_where_listed() {
    let mut found = BTreeSet::new();
    for (src, prefix) in source_dirs() {
        for cycle in cycles_of(&file_graph(&src, true)) {
            let top = cycle.iter().min_by_key(|m| m.matches("::").count()).expect("a cycle has files");
            found.insert(format!("{prefix}{}", top.replace("::", "/")).trim_end_matches('/').to_string());
        }
    }
    let listed: BTreeSet<String> = FAMILY_CYCLES.iter().map(|s| s.to_string()).collect();
    let new: Vec<_> = found.difference(&listed).collect();
    assert!(new.is_empty(), "a parent and its children that import each other, not listed: {new:?}");
    let fixed: Vec<_> = listed.difference(&found).collect();
    assert!(fixed.is_empty(), "fixed, remove from FAMILY_CYCLES: {fixed:?}");
}

/// Which files of the crate at `src` import which (by module path, tests left out): through
/// `crate::`, `super::` and `self::` paths, and with `family` also between a module and its
/// own submodules, a parent naming a child by its bare name (`probe::run`) included.
fn file_graph(src: &Path, family: bool) -> std::collections::BTreeMap<String, BTreeSet<String>> {
    let mut files = Vec::new();
    rust_files(src, &mut files);
    let modules: BTreeSet<String> = files.iter().map(|f| module_path(src, f)).collect();
    let mut edges: std::collections::BTreeMap<String, BTreeSet<String>> = Default::default();
    for file in &files {
        let module = module_path(src, file);
        if module.ends_with("tests") || module.contains("::tests::") {
            continue;
        }
        // The module's own path (`lib`, `main` and `mod` are the folder's), and where a
        // `super::` or `self::` starts from.
        let own: Vec<&str> = module.split("::").filter(|p| !["lib", "main"].contains(p)).collect();
        let code = library_code(&std::fs::read_to_string(file).unwrap());
        let mut named: Vec<Vec<String>> = Vec::new();
        let (root, parent) = (&own[..0], &own[..own.len().saturating_sub(1)]);
        for (start, base) in [("crate::", root), ("super::", parent), ("self::", &own[..])] {
            for path in paths_after(&code, start) {
                named.push(base.iter().map(|p| p.to_string()).chain(path.split("::").map(String::from)).collect());
            }
        }
        let own = own.join("::");
        if family {
            let prefix = if own.is_empty() { String::new() } else { format!("{own}::") };
            let children = modules.iter().filter_map(|m| m.strip_prefix(&prefix)).filter(|c| !c.contains("::"));
            for child in children.filter(|c| !c.is_empty() && !["lib", "main"].contains(c)) {
                if names_bare(&code, child) {
                    named.push(vec![format!("{prefix}{child}")]);
                }
            }
        }
        for mut path in named {
            // The file the path is in: its longest prefix that is a module of its own.
            while !path.is_empty() && !modules.contains(&path.join("::")) {
                path.pop();
            }
            let to = path.join("::");
            let family_of = to.starts_with(&format!("{own}::")) || own.starts_with(&format!("{to}::"));
            if !(to.is_empty() || to == own || (family_of && !family)) {
                edges.entry(own.clone()).or_default().insert(to);
            }
        }
    }
    edges
}

/// Whether `code` names the module `name` by its bare name (`probe::run`, `use probe::X`),
/// not as the end of a longer path (`crate::bus::probe::`).
fn names_bare(code: &str, name: &str) -> bool {
    let needle = format!("{name}::");
    code.match_indices(&needle).any(|(at, _)| {
        !code[..at].chars().last().is_some_and(|c| c.is_alphanumeric() || c == '_' || c == ':' || c == '$')
    })
}

/// The circles of a graph: one path around each strongly connected part of more than one
/// node (Tarjan's algorithm, iterating in name order so the message is stable).
fn cycles_of(edges: &std::collections::BTreeMap<String, BTreeSet<String>>) -> Vec<Vec<String>> {
    struct Walk<'a> {
        edges: &'a std::collections::BTreeMap<String, BTreeSet<String>>,
        index: std::collections::BTreeMap<&'a str, (usize, usize)>,
        stack: Vec<&'a str>,
        found: Vec<Vec<String>>,
    }
    fn visit<'a>(w: &mut Walk<'a>, v: &'a str) {
        let n = w.index.len();
        w.index.insert(v, (n, n));
        w.stack.push(v);
        for to in w.edges.get(v).into_iter().flatten() {
            match w.index.get(to.as_str()) {
                None => {
                    visit(w, to);
                    let low = w.index[to.as_str()].1.min(w.index[v].1);
                    w.index.get_mut(v).unwrap().1 = low;
                }
                Some(&(at, _)) if w.stack.contains(&to.as_str()) => {
                    let low = at.min(w.index[v].1);
                    w.index.get_mut(v).unwrap().1 = low;
                }
                Some(_) => {}
            }
        }
        if w.index[v].0 == w.index[v].1 {
            let at = w.stack.iter().position(|s| *s == v).unwrap();
            let part: Vec<String> = w.stack.drain(at..).map(String::from).collect();
            if part.len() > 1 {
                w.found.push(part);
            }
        }
    }
    let mut w = Walk { edges, index: Default::default(), stack: Vec::new(), found: Vec::new() };
    for v in edges.keys() {
        if !w.index.contains_key(v.as_str()) {
            visit(&mut w, v);
        }
    }
    w.found
}

#[test]
fn a_circle_of_files_is_found() {
    let edge = |a: &str, b: &[&str]| (a.to_string(), b.iter().map(|s| s.to_string()).collect::<BTreeSet<_>>());
    let graph = [edge("a", &["b"]), edge("b", &["c"]), edge("c", &["a"]), edge("d", &["a"])].into_iter().collect();
    let cycles = cycles_of(&graph);
    assert_eq!(cycles.len(), 1, "{cycles:?}");
    assert_eq!(
        cycles[0].iter().collect::<BTreeSet<_>>(),
        ["a", "b", "c"].iter().map(|s| s.to_string()).collect::<BTreeSet<_>>().iter().collect()
    );
    assert!(cycles_of(&[edge("a", &["b"]), edge("b", &[])].into_iter().collect()).is_empty());
}

#[test]
fn the_parser_sees_grouped_and_inline_paths() {
    let code = "use crate::{bus::{Bus, FrameLink}, error::Error};\nlet x = crate::sim::wall_ms();\n// crate::cli\n";
    let paths = crate_paths(&library_code(code));
    assert_eq!(paths.into_iter().collect::<Vec<_>>(), ["bus", "error::Error", "sim::wall_ms"]);
    let test_mod = "fn f() {}\n#[cfg(test)]\nmod tests {\n    use crate::sim::SimLink;\n}\nuse crate::od;\n";
    assert_eq!(crate_paths(&library_code(test_mod)).into_iter().collect::<Vec<_>>(), ["od"]);
    // A glob names the module it takes everything from: `use super::*` is an import of the
    // parent, as much as `use super::Master`.
    assert_eq!(paths_after("use super::*;\n", "super::").into_iter().collect::<Vec<_>>(), ["*"]);
}

/// The string literals of `code` (comments skipped), each with its line number; raw strings
/// and escapes are kept as written.
fn string_literals(code: &str) -> Vec<(usize, String)> {
    let chars: Vec<char> = code.chars().collect();
    let (mut found, mut line, mut i) = (Vec::new(), 1, 0);
    while i < chars.len() {
        match chars[i] {
            '\n' => line += 1,
            '/' if chars.get(i + 1) == Some(&'/') => {
                while i < chars.len() && chars[i] != '\n' {
                    i += 1;
                }
                continue;
            }
            // A char literal: `'"'` or `'\"'` opens no string.
            '\'' if chars.get(i + 1) == Some(&'"') || chars.get(i + 2) == Some(&'"') && chars[i + 1] == '\\' => {
                i += if chars[i + 1] == '"' { 3 } else { 4 };
                continue;
            }
            '"' => {
                // `r#"...."#`: the hashes before the quote close it too.
                let hashes = chars[..i].iter().rev().take_while(|c| **c == '#').count();
                let raw = i > hashes && chars[i - hashes - 1] == 'r';
                let (start, mut text) = (line, String::new());
                i += 1;
                while i < chars.len() {
                    let c = chars[i];
                    if c == '\\' && !raw {
                        text.push(c);
                        text.push(chars[i + 1]);
                        line += usize::from(chars[i + 1] == '\n');
                        i += 2;
                        continue;
                    }
                    if c == '"' && chars[i + 1..].iter().take(hashes).filter(|h| **h == '#').count() == hashes {
                        i += hashes;
                        break;
                    }
                    line += usize::from(c == '\n');
                    text.push(c);
                    i += 1;
                }
                found.push((start, text));
            }
            _ => {}
        }
        i += 1;
    }
    found
}

/// The `--flag`s a text names (`--sync`, `--log-frames`), not `---` rules or `a--b`.
fn flags_named(text: &str) -> Vec<String> {
    let mut flags = Vec::new();
    for (at, _) in text.match_indices("--") {
        let before = text[..at].chars().last();
        let name: String =
            text[at + 2..].chars().take_while(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || *c == '-').collect();
        if before.is_none_or(|c| !c.is_alphanumeric() && c != '-') && name.starts_with(|c: char| c.is_ascii_lowercase())
        {
            flags.push(format!("--{name}"));
        }
    }
    flags
}

/// Library strings that still name a flag or a command of canctl, as `(file, name, why it
/// stays)`. A remedy naming a flag or a command is the command line's to word
/// (`output/remedies.rs`); empty this list, do not grow it.
const NAMING: &[(&str, &str, &str)] = &[
    ("crates/sim/src/faults.rs", "--fault", "echoes the --fault value the user gave, parsed in sim"),
    (
        "crates/sim/src/socketcand_serve.rs",
        "canctl sim",
        "the beacon's description names the program serving the bus, as socketcand's names itself",
    ),
];

/// canctl's commands, as its help lists them.
fn commands() -> Vec<String> {
    let help = std::process::Command::new(env!("CARGO_BIN_EXE_canctl")).arg("--help").output().unwrap();
    let help = String::from_utf8(help.stdout).unwrap();
    let listed = help.split("Commands:").nth(1).expect("the help lists the commands");
    let names = listed
        .lines()
        .skip(1)
        .take_while(|l| !l.trim().is_empty())
        .filter(|l| l.starts_with("  ") && !l.starts_with("   "));
    names.filter_map(|l| l.split_whitespace().next()).filter(|c| *c != "help").map(String::from).collect()
}

/// The commands of canctl `text` names (`canctl scan`, `(canctl nmt reset 2)`).
fn commands_named(text: &str, commands: &[String]) -> Vec<String> {
    let mut named = Vec::new();
    for (at, _) in text.match_indices("canctl ") {
        let word: String =
            text[at + "canctl ".len()..].chars().take_while(|c| c.is_ascii_lowercase() || *c == '-').collect();
        if commands.contains(&word) {
            named.push(format!("canctl {word}"));
        }
    }
    named
}

/// "Sentences are written only in output/; hints naming flags are added by the command
/// line" (issue 28): a library file (outside `cli/` and `output/`) has no string naming a
/// `--flag` or a canctl command, but for those `NAMING` lists with the reason.
#[test]
fn library_strings_name_no_flag_and_no_command() {
    let commands = commands();
    assert!(["scan", "nmt", "config", "sim"].iter().all(|c| commands.iter().any(|k| k == c)), "{commands:?}");
    let mut files = Vec::new();
    for (dir, prefix) in source_dirs() {
        let mut found = Vec::new();
        rust_files(&dir, &mut found);
        files.extend(found.into_iter().map(|f| (dir.clone(), prefix.clone(), f)));
    }
    files.sort();
    let (mut naming, mut used) = (Vec::new(), BTreeSet::new());
    for (src, prefix, file) in &files {
        // A crate's files are named from the workspace root, src's from src/ (as NAMING does).
        let rel = file.strip_prefix(src).unwrap().to_str().unwrap().replace('\\', "/");
        let rel = match prefix.as_str() {
            "src/" => rel,
            crate_src => format!("{crate_src}{rel}"),
        };
        let front_end = ["cli/", "output/"].iter().any(|d| rel.starts_with(d));
        if front_end
            || ["output.rs", "main.rs"].contains(&rel.as_str())
            || rel.ends_with("tests.rs")
            || rel.contains("/tests/")
        {
            continue;
        }
        let text = std::fs::read_to_string(file).unwrap();
        for (line, literal) in string_literals(&library_code(&text)) {
            for name in flags_named(&literal).into_iter().chain(commands_named(&literal, &commands)) {
                match NAMING.iter().position(|(f, l, _)| *f == rel && *l == name) {
                    Some(k) => drop(used.insert(k)),
                    None => naming.push(format!(
                        "{}{rel} (near line {line}): {name} in {literal:?}",
                        if rel.starts_with("crates/") { "" } else { "src/" }
                    )),
                }
            }
        }
    }
    assert!(
        naming.is_empty(),
        "library strings naming a flag or a command; make the remedy a Hint:\n{}",
        naming.join("\n")
    );
    let stale: Vec<_> = (0..NAMING.len()).filter(|k| !used.contains(k)).map(|k| NAMING[k]).collect();
    assert!(stale.is_empty(), "no longer named, remove from NAMING: {stale:?}");
}

#[test]
fn a_command_is_named_by_its_word_not_its_start() {
    let commands = ["sim".to_string(), "scan".to_string()];
    let found = commands_named("`canctl scan` lists; canctl simulated bootloader; (canctl sim reset)", &commands);
    assert_eq!(found, ["canctl scan", "canctl sim"]);
}

#[test]
fn the_scan_finds_flags_in_strings_only() {
    let code = "let a = \"give a lower --start\"; // --not-this\nlet b = r#\"x \"--raw\" y\"#;\nlet c = '\"';\n\
                let d = \"a \\\"--esc\\\" b\";\nlet e = \"--- a rule, x--y\";\n";
    let found: Vec<_> =
        string_literals(code).into_iter().flat_map(|(l, s)| flags_named(&s).into_iter().map(move |f| (l, f))).collect();
    assert_eq!(found, [(1, "--start".into()), (2, "--raw".into()), (4, "--esc".into())]);
}

/// "Smaller rooms" (issues 28 and 40): no source file of any crate is over 700 lines; a file
/// that grows past it holds more than one concern and is split by them.
#[test]
fn no_source_file_is_over_700_lines() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files = Vec::new();
    for (dir, _) in source_dirs() {
        rust_files(&dir, &mut files);
    }
    let large: Vec<String> = files
        .iter()
        .map(|f| (f, std::fs::read_to_string(f).unwrap().lines().count()))
        .filter(|(_, lines)| *lines > 700)
        .map(|(f, lines)| format!("{} has {lines} lines", f.strip_prefix(root).unwrap().display()))
        .collect();
    assert!(large.is_empty(), "split these by concern: {large:?}");
}
