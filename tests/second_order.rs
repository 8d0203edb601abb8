//! Second-order elements: mid-edge nodes on the input's arcs and circles
//! (within 1e-9, halfway in angle), at the middle of every other edge,
//! centre nodes where the 8-node map puts them, and the element types of
//! each format.

use std::path::PathBuf;
use std::process::{Command, Output};

fn freemesh(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_freemesh"))
        .args(args)
        .output()
        .expect("the binary runs")
}

fn tmp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("freemesh-order-tests-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

type P = [f64; 2];

struct Mesh {
    nodes: Vec<P>,
    quads: Vec<Vec<usize>>,
    elements: Vec<Vec<usize>>,
    boundary: Vec<(usize, usize)>,
}

fn mesh(domain: &str, extra: &[&str], stem: &str) -> Mesh {
    let out = tmp(&format!("{stem}.json"));
    let mut args = vec!["mesh", domain, "-o", out.to_str().unwrap()];
    args.extend(extra);
    let o = freemesh(&args);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
    let ids = |q: &serde_json::Value| -> Vec<usize> {
        q.as_array()
            .unwrap()
            .iter()
            .map(|n| n.as_u64().unwrap() as usize)
            .collect()
    };
    Mesh {
        nodes: v["nodes"]
            .as_array()
            .unwrap()
            .iter()
            .map(|p| [p[0].as_f64().unwrap(), p[1].as_f64().unwrap()])
            .collect(),
        quads: v["quads"].as_array().unwrap().iter().map(ids).collect(),
        elements: v["elements"].as_array().unwrap().iter().map(ids).collect(),
        boundary: v["boundary"]
            .as_array()
            .unwrap()
            .iter()
            .map(|e| {
                let n = ids(&e["nodes"]);
                (n[0], n[1])
            })
            .collect(),
    }
}

fn dist(a: P, b: P) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)).sqrt()
}

fn middle(a: P, b: P) -> P {
    [(a[0] + b[0]) / 2.0, (a[1] + b[1]) / 2.0]
}

/// The circles of tests/inputs/dxf/bracket.json (arcs and round holes), as
/// centre and radius.
const BRACKET_CIRCLES: [(P, f64); 5] = [
    ([60.0, 30.0], 20.0), // the rounded corner
    ([30.0, 50.0], 30.0), // the top
    ([30.0, 50.0], 8.0),  // the bore
    ([55.0, 16.0], 4.0),  // the slot's ends
    ([70.0, 16.0], 4.0),
];

/// Checks every element edge's mid node: on the circle (within 1e-9) and
/// as far from both ends (halfway in angle) where the edge is a boundary
/// edge with both ends on one of `circles`; the chord's middle anywhere
/// else. Returns the number of edges found on circles.
fn check_middles(m: &Mesh, circles: &[(P, f64)]) -> usize {
    let boundary: std::collections::HashSet<(usize, usize)> = m
        .boundary
        .iter()
        .map(|&(a, b)| (a.min(b), a.max(b)))
        .collect();
    let mut on_arcs = 0;
    for (q, row) in m.quads.iter().zip(&m.elements) {
        assert_eq!(&row[..4], &q[..]);
        for k in 0..4 {
            let (a, b) = (q[k], q[(k + 1) % 4]);
            let (pa, pb, pm) = (m.nodes[a], m.nodes[b], m.nodes[row[4 + k]]);
            let round = boundary.contains(&(a.min(b), a.max(b))).then(|| {
                circles.iter().find(|(c, r)| {
                    (dist(pa, *c) - r).abs() < 1e-9 && (dist(pb, *c) - r).abs() < 1e-9
                })
            });
            match round.flatten() {
                Some((c, r)) => {
                    on_arcs += 1;
                    assert!((dist(pm, *c) - r).abs() < 1e-9, "middle {pm:?} off its arc");
                    assert!((dist(pm, pa) - dist(pm, pb)).abs() < 1e-9);
                    // on the edge's side of the centre, not across
                    assert!(dist(pm, middle(pa, pb)) < dist(pa, pb));
                }
                None => assert!(dist(pm, middle(pa, pb)) < 1e-12, "edge {a}-{b}"),
            }
        }
    }
    on_arcs
}

