//! The answer store (`src/kb/answer_store.rs`): answers the engine gave
//! in earlier runs, kept in a folder. A run that takes some or all of its
//! answers from it makes the same mesh and the same trace as a run without
//! it; a store that cannot be read or written changes nothing.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn folder(name: &str) -> PathBuf {
    let dir = std::env::temp_dir()
        .join(format!("freemesh-store-tests-{}", std::process::id()))
        .join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Meshes `domain` graded to six times its size (bounds change during
/// such a run: the store must follow them) with the store in `store`
/// (`off` for none), writing `out.msh` and `out.trace`; returns the
/// output, the mesh and the trace.
fn mesh(domain: &str, store: &str, out: &Path) -> (Output, Vec<u8>, Vec<u8>) {
    let path = format!("../shared/bench/domains/{domain}.json");
    let text = std::fs::read_to_string(&path).unwrap();
    let v: serde_json::Value = serde_json::from_str(&text).unwrap();
    let max = v["size"].as_f64().unwrap() * 6.0;
    mesh_with(&path, store, out, &["--max-size", &max.to_string()])
}

/// Meshes the domain file `path` with `extra` arguments, as `mesh`.
fn mesh_with(path: &str, store: &str, out: &Path, extra: &[&str]) -> (Output, Vec<u8>, Vec<u8>) {
    let (msh, trace) = (out.with_extension("msh"), out.with_extension("trace"));
    let o = Command::new(env!("CARGO_BIN_EXE_freemesh"))
        .args(["mesh", path, "-o"])
        .arg(&msh)
        .arg("--trace")
        .arg(&trace)
        .args(extra)
        .arg("--stats")
        .env("FREEMESH_ANSWER_STORE", store)
        .output()
        .expect("the binary runs");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    (
        o,
        std::fs::read(msh).unwrap(),
        std::fs::read(trace).unwrap(),
    )
}

/// From `--stats`: the questions the engine answered and those the store
/// answered.
fn asked(o: &Output) -> (u64, u64) {
    let err = String::from_utf8_lossy(&o.stderr);
    let line = err
        .lines()
        .find(|l| l.contains("from the answer store"))
        .unwrap_or_else(|| panic!("no engine line in {err}"));
    let number_before = |word: &str| -> u64 {
        let head = &line[..line.find(word).unwrap()];
        head.split_whitespace().last().unwrap().parse().unwrap()
    };
    (
        number_before(" queries ("),
        number_before(" from the answer store"),
    )
}

/// A uniform run of a domain large enough for a second engine, made in
/// blocks: where the store answers every question, no engine is built and
/// the finest layout is made on a thread of its own by a twin of the
/// knowledge base; the mesh and trace are those of a run without a store.
#[test]
fn a_run_the_store_answers_whole_makes_its_layouts_side_by_side_and_the_same_mesh() {
    let dir = folder("layouts");
    let store = dir.join("store");
    let store = store.to_str().unwrap();
    let path = "../shared/bench/domains/multi-connected.json";
    let (_, alone_msh, alone_trace) = mesh_with(path, "off", &dir.join("alone"), &[]);
    let (first, _, _) = mesh_with(path, store, &dir.join("first"), &[]);
    assert!(asked(&first).0 > 0, "the first run asks the engine");
    let (warm, warm_msh, warm_trace) = mesh_with(path, store, &dir.join("warm"), &[]);
    assert_eq!(
        asked(&warm).0,
        0,
        "{}",
        String::from_utf8_lossy(&warm.stderr)
    );
    assert!(alone_msh == warm_msh, "the meshes differ");
    assert!(alone_trace == warm_trace, "the traces differ");
}

#[test]
fn runs_that_take_answers_from_the_store_mesh_as_a_run_without_it() {
    let dir = folder("same");
    let store = dir.join("store");
    let store = store.to_str().unwrap();
    let (_, alone_msh, alone_trace) = mesh("l-bracket-lines", "off", &dir.join("alone"));
    // an empty store: the run's parallel parts answer each other from it
    let fresh = dir.join("fresh");
    let (_, fresh_msh, fresh_trace) = mesh(
        "l-bracket-lines",
        fresh.to_str().unwrap(),
        &dir.join("fresh"),
    );
    // another domain first: its answers answer some of the questions
    // (bound changes among them) and the engine is built for the rest
    mesh("fig1-polygon", store, &dir.join("other"));
    let (part, part_msh, part_trace) = mesh("l-bracket-lines", store, &dir.join("part"));
    let (engine, stored) = asked(&part);
    assert!(engine > 0 && stored > 0, "{engine} {stored}");
    // all of them now: no engine at all
    let (all, all_msh, all_trace) = mesh("l-bracket-lines", store, &dir.join("all"));
    assert_eq!(asked(&all).0, 0);
    assert!(String::from_utf8_lossy(&all.stderr).contains("engine start 0.000 s"));
    let runs = [
        (fresh_msh, fresh_trace),
        (part_msh, part_trace),
        (all_msh, all_trace),
    ];
    for (msh, trace) in runs {
        assert!(msh == alone_msh, "the mesh differs with the store");
        assert!(trace == alone_trace, "the trace differs with the store");
    }
}

#[test]
fn a_store_that_cannot_be_read_or_written_changes_nothing() {
    let dir = folder("broken");
    let (_, alone_msh, _) = mesh("mapping-unequal", "off", &dir.join("alone"));
    // a file where the store's folder should be: nothing is written
    let not_a_folder = dir.join("a-file");
    std::fs::write(&not_a_folder, "x").unwrap();
    let (o, msh, _) = mesh(
        "mapping-unequal",
        not_a_folder.to_str().unwrap(),
        &dir.join("a"),
    );
    assert!(msh == alone_msh);
    assert!(String::from_utf8_lossy(&o.stderr).contains("answer store: not written"));
    // a store file that is not one: read as empty, then written whole
    let store = dir.join("store");
    mesh("mapping-unequal", store.to_str().unwrap(), &dir.join("b"));
    for entry in std::fs::read_dir(&store).unwrap() {
        let path = entry.unwrap().path();
        let bytes = std::fs::read(&path).unwrap();
        std::fs::write(&path, &bytes[..bytes.len() / 2]).unwrap();
    }
    let (o, msh, _) = mesh("mapping-unequal", store.to_str().unwrap(), &dir.join("c"));
    assert!(msh == alone_msh);
    assert_eq!(asked(&o).1, 0, "a store cut short answered");
    let (o, msh, _) = mesh("mapping-unequal", store.to_str().unwrap(), &dir.join("d"));
    assert!(msh == alone_msh);
    assert_eq!(asked(&o).0, 0, "the store was not written again");
}
