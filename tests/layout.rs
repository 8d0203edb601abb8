//! The source layout keeps its promises: no source file above 800 lines,
//! no public module in the library (a short list of re-exports instead),
//! and no module that imports another which imports it back.
//!
//! A module "imports" another when its file names it by a `crate::...`
//! or `super::...` path (in a `use` line or inline), or, for a folder's
//! `mod.rs`, re-exports from a child with `pub use child::...`.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

const MAX_LINES: usize = 800;

/// Every file under `dir` with one of these extensions.
fn files(dir: &Path, exts: &[&str], out: &mut Vec<PathBuf>) {
    let mut entries: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    entries.sort();
    for p in entries {
        if p.is_dir() {
            files(&p, exts, out);
        } else if p
            .extension()
            .is_some_and(|e| exts.contains(&e.to_str().unwrap_or("")))
        {
            out.push(p);
        }
    }
}

/// The library's modules by path (`kb::engine`; "" for the crate root)
/// with their source text; the binary's files left out.
fn library_modules() -> BTreeMap<String, String> {
    let mut paths = Vec::new();
    files(Path::new("src"), &["rs"], &mut paths);
    let mut mods = BTreeMap::new();
    for p in paths {
        let rel = p.strip_prefix("src").unwrap().with_extension("");
        let mut parts: Vec<String> = rel
            .components()
            .map(|c| c.as_os_str().to_string_lossy().into_owned())
            .collect();
        if parts == ["main"] || parts == ["cli"] {
            continue;
        }
        if parts.last().is_some_and(|l| l == "mod" || l == "lib") {
            parts.pop();
        }
        mods.insert(parts.join("::"), std::fs::read_to_string(&p).unwrap());
    }
    mods
}

/// The text without `//` comments.
fn code(text: &str) -> String {
    text.lines()
        .map(|l| l.split("//").next().unwrap_or(""))
        .collect::<Vec<_>>()
        .join("\n")
}

fn is_ident(c: char) -> bool {
    c.is_ascii_alphanumeric() || c == '_'
}

/// The paths named after each `prefix::` in `text`, a `{a, b::c}` group
/// read as one path per item (one level of braces).
fn paths_after(text: &str, prefix: &str) -> Vec<Vec<String>> {
    let mut out = Vec::new();
    let needle = format!("{prefix}::");
    let mut from = 0;
    while let Some(at) = text[from..].find(&needle) {
        let start = from + at;
        from = start + needle.len();
        if text[..start].chars().next_back().is_some_and(is_ident) {
            continue; // part of a longer name
        }
        let rest = &text[from..];
        let mut base = Vec::new();
        let mut chars = rest.char_indices().peekable();
        let mut word = String::new();
        let mut group = None;
        while let Some((i, c)) = chars.next() {
            if is_ident(c) {
                word.push(c);
            } else if c == ':' && rest[i..].starts_with("::") {
                chars.next();
                base.push(std::mem::take(&mut word));
                if rest[i + 2..].starts_with('{') {
                    let close = rest[i + 2..].find('}').map_or(rest.len(), |e| i + 2 + e);
                    group = Some(&rest[i + 3..close]);
                    break;
                }
            } else {
                break;
            }
        }
        match group {
            Some(items) => {
                for item in items.split(',') {
                    let item = item.split(" as ").next().unwrap_or("").trim();
                    if item.is_empty() {
                        continue;
                    }
                    let mut p = base.clone();
                    p.extend(item.split("::").map(|s| s.trim().to_string()));
                    out.push(p);
                }
            }
            None => {
                if !word.is_empty() {
                    base.push(word);
                }
                // `super::*` in a file's inline test module is the file itself
                if !base.is_empty() {
                    out.push(base);
                }
            }
        }
    }
    out
}

/// The longest module path that `path` starts with.
fn resolve(mods: &BTreeMap<String, String>, path: &[String]) -> Option<String> {
    (1..=path.len())
        .rev()
        .map(|k| path[..k].join("::"))
        .find(|m| mods.contains_key(m))
}

/// Each module's imports of other modules.
fn import_graph() -> BTreeMap<String, BTreeSet<String>> {
    let mods = library_modules();
    let mut graph = BTreeMap::new();
    for (m, text) in &mods {
        let text = code(text);
        let parts: Vec<String> = if m.is_empty() {
            vec![]
        } else {
            m.split("::").map(String::from).collect()
        };
        let mut named = paths_after(&text, "crate");
        for p in paths_after(&text, "super") {
            let mut full = parts[..parts.len().saturating_sub(1)].to_vec();
            full.extend(p);
            named.push(full);
        }
        // a folder module re-exporting from its children
        for line in text.lines() {
            let line = line.trim_start();
            let Some(rest) = line
                .strip_prefix("pub use ")
                .or_else(|| line.strip_prefix("pub(crate) use "))
                .or_else(|| line.strip_prefix("use "))
            else {
                continue;
            };
            let first: String = rest.chars().take_while(|&c| is_ident(c)).collect();
            let mut full = parts.clone();
            full.push(first);
            named.push(full);
        }
        let to: BTreeSet<String> = named
            .iter()
            .filter_map(|p| resolve(&mods, p))
            .filter(|t| t != m)
            .collect();
        graph.insert(m.clone(), to);
    }
    graph
}

#[test]
fn no_source_file_is_longer_than_800_lines() {
    let mut paths = Vec::new();
    files(Path::new("src"), &["rs", "pl"], &mut paths);
    files(Path::new("kb"), &["pl"], &mut paths);
    let long: Vec<String> = paths
        .iter()
        .map(|p| (p, std::fs::read_to_string(p).unwrap().lines().count()))
        .filter(|(_, n)| *n > MAX_LINES)
        .map(|(p, n)| format!("{}: {n} lines", p.display()))
        .collect();
    assert!(long.is_empty(), "above {MAX_LINES} lines: {long:?}");
}

#[test]
fn the_library_declares_no_public_module() {
    let lib = std::fs::read_to_string("src/lib.rs").unwrap();
    let public: Vec<&str> = lib
        .lines()
        .filter(|l| l.trim_start().starts_with("pub mod"))
        .collect();
    assert!(public.is_empty(), "{public:?}");
}

#[test]
fn no_module_imports_one_that_imports_it_back() {
    let graph = import_graph();
    assert!(
        graph["pipeline"].contains("recursion") && graph["recursion::mesher"].contains("kb"),
        "the import graph misses imports it should see: {graph:?}"
    );
    // a module is in a cycle iff it reaches itself
    for start in graph.keys() {
        let mut seen = BTreeSet::new();
        let mut todo: Vec<(&String, Vec<&String>)> = vec![(start, vec![start])];
        while let Some((m, path)) = todo.pop() {
            for next in &graph[m] {
                let mut p = path.clone();
                p.push(next);
                assert!(next != start, "an import cycle: {}", {
                    let names: Vec<&str> = p.iter().map(|s| s.as_str()).collect();
                    names.join(" -> ")
                });
                if seen.insert(next) {
                    todo.push((next, p));
                }
            }
        }
    }
}

#[test]
fn a_cycle_is_found_where_there_is_one() {
    // the reader of paths, on the two shapes a cycle hides in
    let text = "use crate::kb::{engine::KnowledgeBase, Action};\nlet x = super::queue::Candidate;";
    assert_eq!(
        paths_after(text, "crate"),
        vec![
            vec!["kb".to_string(), "engine".into(), "KnowledgeBase".into()],
            vec!["kb".to_string(), "Action".into()],
        ]
    );
    assert_eq!(
        paths_after(text, "super"),
        vec![vec!["queue".to_string(), "Candidate".into()]]
    );
}
