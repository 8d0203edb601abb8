//! DXF outlines in: a drawing made by an outside program (ezdxf, see
//! tests/inputs/dxf/bracket.py) read into the domain typed by hand, meshed to
//! the same mesh, converted to a domain file; the errors.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use freemesh::read_dxf;

fn freemesh(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_freemesh"))
        .args(args)
        .output()
        .expect("the binary runs")
}

fn tmp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("freemesh-dxf-tests-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn read_json(path: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// Asserts two JSON values equal, numbers within `tol`; `at` says where.
fn assert_json_near(got: &serde_json::Value, want: &serde_json::Value, tol: f64, at: &str) {
    use serde_json::Value;
    match (got, want) {
        (Value::Number(a), Value::Number(b)) => {
            let (a, b) = (a.as_f64().unwrap(), b.as_f64().unwrap());
            assert!((a - b).abs() <= tol, "{at}: {a} != {b}");
        }
        (Value::Array(a), Value::Array(b)) => {
            assert_eq!(a.len(), b.len(), "{at}: lengths differ");
            for (i, (x, y)) in a.iter().zip(b).enumerate() {
                assert_json_near(x, y, tol, &format!("{at}[{i}]"));
            }
        }
        (Value::Object(a), Value::Object(b)) => {
            let keys = |m: &serde_json::Map<String, Value>| m.keys().cloned().collect::<Vec<_>>();
            assert_eq!(keys(a), keys(b), "{at}: keys differ");
            for (k, x) in a {
                assert_json_near(x, &b[k], tol, &format!("{at}.{k}"));
            }
        }
        _ => assert_eq!(got, want, "{at}"),
    }
}

#[test]
fn the_ezdxf_drawing_reads_as_the_domain_typed_by_hand() {
    let outline = read_dxf(Path::new("tests/inputs/dxf/bracket.dxf")).unwrap();
    let got = outline.domain_file("bracket", 2.5, None).to_json_value();
    let want = read_json(Path::new("tests/inputs/dxf/bracket.json"));
    // the arcs' ends are computed from their angles: within rounding
    assert_json_near(&got, &want, 1e-12, "domain");
    // the TEXT label is skipped, and said so
    assert_eq!(outline.warnings.len(), 1, "{:?}", outline.warnings);
    assert!(
        outline.warnings[0].contains("skipped 1 TEXT"),
        "{:?}",
        outline.warnings
    );
    // the drawing spans 80 units: points join within 8e-5
    assert!((outline.tolerance - 80.0 * 1e-6).abs() < 1e-12);
}

/// Nodes and quads of a mesh written as JSON.
fn mesh_of(path: &Path) -> (Vec<[f64; 2]>, Vec<[u64; 4]>) {
    let v = read_json(path);
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
        .map(|q| std::array::from_fn(|i| q[i].as_u64().unwrap()))
        .collect();
    (nodes, quads)
}

#[test]
fn the_dxf_meshes_to_the_same_mesh_as_the_json_domain() {
    let (from_dxf, from_json) = (tmp("bracket-dxf.json"), tmp("bracket-json.json"));
    let o = freemesh(&[
        "mesh",
        "tests/inputs/dxf/bracket.dxf",
        "--size",
        "2.5",
        "-o",
        from_dxf.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    // the skipped label is a warning, the tags no unknown keys
    assert!(stderr(&o).contains("warning: tests/inputs/dxf/bracket.dxf: skipped 1 TEXT"));
    assert!(!stderr(&o).contains("unknown keys"), "{}", stderr(&o));
    let o = freemesh(&[
        "mesh",
        "tests/inputs/dxf/bracket.json",
        "-o",
        from_json.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let (nodes_a, quads_a) = mesh_of(&from_dxf);
    let (nodes_b, quads_b) = mesh_of(&from_json);
    assert!(quads_a.len() > 500, "{} quads", quads_a.len());
    assert_eq!(quads_a, quads_b);
    assert_eq!(nodes_a.len(), nodes_b.len());
    for (i, (a, b)) in nodes_a.iter().zip(&nodes_b).enumerate() {
        assert!(
            (a[0] - b[0]).abs() < 1e-9 && (a[1] - b[1]).abs() < 1e-9,
            "node {i}: {a:?} != {b:?}"
        );
    }
}

#[test]
fn convert_writes_the_domain_file_of_a_drawing() {
    let out = tmp("converted.json");
    let o = freemesh(&[
        "convert",
        "tests/inputs/dxf/bracket.dxf",
        "--size",
        "2.5",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("outer loop of 6 edges, 2 holes, 1 lines"),
        "{}",
        stderr(&o)
    );
    let want = read_json(Path::new("tests/inputs/dxf/bracket.json"));
    assert_json_near(&read_json(&out), &want, 1e-12, "converted");
    // pretty, in the format's order of keys
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(
        text.starts_with("{\n  \"name\": \"bracket\",\n  \"size\": 2.5,\n  \"outer\""),
        "{text}"
    );
}

#[test]
fn a_drawing_without_a_size_is_refused_in_one_line() {
    for cmd in ["mesh", "convert"] {
        let out = tmp(&format!("nosize-{cmd}.json"));
        let o = freemesh(&[
            cmd,
            "tests/inputs/dxf/bracket.dxf",
            "-o",
            out.to_str().unwrap(),
        ]);
        assert_eq!(o.status.code(), Some(1));
        assert_eq!(
            stderr(&o).trim(),
            "error: tests/inputs/dxf/bracket.dxf: a DXF drawing gives no element size: give one with --size H (the boundary segment length)"
        );
        assert!(!out.exists());
    }
}

/// A minimal ASCII DXF of LINE entities (the ENTITIES section alone, as
/// small exporters write it).
fn lines_dxf(lines: &[[f64; 4]]) -> String {
    let mut s = String::from("0\nSECTION\n2\nENTITIES\n");
    for l in lines {
        s.push_str(&format!(
            "0\nLINE\n8\nwall\n10\n{}\n20\n{}\n30\n0\n11\n{}\n21\n{}\n31\n0\n",
            l[0], l[1], l[2], l[3]
        ));
    }
    s.push_str("0\nENDSEC\n0\nEOF\n");
    s
}

#[test]
fn an_outline_that_does_not_close_names_the_gap() {
    let path = tmp("open.dxf");
    // a 10 x 5 rectangle whose left side stops 0.01 short of the corner
    let text = lines_dxf(&[
        [0.0, 0.0, 10.0, 0.0],
        [10.0, 0.0, 10.0, 5.0],
        [10.0, 5.0, 0.0, 5.0],
        [0.0, 5.0, 0.0, 0.01],
    ]);
    std::fs::write(&path, text).unwrap();
    let out = tmp("open.msh");
    let o = freemesh(&[
        "mesh",
        path.to_str().unwrap(),
        "--size",
        "1",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(1));
    let err = stderr(&o);
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(
        err.contains("the outline does not close: a gap between (0, 0) and (0, 0.01), 1.000000e-2 apart (end points join within 1.000e-5)"),
        "{err}"
    );
    assert!(!out.exists());
}

#[test]
fn a_closed_minimal_drawing_meshes() {
    let path = tmp("closed.dxf");
    std::fs::write(
        &path,
        lines_dxf(&[
            [0.0, 0.0, 4.0, 0.0],
            [4.0, 0.0, 4.0, 4.0],
            [4.0, 4.0, 0.0, 4.0],
            [0.0, 4.0, 0.0, 0.0],
        ]),
    )
    .unwrap();
    let out = tmp("closed.json");
    let o = freemesh(&[
        "mesh",
        path.to_str().unwrap(),
        "--size",
        "1",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(mesh_of(&out).1.len(), 16);
}

#[test]
fn a_file_that_is_not_dxf_is_refused_in_one_line() {
    let path = tmp("garbage.dxf");
    std::fs::write(&path, "this is not a drawing\n").unwrap();
    let o = freemesh(&[
        "convert",
        path.to_str().unwrap(),
        "--size",
        "1",
        "-o",
        tmp("g.json").to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(1));
    let err = stderr(&o);
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(
        err.starts_with("error: ") && err.contains("garbage.dxf"),
        "{err}"
    );
}

#[test]
fn features_reads_a_drawing_too() {
    let o = freemesh(&["features", "tests/inputs/dxf/bracket.dxf", "--size", "2.5"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(text.starts_with("nodes: id x y angle concave\n"), "{text}");
    assert!(text.contains("concave"), "the weld line's ends are reflex");
}
