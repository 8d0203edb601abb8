//! The command line end to end: meshing, outputs, the KB options, errors.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn freemesh(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_freemesh"))
        .args(args)
        .output()
        .expect("the binary runs")
}

fn tmp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("freemesh-tests-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Reads a mesh written as JSON: nodes and quads.
fn read_json_mesh(path: &Path) -> (Vec<[f64; 2]>, Vec<[usize; 4]>) {
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    let nodes = v["nodes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| [p[0].as_f64().unwrap(), p[1].as_f64().unwrap()])
        .collect();
    let quads = v["quads"]
        .as_array()
        .unwrap()
        .iter()
        .map(|q| std::array::from_fn(|i| q[i].as_u64().unwrap() as usize))
        .collect();
    (nodes, quads)
}

/// Every quad convex and counter-clockwise, no edge in three quads; returns
/// the total area.
fn assert_valid(nodes: &[[f64; 2]], quads: &[[usize; 4]]) -> f64 {
    assert!(!quads.is_empty());
    let mut edges = std::collections::HashMap::new();
    let mut area = 0.0;
    for q in quads {
        for i in 0..4 {
            let (a, b, c) = (nodes[q[i]], nodes[q[(i + 1) % 4]], nodes[q[(i + 2) % 4]]);
            let cross = (b[0] - a[0]) * (c[1] - b[1]) - (b[1] - a[1]) * (c[0] - b[0]);
            assert!(
                cross > 0.0,
                "quad {q:?} is not convex and counter-clockwise"
            );
            area += (a[0] * b[1] - b[0] * a[1]) / 2.0;
            let k = (q[i].min(q[(i + 1) % 4]), q[i].max(q[(i + 1) % 4]));
            *edges.entry(k).or_insert(0) += 1;
        }
    }
    assert!(
        edges.values().all(|&c| c <= 2),
        "an edge is shared by three quads"
    );
    area
}

#[test]
fn square_meshes_into_sixteen_unit_quads() {
    let out = tmp("square.json");
    let o = freemesh(&[
        "mesh",
        "tests/inputs/square.json",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let (nodes, quads) = read_json_mesh(&out);
    assert_eq!(quads.len(), 16);
    assert!((assert_valid(&nodes, &quads) - 16.0).abs() < 1e-9);
    assert!(stderr(&o).contains("16 quads"));
}

#[test]
fn every_benchmark_domain_gives_a_valid_all_quad_mesh() {
    // the judge's public set: domains/ and hard/
    let mut files: Vec<PathBuf> = Vec::new();
    for dir in ["../shared/bench/domains", "../shared/bench/hard"] {
        let mut here: Vec<PathBuf> = std::fs::read_dir(dir)
            .unwrap_or_else(|e| panic!("{dir} beside the clone: {e}"))
            .map(|e| e.unwrap().path())
            .collect();
        here.sort();
        files.extend(here);
    }
    assert!(files.len() >= 16);
    for f in files {
        let out = tmp(&format!(
            "{}.json",
            f.file_stem().unwrap().to_string_lossy()
        ));
        let o = freemesh(&["mesh", f.to_str().unwrap(), "-o", out.to_str().unwrap()]);
        let err = stderr(&o);
        if err.contains("the loop intersects itself") {
            // not a domain (hard/cusp-arc): one line naming where, no mesh
            assert_eq!(o.status.code(), Some(1), "{err}");
            assert_eq!(err.trim().lines().count(), 1, "{err}");
            assert!(!out.exists());
            continue;
        }
        assert!(o.status.success(), "{}: {err}", f.display());
        let (nodes, quads) = read_json_mesh(&out);
        assert!(assert_valid(&nodes, &quads) > 0.0);
    }
}

#[test]
fn several_outputs_are_written_in_their_formats() {
    let (msh, vtk, svg) = (tmp("l.msh"), tmp("l.vtk"), tmp("l.svg"));
    let o = freemesh(&[
        "mesh",
        "tests/inputs/l-shape.json",
        "-o",
        msh.to_str().unwrap(),
        "-o",
        vtk.to_str().unwrap(),
        "-o",
        svg.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let m = std::fs::read_to_string(&msh).unwrap();
    assert!(m.starts_with("$MeshFormat\n4.1 0 8\n"));
    assert!(m.contains("2 1 3 "), "quads as element type 3 in one block");
    assert!(std::fs::read_to_string(&vtk)
        .unwrap()
        .contains("DATASET UNSTRUCTURED_GRID"));
    assert!(std::fs::read_to_string(&svg).unwrap().starts_with("<svg"));
}

/// The free mesh's trace (the paper's recursion, `bound(blocks_first,
/// 0)`): a uniform run is otherwise meshed in blocks first, whose trace
/// has a step a block (tests/blocks.rs).
#[test]
fn trace_has_one_record_per_element_naming_kb_features() {
    let (out, trace) = (tmp("t.json"), tmp("t.jsonl"));
    let o = freemesh(&[
        "mesh",
        "tests/inputs/l-shape.json",
        "-o",
        out.to_str().unwrap(),
        "--trace",
        trace.to_str().unwrap(),
        "--kb",
        "tests/kb/free-first.pl",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let (_, quads) = read_json_mesh(&out);
    let lines: Vec<serde_json::Value> = std::fs::read_to_string(&trace)
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    // (a veto line comes before the step it preceded, and has no element)
    let steps: Vec<&serde_json::Value> = lines.iter().filter(|l| l.get("veto").is_none()).collect();
    let elements = steps
        .iter()
        .filter(|l| l["element"].as_array().unwrap().len() == 4 && l["action"] != "unmesh")
        .count();
    assert!(elements >= quads.len());
    assert!(
        lines.iter().any(|l| l["feature"] == "b2"),
        "the corner feature b2 drives the rows"
    );
    for l in &steps {
        for key in [
            "step", "edge", "angles", "feature", "action", "redesign", "element",
        ] {
            assert!(l.get(key).is_some(), "trace line without {key}");
        }
    }
}

#[test]
fn a_strategy_given_with_kb_changes_the_trace_and_the_mesh() {
    let (m1, t1, m2, t2) = (
        tmp("s1.json"),
        tmp("s1.jsonl"),
        tmp("s2.json"),
        tmp("s2.jsonl"),
    );
    let a = freemesh(&[
        "mesh",
        "tests/inputs/plate-hole.json",
        "-o",
        m1.to_str().unwrap(),
        "--trace",
        t1.to_str().unwrap(),
    ]);
    let b = freemesh(&[
        "mesh",
        "tests/inputs/plate-hole.json",
        "-o",
        m2.to_str().unwrap(),
        "--trace",
        t2.to_str().unwrap(),
        "--kb",
        "tests/kb/strategy-b2-first.pl",
    ]);
    assert!(
        a.status.success() && b.status.success(),
        "{}{}",
        stderr(&a),
        stderr(&b)
    );
    let (ta, tb) = (
        std::fs::read_to_string(&t1).unwrap(),
        std::fs::read_to_string(&t2).unwrap(),
    );
    assert_ne!(ta, tb);
    let count = |t: &str, f: &str| {
        t.lines()
            .filter(|l| serde_json::from_str::<serde_json::Value>(l).unwrap()["feature"] == f)
            .count()
    };
    assert!(
        count(&tb, "b2") > count(&ta, "b2"),
        "b2 first in the strategy: more elements come of b2"
    );
    assert_ne!(
        std::fs::read_to_string(&m1).unwrap(),
        std::fs::read_to_string(&m2).unwrap()
    );
}

#[test]
fn the_same_input_gives_the_same_mesh_and_trace() {
    let (m1, t1, m2, t2) = (
        tmp("d1.json"),
        tmp("d1.jsonl"),
        tmp("d2.json"),
        tmp("d2.jsonl"),
    );
    for (m, t) in [(&m1, &t1), (&m2, &t2)] {
        let o = freemesh(&[
            "mesh",
            "tests/inputs/plate-hole.json",
            "-o",
            m.to_str().unwrap(),
            "--trace",
            t.to_str().unwrap(),
        ]);
        assert!(o.status.success());
    }
    assert_eq!(std::fs::read(&m1).unwrap(), std::fs::read(&m2).unwrap());
    assert_eq!(std::fs::read(&t1).unwrap(), std::fs::read(&t2).unwrap());
}

/// Runs a failing command: one `error:` line, exit 1, no output file.
fn assert_refused(args: &[&str], out: &Path, expect: &str) {
    let o = freemesh(args);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    let err = stderr(&o);
    assert_eq!(err.lines().count(), 1, "one line: {err}");
    assert!(
        err.starts_with("error: ") && err.contains(expect),
        "{err} should name {expect}"
    );
    assert!(!out.exists(), "no output on error");
}

/// Meshing the square with `--kb kb` fails as `assert_refused` asks, the
/// error naming `expect`.
fn assert_kb_refused(out: &str, kb: &str, expect: &str) {
    let out = tmp(out);
    assert_refused(
        &[
            "mesh",
            "tests/inputs/square.json",
            "-o",
            out.to_str().unwrap(),
            "--kb",
            kb,
        ],
        &out,
        expect,
    );
}

#[test]
fn a_broken_kb_file_is_refused_with_its_name_and_line() {
    assert_kb_refused("broken.msh", "tests/kb/broken.pl", "broken.pl:3");
}

#[test]
fn a_folder_given_as_a_kb_file_is_refused_in_words() {
    assert_kb_refused(
        "kb-folder.msh",
        "tests/kb",
        "tests/kb: cannot read: a folder, not a file",
    );
}

#[test]
fn a_kb_file_that_is_not_utf8_is_refused_naming_the_line() {
    assert_kb_refused(
        "kb-latin-1.msh",
        "tests/kb/latin-1.pl",
        "tests/kb/latin-1.pl: cannot read: not UTF-8 text (line 1",
    );
}

#[test]
fn a_kb_rule_that_throws_is_refused_with_its_file_line_and_reason() {
    assert_kb_refused(
        "throws.msh",
        "tests/kb/throws.pl",
        "tests/kb/throws.pl:4: rule_raised(feature/2, evaluation_error(zero_divisor))",
    );
}

#[test]
fn a_kb_rule_that_runs_away_is_refused_with_its_file_and_line() {
    assert_kb_refused(
        "runs-away.msh",
        "tests/kb/runs-away.pl",
        "tests/kb/runs-away.pl:3: rule_runs_away(feature/2)",
    );
}

#[test]
fn a_rule_that_throws_while_meshing_stops_the_run_naming_the_rule() {
    let out = tmp("late-throw.msh");
    assert_refused(
        &[
            "mesh",
            "tests/inputs/l-shape.json",
            "-o",
            out.to_str().unwrap(),
            "--kb",
            "tests/kb/throws-on-a-reflex-corner.pl",
        ],
        &out,
        "the rule feature(b6) raised evaluation_error(zero_divisor) on ctx(180, 180, 270,",
    );
}

#[test]
fn a_rule_that_runs_away_while_meshing_stops_the_run_naming_the_rule() {
    let out = tmp("late-loop.msh");
    assert_refused(
        &[
            "mesh",
            "tests/inputs/l-shape.json",
            "-o",
            out.to_str().unwrap(),
            "--kb",
            "tests/kb/runs-away-on-a-reflex-corner.pl",
        ],
        &out,
        "the rule feature(b6) ran past the inference limit",
    );
}

/// Runs `freemesh repl ARGS` with `script` piped in.
fn repl(args: &[&str], script: &str) -> Output {
    use std::io::Write;
    let mut child = Command::new(env!("CARGO_BIN_EXE_freemesh"))
        .arg("repl")
        .args(args)
        .stdin(std::process::Stdio::piped())
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("the binary runs");
    child
        .stdin
        .take()
        .unwrap()
        .write_all(script.as_bytes())
        .unwrap();
    child.wait_with_output().unwrap()
}

#[test]
fn repl_answers_front_queries_and_goes_on_after_a_malformed_one() {
    let o = repl(
        &["../shared/bench/domains/fig1-polygon.json"],
        "concave_point(N).\nfoo(.\nedge_feature(E, F).\n:quit\n",
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let out = String::from_utf8_lossy(&o.stdout);
    let lines: Vec<&str> = out.lines().collect();
    let error_at = lines
        .iter()
        .position(|l| l.starts_with("error"))
        .expect("an error line for foo(");
    let binding = |l: &str, var: &str| l.trim_start_matches([' ', ';']).starts_with(var);
    assert!(
        lines[..error_at].iter().any(|l| binding(l, "N = ")),
        "bindings of N before the error: {out}"
    );
    let after = &lines[error_at + 1..];
    assert!(!after.is_empty(), "answers after the error: {out}");
    for l in after {
        let l = l.trim_start_matches([' ', ';']).trim_end_matches('.');
        if l == "false" {
            continue; // the last answer had choice points left
        }
        let (e, f) = l.split_once(", F = ").expect("E = .., F = .. bindings");
        assert!(e.starts_with("E = "), "{l}");
        // F = at(Feature, Node): the feature and the end it is anchored on
        let feature = f.trim_start_matches("at(").split(',').next().unwrap();
        assert!(
            ["b1", "b2", "b3", "b4", "b5"].contains(&feature),
            "F is a paper feature: {l}"
        );
    }
}

#[test]
fn repl_has_the_libraries_a_prolog_prompt_has() {
    // the machines are built without the engine's toplevel; the REPL
    // loads what it would have brought
    let o = repl(&[], "format(\"~a\", [x]).\nmust_be(integer, 1).\n:quit\n");
    assert!(o.status.success(), "{}", stderr(&o));
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(!out.contains("unknown_procedure"), "{out}");
    assert_eq!(out.matches("true.").count(), 2, "{out}");
}

#[test]
fn repl_refuses_a_bad_domain_at_the_start_with_one_line() {
    let o = repl(&["tests/inputs/no-such-domain.json"], ":quit\n");
    assert_eq!(o.status.code(), Some(1));
    let err = stderr(&o);
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.starts_with("error: ") && err.contains("no-such-domain.json"));
}

#[test]
fn a_kb_rule_with_an_undefined_action_is_refused() {
    assert_kb_refused(
        "undef.msh",
        "tests/kb/undefined-action.pl",
        "undefined_action(a9/2)",
    );
}

#[test]
fn bad_domains_are_refused_with_a_message_naming_the_fault() {
    let cases: &[(&str, &str)] = &[
        ("{\"size\": 1, \"outer\": {\"points\": [[0,0],[1,0]", "not valid JSON"),
        ("{\"outer\": {\"points\": [[0,0],[1,0],[1,1]]}}", "size: missing key"),
        ("{\"size\": -1, \"outer\": {\"points\": [[0,0],[1,0],[1,1]]}}", "size: must be positive"),
        ("{\"size\": 1, \"outer\": {\"points\": [[0,0],[1,0]]}}", "outer.points: needs at least 3 points"),
        ("{\"size\": 1, \"outer\": {\"points\": [[0,0],[0,0],[1,1]]}}", "zero-length edge"),
        ("{\"size\": 0.1, \"outer\": {\"points\": [[0,0],[2,2],[2,0],[0,2]]}}", "intersects itself"),
        ("{\"size\": 1, \"outer\": {\"points\": [[0,0],[4,0],[4,4],[0,4]], \"segments\": [1,1,1,2]}}", "odd"),
        ("{\"size\": 1, \"outer\": {\"points\": [[0,0],[4,0],[4,4],[0,4]]}, \"holes\": [{\"circle\": {\"center\": [9,9], \"radius\": 1}}]}", "holes[0] lies outside"),
        ("", "not valid JSON"),
        ("[1, 2, 3]", "expected a JSON object"),
        ("{\"size\": NaN, \"outer\": {\"points\": [[0,0],[1,0],[1,1]]}}", "not valid JSON"),
        ("{\"size\": 1e999, \"outer\": {\"points\": [[0,0],[1,0],[1,1]]}}", "number out of range"),
        ("{\"size\": \"big\", \"outer\": {\"points\": [[0,0],[1,0],[1,1]]}}", "size: expected a number"),
        ("{\"size\": 1, \"outer\": {\"points\": [[0,0],[1,\"x\"],[1,1]]}}", "outer.points[1][1]: expected a number"),
        ("{\"size\": 1}", "outer: missing key"),
        ("{\"size\": 1, \"max_size\": -2, \"outer\": {\"points\": [[0,0],[1,0],[1,1]]}}", "max_size: must be positive"),
        ("{\"size\": 1, \"outer\": {\"circle\": {\"center\": [0,0], \"radius\": 0}}}", "outer.circle.radius: must be positive"),
        ("{\"size\": 0.5, \"outer\": {\"points\": [[0,0],[10,0],[10,10],[0,10]]}, \"holes\": [{\"points\": [[1,1],[4,1],[4,4],[1,4]]}, {\"points\": [[3,3],[6,3],[6,6],[3,6]]}]}", "holes[0] and holes[1] cross or touch"),
        ("{\"size\": 0.5, \"outer\": {\"points\": [[0,0],[10,0],[10,10],[0,10]]}, \"holes\": [{\"points\": [[0,2],[4,2],[4,4],[0,4]]}]}", "outer and holes[0] cross or touch"),
        ("{\"size\": 0.5, \"outer\": {\"points\": [[0,0],[10,0],[10,10],[0,10]]}, \"lines\": [{\"points\": [[1,1],[20,20]]}]}", "outer and lines[0] cross or touch"),
        ("{\"size\": 0.5, \"outer\": {\"points\": [[0,0],[10,0],[10,10],[0,10]]}, \"lines\": [{\"points\": [[20,20],[30,30]]}]}", "lines[0] lies outside"),
        ("{\"size\": 0.5, \"outer\": {\"points\": [[0,0],[10,0],[10,10],[0,10]]}, \"lines\": [{\"points\": [[1,1]]}]}", "lines[0].points: needs at least 2 points"),
        ("{\"size\": 1e-9, \"outer\": {\"points\": [[0,0],[10,0],[10,10],[0,10]]}}", "elements over the domain's area 1.0000e2, above the limit of 5000000"),
        ("{\"size\": 0.001, \"outer\": {\"points\": [[0,0],[10,0],[10,10],[0,10]]}}", "about 1.00e8 elements"),
        ("{\"size\": 1, \"outer\": {\"points\": [[0,0],[10,0],[10,10],[0,10]], \"segments\": [100000000, 2, 2, 2]}}", "outer.segments[0]: 100000000 segments is above the limit"),
        ("{\"size\": 1, \"outer\": {\"points\": [[0,0],[10,0],[10,10],[0,10]], \"segments\": [-1, 2, 2, 2]}}", "outer.segments[0]: expected a whole number >= 0"),
        ("{\"size\": 1, \"outer\": {\"points\": [[0,0],[10,0],[10,10],[0,10]], \"bulges\": [0, 0]}}", "outer.bulges: expected 4 entries"),
        ("{\"size\": 1, \"outer\": {\"points\": [[0,0],[4,0],[4,4],[0,4]], \"bulges\": [0, 1e9, 0, 0]}}", "bulges[1]"),
        ("{\"size\": 1, \"max_size\": 0.5, \"outer\": {\"points\": [[0,0],[4,0],[4,4],[0,4]]}}", "max_size: 0.5 is below size 1"),
        // a bowtie: the crossing point, as the input writes numbers
        ("{\"size\": 1, \"outer\": {\"points\": [[0,0],[10,0],[0,10],[10,10]]}}", "outer: the loop intersects itself at (5, 5)"),
        ("{\"size\": 0.1, \"outer\": {\"points\": [[0,0],[1.5,0],[0,1.5],[1.5,1.5]]}}", "outer: the loop intersects itself near (0.8, 0.8)"),
        ("{\"size\": 0.5, \"outer\": {\"points\": [[0,0],[10,0],[10,10],[0,10]]}, \"holes\": [{\"points\": [[1,1],[4,1],[4,4],[1,4]]}], \"lines\": [{\"points\": [[0.5,2.5],[2.5,2.5]]}]}", "holes[0] and lines[0] cross or touch at (1.0, 2.5)"),
        // an arc that runs back across the edge before it: the two edges,
        // and how far from the point they share
        ("{\"size\": 0.5, \"outer\": {\"points\": [[0,0],[10,0],[10,10],[0,10]]}, \"lines\": [{\"points\": [[2,2],[6,2],[3,2.5]], \"bulges\": [0, -0.6]}]}", "lines[0]: the line crosses itself near (3.3, 2.0): edges 0 and 1 meet again 2.7 from point 1 at (6.0, 2.0), where they join"),
    ];
    for (i, (text, expect)) in cases.iter().enumerate() {
        let dom = tmp(&format!("bad{i}.json"));
        std::fs::write(&dom, text).unwrap();
        let out = tmp(&format!("bad{i}.msh"));
        assert_refused(
            &["mesh", dom.to_str().unwrap(), "-o", out.to_str().unwrap()],
            &out,
            expect,
        );
    }
}

#[test]
fn an_unknown_key_is_refused_with_the_key_meant() {
    let dom = tmp("typo.json");
    std::fs::write(
        &dom,
        "{\"size\": 1, \"outer\": {\"points\": [[0,0],[4,0],[4,4],[0,4]]}, \"hole\": [{\"circle\": {\"center\": [2,2], \"radius\": 1}}]}",
    )
    .unwrap();
    let out = tmp("typo.json.msh");
    assert_refused(
        &["mesh", dom.to_str().unwrap(), "-o", out.to_str().unwrap()],
        &out,
        "unknown key: hole (did you mean holes?)",
    );
    // the keys of format 1.1 are known
    let tagged = tmp("tagged.json");
    std::fs::write(
        &tagged,
        "{\"size\": 1, \"outer\": {\"points\": [[0,0],[4,0],[4,4],[0,4]], \"tags\": [\"bottom\", \"\", \"\", \"\"]}, \"holes\": [{\"circle\": {\"center\": [2,2], \"radius\": 1, \"tag\": \"bore\"}}]}",
    )
    .unwrap();
    let o = freemesh(&["features", tagged.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
}

#[test]
fn a_missing_domain_file_is_an_error_not_a_panic() {
    let out = tmp("missing.msh");
    let args = ["mesh", "no/such/domain.json", "-o", out.to_str().unwrap()];
    assert_refused(&args, &out, "no/such/domain.json");
    // the system's reason once, not repeated by the error chain
    let err = stderr(&freemesh(&args));
    assert_eq!(err.matches("No such file").count(), 1, "{err}");
}

#[test]
fn an_unknown_output_format_is_refused_before_meshing() {
    let out = tmp("mesh.xyz");
    assert_refused(
        &[
            "mesh",
            "tests/inputs/square.json",
            "-o",
            out.to_str().unwrap(),
        ],
        &out,
        "unknown output format",
    );
}

#[test]
fn features_lists_concave_corners_and_the_kb_actions() {
    let o = freemesh(&[
        "features",
        "../shared/bench/domains/fig1-polygon.json",
        "--json",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let nodes = v["nodes"].as_array().unwrap();
    // fig1's polygon has two reflex corners: (4, 2.5) and (1.5, 2.5)
    let concave: Vec<(f64, f64)> = nodes
        .iter()
        .filter(|n| n["concave"] == true)
        .map(|n| (n["x"].as_f64().unwrap(), n["y"].as_f64().unwrap()))
        .collect();
    assert!(
        concave.contains(&(4.0, 2.5)) && concave.contains(&(1.5, 2.5)),
        "{concave:?}"
    );
    let edges = v["edges"].as_array().unwrap();
    assert_eq!(edges.len(), 2 * nodes.len(), "each edge in both readings");
    assert!(edges
        .iter()
        .any(|e| e["feature"] == "b1" && e["action"].as_str().unwrap().starts_with("a1(")));
    assert!(edges
        .iter()
        .any(|e| e["feature"] == "b2" && e["action"].as_str().unwrap().starts_with("a2(")));
}

#[test]
fn fronts_that_meet_at_a_fine_size_are_closed_by_the_rules() {
    // At a uniform 0.08 the fronts from the outer loop and the holes meet
    // in many places; the loops they leave must be closed by the rules and
    // the loop subdivision, not by the whole-domain triangle fallback.
    let out = tmp("plate-holes-fine.json");
    let o = freemesh(&[
        "mesh",
        "../shared/bench/domains/plate-holes.json",
        "--size",
        "0.08",
        "--max-size",
        "0.08",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(!stderr(&o).contains("triangle fallback"), "{}", stderr(&o));
    let (nodes, quads) = read_json_mesh(&out);
    let area = assert_valid(&nodes, &quads);
    let holes = std::f64::consts::PI * (1.2f64.powi(2) + 1.0);
    assert!((area - (60.0 - holes)).abs() < 0.05, "area {area}");
    // elements of the requested size, not the fallback's halves
    assert!((7000..9500).contains(&quads.len()), "{} quads", quads.len());
}

#[test]
fn stats_say_where_the_time_goes() {
    let out = tmp("stats.msh");
    let o = freemesh(&[
        "mesh",
        "../shared/bench/domains/fig1-polygon.json",
        "--stats",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let err = stderr(&o);
    assert!(err.contains("queries and"), "{err}");
    assert!(err.contains("us of engine time per element"), "{err}");
    for phase in ["prepare", "recursion", "smoothing", "check"] {
        assert!(err.contains(&format!("{phase} ")), "no {phase} in {err}");
    }
    // its mesh has no more elements than its area asks for
    assert!(!err.contains("coarser pass"), "{err}");
    // a 9.5-degree spike's has: the coarser pass's meshes have a line
    // of their own, not "the rest"
    let spike = tmp("stats-spike.json");
    std::fs::write(
        &spike,
        r#"{"name": "spike", "size": 1, "outer": {"points": [[0,0],[6,0],[6,1.0]]}}"#,
    )
    .unwrap();
    let o = freemesh(&[
        "mesh",
        spike.to_str().unwrap(),
        "--stats",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let err = stderr(&o);
    assert!(err.contains("spike: coarser pass "), "{err}");
}

#[test]
fn quality_measures_our_mesh_and_another_programs() {
    let ours = tmp("quality-ours.msh");
    let o = freemesh(&[
        "mesh",
        "../shared/bench/domains/fig1-polygon.json",
        "-o",
        ours.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let summary = stderr(&o);
    let q = freemesh(&["quality", ours.to_str().unwrap()]);
    assert!(q.status.success(), "{}", stderr(&q));
    let text = String::from_utf8_lossy(&q.stdout).into_owned();
    // the same count as the mesh command's summary line
    let quads = summary
        .split(" quads")
        .next()
        .unwrap()
        .rsplit(' ')
        .next()
        .unwrap();
    assert!(
        text.contains(&format!("{quads} quads")),
        "{text}\n{summary}"
    );
    for what in ["in [45, 135]", "scaled Jacobian", "taper", "corner angles"] {
        assert!(text.contains(what), "no {what} in {text}");
    }
    // a unit square and a triangle as Gmsh writes MSH 2.2
    let theirs = tmp("quality-theirs.msh");
    std::fs::write(
        &theirs,
        "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n5\n1 0 0 0\n2 1 0 0\n3 1 1 0\n4 0 1 0\n5 2 0 0\n$EndNodes\n$Elements\n2\n1 3 2 0 1 1 2 3 4\n2 2 2 0 1 2 5 3\n$EndElements\n",
    )
    .unwrap();
    let q = freemesh(&["quality", theirs.to_str().unwrap(), "--json"]);
    assert!(q.status.success(), "{}", stderr(&q));
    let v: serde_json::Value = serde_json::from_slice(&q.stdout).unwrap();
    assert_eq!(v["quality"]["quads"], 1);
    assert_eq!(v["other_faces"], 1);
    assert_eq!(v["quality"]["min_angle"].as_f64().unwrap().round(), 90.0);
    assert_eq!(v["angle_bins_10deg"][9], 4);
}

#[test]
fn quality_of_a_file_that_is_no_mesh_is_one_error_line() {
    let bad = tmp("not-a-mesh.msh");
    std::fs::write(&bad, "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 2 1").unwrap();
    let q = freemesh(&["quality", bad.to_str().unwrap()]);
    assert_eq!(q.status.code(), Some(1));
    let err = stderr(&q);
    assert!(
        err.starts_with("error:") && err.contains("not-a-mesh.msh"),
        "{err}"
    );
    assert_eq!(err.trim().lines().count(), 1, "{err}");
}

#[test]
fn an_option_out_of_range_names_its_flag() {
    // `--size -1` too: clap alone read `-1` as an option of its own
    let cases = [
        ("--size", "-1", true),
        ("--max-size", "0", true),
        ("--size", "-1", false),
        ("--max-size", "-2", false),
    ];
    for (flag, value, joined) in cases {
        let out = tmp("bad-option.msh");
        let joined_arg = format!("{flag}={value}");
        let mut args = vec!["mesh", "tests/inputs/square.json"];
        if joined {
            args.push(&joined_arg);
        } else {
            args.extend([flag, value]);
        }
        args.extend(["-o", out.to_str().unwrap()]);
        let o = freemesh(&args);
        assert_eq!(o.status.code(), Some(1));
        let err = stderr(&o);
        assert_eq!(
            err.trim(),
            format!("error: {flag} must be a positive number, got {value}")
        );
        assert!(!out.exists(), "no output for a refused option");
    }
}

/// The files in a folder whose names hold `.tmp-`: temporaries left.
fn temporaries_in(dir: &Path) -> Vec<String> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.contains(".tmp-"))
        .collect()
}

/// A fresh empty folder for one test.
fn tmp_dir(name: &str) -> PathBuf {
    let dir = tmp(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn the_same_output_named_twice_is_refused_before_meshing() {
    let dir = tmp_dir("twice");
    let same = dir.join("same.msh");
    let same = same.to_str().unwrap();
    // a rule that throws while meshing: refused before it is asked
    let kb = ["--kb", "tests/kb/throws-on-a-reflex-corner.pl"];
    let dotted = format!("{}/./same.msh", dir.display());
    let trace = dir.join("same.msh");
    for args in [
        vec!["-o", same, "-o", same],
        vec!["-o", same, "-o", &dotted],
        vec!["-o", same, "--trace", trace.to_str().unwrap()],
    ] {
        let mut all = vec!["mesh", "tests/inputs/l-shape.json"];
        all.extend(&args);
        all.extend(kb);
        assert_refused(
            &all,
            Path::new(same),
            "same.msh is given twice as an output",
        );
        assert!(temporaries_in(&dir).is_empty());
    }
}

#[test]
fn the_binary_draws_where_the_rules_stopped_when_a_developer_asks() {
    let out = tmp("spike.msh");
    let svg = tmp("spike-stopped.svg");
    let trace = tmp("spike.jsonl");
    let o = Command::new(env!("CARGO_BIN_EXE_freemesh"))
        .args([
            "mesh",
            "tests/stuck/spike.json",
            "-o",
            out.to_str().unwrap(),
        ])
        .args(["--trace", trace.to_str().unwrap()])
        .env("FREEMESH_DEBUG_SVG", &svg)
        .output()
        .expect("the binary runs");
    assert!(o.status.success(), "{}", stderr(&o));
    let picture = std::fs::read_to_string(&svg).unwrap();
    assert!(picture.starts_with("<svg"), "{}", &picture[..40]);
    // the rules' trace up to where they stopped; the run's own trace goes
    // on to the step that closed the loops they left open
    let steps = std::fs::read_to_string(svg.with_extension("svg.trace")).unwrap();
    assert!(steps.lines().count() > 1, "{steps}");
    assert!(steps.lines().all(|l| l.starts_with('{')), "{steps}");
    let run = std::fs::read_to_string(&trace).unwrap();
    assert!(run.lines().count() > steps.lines().count(), "{run}");
    let last = run.lines().last().unwrap_or("");
    assert!(last.contains("loop_triangle_pairs("), "{last}");
}

#[test]
fn two_domains_that_would_write_one_file_are_refused() {
    let dir = tmp_dir("stems");
    let a = dir.join("a");
    let b = dir.join("b");
    for d in [&a, &b] {
        std::fs::create_dir_all(d).unwrap();
        std::fs::copy("tests/inputs/square.json", d.join("square.json")).unwrap();
    }
    let out = dir.join("{stem}.msh");
    assert_refused(
        &[
            "mesh",
            a.join("square.json").to_str().unwrap(),
            b.join("square.json").to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ],
        &dir.join("square.msh"),
        "would both write",
    );
}

#[test]
fn an_output_folder_that_is_missing_or_cannot_be_written_is_refused_before_meshing() {
    let missing = tmp("no-such-folder/out.msh");
    // with a rule that throws while meshing: the folder is named, not the rule
    assert_refused(
        &[
            "mesh",
            "tests/inputs/l-shape.json",
            "-o",
            missing.to_str().unwrap(),
            "--kb",
            "tests/kb/throws-on-a-reflex-corner.pl",
        ],
        &missing,
        "no-such-folder does not exist",
    );
    let file = tmp("a-file");
    std::fs::write(&file, "").unwrap();
    let under_a_file = file.join("out.msh");
    assert_refused(
        &[
            "mesh",
            "tests/inputs/square.json",
            "-o",
            under_a_file.to_str().unwrap(),
        ],
        &under_a_file,
        "a-file is not a folder",
    );
    // a folder even root cannot write in (chmod would not stop root)
    if cfg!(target_os = "linux") {
        let sys = Path::new("/sys/freemesh-test.msh");
        assert_refused(
            &[
                "mesh",
                "tests/inputs/l-shape.json",
                "-o",
                sys.to_str().unwrap(),
                "--kb",
                "tests/kb/throws-on-a-reflex-corner.pl",
            ],
            sys,
            "/sys/freemesh-test.msh: cannot write: ",
        );
        // the system's reason once, not repeated by an error chain
        let err = stderr(&freemesh(&[
            "mesh",
            "tests/inputs/square.json",
            "-o",
            sys.to_str().unwrap(),
        ]));
        assert_eq!(err.matches("os error").count(), 1, "{err}");
    }
}

#[test]
fn max_size_below_size_is_refused() {
    let out = tmp("max-below.msh");
    assert_refused(
        &[
            "mesh",
            "tests/inputs/square.json",
            "-o",
            out.to_str().unwrap(),
            "--size",
            "0.5",
            "--max-size",
            "0.25",
        ],
        &out,
        "--max-size 0.25 is below --size 0.5",
    );
    let dom = tmp("with-max.json");
    std::fs::write(
        &dom,
        "{\"size\": 1, \"max_size\": 2, \"outer\": {\"points\": [[0,0],[4,0],[4,4],[0,4]]}}",
    )
    .unwrap();
    assert_refused(
        &[
            "mesh",
            dom.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--size",
            "3",
        ],
        &out,
        "the domain's max_size 2 is below --size 3",
    );
}

#[test]
fn stem_is_replaced_with_one_input_too() {
    let dir = tmp_dir("one-stem");
    let pattern = dir.join("{stem}-x.json");
    let o = freemesh(&[
        "mesh",
        "tests/inputs/square.json",
        "-o",
        pattern.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(dir.join("square-x.json").exists());
    assert!(!pattern.exists(), "no file named {{stem}}-x.json");
}

#[test]
fn a_failing_domain_of_several_names_its_file_once() {
    let dir = tmp_dir("batch");
    std::fs::copy("tests/inputs/square.json", dir.join("good.json")).unwrap();
    std::fs::write(dir.join("trunc.json"), "{\"size\": 1, \"outer\": {\"po").unwrap();
    let o = freemesh(&[
        "mesh",
        dir.join("good.json").to_str().unwrap(),
        dir.join("trunc.json").to_str().unwrap(),
        "-o",
        dir.join("{stem}.msh").to_str().unwrap(),
        "--jobs",
        "1",
    ]);
    assert_eq!(o.status.code(), Some(1));
    let err = stderr(&o);
    let line = err
        .lines()
        .find(|l| l.contains("not valid JSON"))
        .expect(&err);
    assert_eq!(line.matches("trunc.json").count(), 1, "{line}");
    // a fault that does not name the file gets its name first
    std::fs::write(
        dir.join("trunc.json"),
        "{\"outer\": {\"points\": [[0,0],[1,0],[1,1]]}}",
    )
    .unwrap();
    let o = freemesh(&[
        "mesh",
        dir.join("good.json").to_str().unwrap(),
        dir.join("trunc.json").to_str().unwrap(),
        "-o",
        dir.join("{stem}.msh").to_str().unwrap(),
    ]);
    let err = stderr(&o);
    assert!(err.contains("trunc.json: size: missing key"), "{err}");
    assert!(dir.join("good.msh").exists());
}

#[test]
fn the_summary_never_rounds_a_share_up_to_all() {
    // dam has a sharp input corner: an element or two stay outside [45, 135]
    let out = tmp("dam.json");
    let o = freemesh(&[
        "mesh",
        "../shared/bench/domains/dam.json",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let summary = stderr(&o);
    let q = freemesh(&["quality", out.to_str().unwrap(), "--json"]);
    let v: serde_json::Value = serde_json::from_slice(&q.stdout).unwrap();
    let outside = v["quality"]["outside_45_135"].as_u64().unwrap();
    assert!(outside > 0, "dam keeps a corner outside: {summary}");
    assert!(!summary.contains("100.0%"), "{summary}");
    assert!(
        summary.contains(&format!("({outside} outside)")),
        "{summary}"
    );
    let text =
        String::from_utf8_lossy(&freemesh(&["quality", out.to_str().unwrap()]).stdout).into_owned();
    assert!(text.contains(&format!("({outside} outside)")), "{text}");
}

#[test]
fn quality_reads_binary_msh_as_gmsh_writes_it() {
    // one mesh written by Gmsh 4.15 twice: binary and ASCII MSH 4.1
    // (ASCII rounds the coordinates to 16 digits: the measures agree to
    // far below their printed digits, not bit for bit)
    let read = |f: &str| {
        let q = freemesh(&["quality", f, "--json"]);
        assert!(q.status.success(), "{f}: {}", stderr(&q));
        let v: serde_json::Value = serde_json::from_slice(&q.stdout).unwrap();
        v
    };
    let (binary, ascii) = (
        read("tests/inputs/gmsh-plate-binary.msh"),
        read("tests/inputs/gmsh-plate-ascii.msh"),
    );
    assert_eq!(binary["quality"]["quads"], 49);
    assert_eq!(binary["other_faces"], 6, "Gmsh left six triangles");
    for (k, v) in binary["quality"].as_object().unwrap() {
        match (v.as_f64(), ascii["quality"][k].as_f64()) {
            (Some(b), Some(a)) => assert!((b - a).abs() < 1e-9, "{k}: binary {b}, ASCII {a}"),
            _ => assert_eq!(v, &ascii["quality"][k], "{k}"),
        }
    }
}

#[test]
fn a_binary_file_that_is_no_mesh_is_named_as_such() {
    let bad = tmp("binary.msh");
    std::fs::write(&bad, [0u8, 159, 146, 150, 0, 1]).unwrap();
    let q = freemesh(&["quality", bad.to_str().unwrap()]);
    assert_eq!(q.status.code(), Some(1));
    let err = stderr(&q);
    assert!(
        err.contains("binary.msh: not a text file, nor a binary MSH 4.1 file"),
        "{err}"
    );
    assert!(!err.contains("UTF-8"), "{err}");
}

/// Sends a signal to a process by its id.
fn signal(pid: u32, name: &str) {
    let s = Command::new("kill")
        .args([&format!("-{name}"), &pid.to_string()])
        .status()
        .expect("kill runs");
    assert!(s.success());
}

/// Waits until a process is stopped or gone (its state in /proc: T, Z
/// or X), at most a second.
fn wait_until_stopped(pid: u32) {
    for _ in 0..10_000 {
        let Ok(stat) = std::fs::read_to_string(format!("/proc/{pid}/stat")) else {
            return;
        };
        // the state follows the command's name in parentheses
        let state = stat
            .rsplit(')')
            .next()
            .and_then(|r| r.split_whitespace().next());
        if matches!(state, Some("T" | "t" | "Z" | "X")) {
            return;
        }
        std::thread::sleep(std::time::Duration::from_micros(100));
    }
}

#[test]
#[cfg(unix)]
fn ctrl_c_while_writing_removes_the_temporaries() {
    // A large mesh into five outputs: the child is stopped the moment a
    // temporary shows up, and interrupted while one is there for sure.
    let dir = tmp_dir("interrupted");
    let outs: Vec<PathBuf> = ["m.msh", "m.vtk", "m.json", "m.svg"]
        .iter()
        .map(|n| dir.join(n))
        .collect();
    let mut caught = false;
    for attempt in 0..20 {
        let mut args = vec![
            "mesh".to_string(),
            "../shared/bench/domains/plate-holes.json".into(),
            "--size".into(),
            "0.04".into(),
            "--max-size".into(),
            "0.04".into(),
            "--trace".into(),
            dir.join("m.jsonl").to_string_lossy().into_owned(),
        ];
        for o in &outs {
            args.push("-o".into());
            args.push(o.to_string_lossy().into_owned());
        }
        let mut child = Command::new(env!("CARGO_BIN_EXE_freemesh"))
            .args(&args)
            .stderr(std::process::Stdio::piped())
            .spawn()
            .unwrap();
        let pid = child.id();
        loop {
            if !temporaries_in(&dir).is_empty() {
                signal(pid, "STOP");
                // kill returns before the child has stopped: until it
                // has, it may still put its outputs in place and exit 0
                wait_until_stopped(pid);
                if !temporaries_in(&dir).is_empty() {
                    caught = true;
                    signal(pid, "INT");
                }
                signal(pid, "CONT");
                break;
            }
            if child.try_wait().unwrap().is_some() {
                break;
            }
        }
        let status = child.wait().unwrap();
        assert!(
            temporaries_in(&dir).is_empty(),
            "left: {:?}",
            temporaries_in(&dir)
        );
        if caught {
            assert_eq!(status.code(), Some(130), "attempt {attempt}");
            break;
        }
        for entry in std::fs::read_dir(&dir).unwrap() {
            std::fs::remove_file(entry.unwrap().path()).unwrap();
        }
    }
    assert!(caught, "no run was caught writing in twenty attempts");
}

/// The README's text.
fn readme() -> String {
    std::fs::read_to_string("README.md").unwrap()
}

/// The README's section from a heading to the next heading of its level
/// or above.
fn readme_section(heading: &str) -> String {
    let text = readme();
    let start = text
        .find(heading)
        .unwrap_or_else(|| panic!("README has no {heading}"));
    let level = heading.chars().take_while(|&c| c == '#').count();
    let rest = &text[start + heading.len()..];
    let end = rest
        .lines()
        .scan(0, |at, l| {
            let here = *at;
            *at += l.len() + 1;
            Some((here, l))
        })
        .find(|(_, l)| {
            let hashes = l.chars().take_while(|&c| c == '#').count();
            hashes > 0 && hashes <= level && l[hashes..].starts_with(' ')
        })
        .map_or(rest.len(), |(at, _)| at);
    rest[..end].to_string()
}

#[test]
fn the_readmes_first_command_leaves_no_untracked_file() {
    let section = readme_section("## Two commands");
    let command = section
        .lines()
        .map(str::trim)
        .find(|l| l.starts_with("cargo run") && l.contains(" -- mesh "))
        .expect("a cargo run -- mesh command in the README");
    let args: Vec<&str> = command
        .split(" -- ")
        .nth(1)
        .unwrap()
        .split_whitespace()
        .collect();
    let o = freemesh(&args);
    assert!(o.status.success(), "{command}: {}", stderr(&o));
    let outputs: Vec<&str> = args
        .windows(2)
        .filter(|w| w[0] == "-o")
        .map(|w| w[1])
        .collect();
    assert!(!outputs.is_empty());
    for out in outputs {
        assert!(Path::new(out).exists(), "{out} written");
        let ignored = Command::new("git")
            .args(["check-ignore", "-q", out])
            .status()
            .expect("git runs in the clone");
        assert!(ignored.success(), "{out} is left untracked by git");
    }
}

#[test]
fn every_field_of_the_trace_is_documented_in_the_readme() {
    let trace = tmp("documented.jsonl");
    let out = tmp("documented.json");
    let o = freemesh(&[
        "mesh",
        "tests/inputs/plate-hole.json",
        "-o",
        out.to_str().unwrap(),
        "--trace",
        trace.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let docs = readme_section("### The trace");
    let mut fields = std::collections::BTreeSet::new();
    for line in std::fs::read_to_string(&trace).unwrap().lines() {
        let v: serde_json::Value = serde_json::from_str(line).unwrap();
        for (k, value) in v.as_object().unwrap() {
            fields.insert(k.clone());
            if k == "angles" {
                for name in value.as_object().unwrap().keys() {
                    fields.insert(name.clone());
                }
            }
        }
    }
    let missing: Vec<&String> = fields
        .iter()
        .filter(|f| !docs.contains(&format!("`{f}`")))
        .collect();
    assert!(
        missing.is_empty(),
        "trace fields not in the README: {missing:?}"
    );
    assert!(docs.contains("`-1`"), "the -1 node id is explained");
}