#[test]
fn mid_edge_nodes_lie_on_the_arcs_and_circles_within_1e_9() {
    let m = mesh(
        "tests/inputs/dxf/bracket.json",
        &["--order", "2"],
        "bracket-8",
    );
    assert!(m.elements.iter().all(|e| e.len() == 8));
    let on_arcs = check_middles(&m, &BRACKET_CIRCLES);
    // the arcs' lengths over size 2.5: 12.6, 37.7, 20.1 and twice 5.0
    assert!(on_arcs >= 70, "{on_arcs} edges on arcs");
    // each edge has one middle, shared by its elements
    let edges: std::collections::HashSet<(usize, usize)> = m
        .quads
        .iter()
        .flat_map(|q| (0..4).map(move |k| (q[k].min(q[(k + 1) % 4]), q[k].max(q[(k + 1) % 4]))))
        .collect();
    let corners = m.quads.iter().flatten().max().unwrap() + 1;
    assert_eq!(m.nodes.len(), corners + edges.len());
}

#[test]
fn nine_node_elements_have_their_centre_where_the_eight_node_map_puts_it() {
    let m = mesh(
        "tests/inputs/plate-hole.json",
        &["--order", "2", "--serendipity", "false"],
        "plate-hole-9",
    );
    assert!(check_middles(&m, &[([3.0, 2.0], 0.8)]) >= 6);
    for row in &m.elements {
        assert_eq!(row.len(), 9);
        let sum = |ids: &[usize]| {
            ids.iter()
                .map(|&n| m.nodes[n])
                .fold([0.0, 0.0], |s, p| [s[0] + p[0], s[1] + p[1]])
        };
        let (c, e) = (sum(&row[..4]), sum(&row[4..8]));
        let want = [-0.25 * c[0] + 0.5 * e[0], -0.25 * c[1] + 0.5 * e[1]];
        assert!(dist(m.nodes[row[8]], want) < 1e-12);
    }
}

/// The distinct cell types of a legacy VTK file: the `CELL_TYPES n`
/// section's n lines (a cell array, such as a mesh in blocks' `block`,
/// may follow them).
fn cell_types(vtk: &str) -> Vec<String> {
    let mut lines = vtk.lines().skip_while(|l| !l.starts_with("CELL_TYPES"));
    let n: usize = lines
        .next()
        .and_then(|l| l.split_whitespace().nth(1))
        .and_then(|n| n.parse().ok())
        .expect("a CELL_TYPES section");
    let mut types: Vec<String> = lines.take(n).map(str::to_string).collect();
    assert_eq!(types.len(), n, "CELL_TYPES {n} lists {}", types.len());
    types.sort();
    types.dedup();
    types
}

#[test]
fn each_format_names_the_second_order_element_type() {
    let (msh, vtk) = (tmp("ring-8.msh"), tmp("ring-8.vtk"));
    let o = freemesh(&[
        "mesh",
        "tests/inputs/plate-hole.json",
        "--order",
        "2",
        "-o",
        msh.to_str().unwrap(),
        "-o",
        vtk.to_str().unwrap(),
    ]);
    assert!(o.status.success());
    let msh_text = std::fs::read_to_string(&msh).unwrap();
    // the quads' block is of type 16, the boundary lines' of type 8
    assert!(msh_text.contains("\n2 1 16 "), "no quad8 block");
    assert!(msh_text.contains("\n1 1 8 ") && msh_text.contains("\n1 2 8 "));
    let vtk_text = std::fs::read_to_string(&vtk).unwrap();
    assert_eq!(cell_types(&vtk_text), ["23"]);
    let o = freemesh(&[
        "mesh",
        "tests/inputs/plate-hole.json",
        "--order",
        "2",
        "--serendipity",
        "false",
        "-o",
        msh.to_str().unwrap(),
        "-o",
        vtk.to_str().unwrap(),
    ]);
    assert!(o.status.success());
    assert!(std::fs::read_to_string(&msh).unwrap().contains("\n2 1 10 "));
    let vtk_text = std::fs::read_to_string(&vtk).unwrap();
    assert_eq!(cell_types(&vtk_text), ["28"]);
}

#[test]
fn serendipity_without_order_two_is_refused() {
    let out = tmp("refused.msh");
    let o = freemesh(&[
        "mesh",
        "tests/inputs/square.json",
        "--serendipity",
        "false",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(1));
    assert_eq!(
        String::from_utf8_lossy(&o.stderr).trim(),
        "error: --serendipity is for second-order elements: give --order 2 with it"
    );
    assert!(!out.exists());
}
