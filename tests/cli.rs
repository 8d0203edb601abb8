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
    let dir = Path::new("../shared/bench/domains");
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .expect("../shared/bench/domains beside the clone")
        .map(|e| e.unwrap().path())
        .collect();
    files.sort();
    assert!(files.len() >= 9);
    for f in files {
        let out = tmp(&format!(
            "{}.json",
            f.file_stem().unwrap().to_string_lossy()
        ));
        let o = freemesh(&["mesh", f.to_str().unwrap(), "-o", out.to_str().unwrap()]);
        assert!(o.status.success(), "{}: {}", f.display(), stderr(&o));
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
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let (_, quads) = read_json_mesh(&out);
    let lines: Vec<serde_json::Value> = std::fs::read_to_string(&trace)
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    let elements = lines
        .iter()
        .filter(|l| l["element"].as_array().unwrap().len() == 4 && l["action"] != "unmesh")
        .count();
    assert!(elements >= quads.len());
    assert!(
        lines.iter().any(|l| l["feature"] == "b2"),
        "the corner feature b2 drives the rows"
    );
    for l in &lines {
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

#[test]
fn a_broken_kb_file_is_refused_with_its_name_and_line() {
    let out = tmp("broken.msh");
    assert_refused(
        &[
            "mesh",
            "tests/inputs/square.json",
            "-o",
            out.to_str().unwrap(),
            "--kb",
            "tests/kb/broken.pl",
        ],
        &out,
        "broken.pl:3",
    );
}

#[test]
fn a_kb_rule_that_throws_is_refused_with_its_file_line_and_reason() {
    let out = tmp("throws.msh");
    assert_refused(
        &[
            "mesh",
            "tests/inputs/square.json",
            "-o",
            out.to_str().unwrap(),
            "--kb",
            "tests/kb/throws.pl",
        ],
        &out,
        "tests/kb/throws.pl:4: rule_raised(feature/2, evaluation_error(zero_divisor))",
    );
}

#[test]
fn a_kb_rule_that_runs_away_is_refused_with_its_file_and_line() {
    let out = tmp("runs-away.msh");
    assert_refused(
        &[
            "mesh",
            "tests/inputs/square.json",
            "-o",
            out.to_str().unwrap(),
            "--kb",
            "tests/kb/runs-away.pl",
        ],
        &out,
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
    let out = tmp("undef.msh");
    assert_refused(
        &[
            "mesh",
            "tests/inputs/square.json",
            "-o",
            out.to_str().unwrap(),
            "--kb",
            "tests/kb/undefined-action.pl",
        ],
        &out,
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
fn an_unknown_key_is_named_in_a_warning_with_the_key_meant() {
    let dom = tmp("typo.json");
    std::fs::write(
        &dom,
        "{\"size\": 1, \"outer\": {\"points\": [[0,0],[4,0],[4,4],[0,4]]}, \"hole\": []}",
    )
    .unwrap();
    let out = tmp("typo.json.msh");
    let o = freemesh(&["mesh", dom.to_str().unwrap(), "-o", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("warning: ") && stderr(&o).contains("hole (did you mean holes?)"),
        "{}",
        stderr(&o)
    );
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
    for (flag, value) in [("--size", "-1"), ("--max-size", "0")] {
        let out = tmp("bad-option.msh");
        let o = freemesh(&[
            "mesh",
            "tests/inputs/square.json",
            &format!("{flag}={value}"),
            "-o",
            out.to_str().unwrap(),
        ]);
        assert_eq!(o.status.code(), Some(1));
        let err = stderr(&o);
        assert_eq!(
            err.trim(),
            format!("error: {flag} must be a positive number, got {value}")
        );
        assert!(!out.exists(), "no output for a refused option");
    }
}

#[test]
fn the_binary_draws_where_the_rules_stopped_when_a_developer_asks() {
    let out = tmp("slot.msh");
    let svg = tmp("slot-stopped.svg");
    let trace = tmp("slot.jsonl");
    let o = Command::new(env!("CARGO_BIN_EXE_freemesh"))
        .args(["mesh", "tests/stuck/slot.json", "-o", out.to_str().unwrap()])
        .args(["--trace", trace.to_str().unwrap()])
        .env("FREEMESH_DEBUG_SVG", &svg)
        .output()
        .expect("the binary runs");
    assert!(o.status.success(), "{}", stderr(&o));
    let picture = std::fs::read_to_string(&svg).unwrap();
    assert!(picture.starts_with("<svg"), "{}", &picture[..40]);
    // the rules' trace up to where they stopped (the run's own trace is
    // the last resort's one step)
    let steps = std::fs::read_to_string(svg.with_extension("svg.trace")).unwrap();
    assert!(steps.lines().count() > 1, "{steps}");
    assert!(steps.lines().all(|l| l.starts_with('{')), "{steps}");
    let run = std::fs::read_to_string(&trace).unwrap();
    assert_eq!(run.lines().count(), 1, "{run}");
}
