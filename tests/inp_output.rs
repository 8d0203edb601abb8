//! Abaqus / CalculiX decks: the deck of a run holds the same nodes and
//! elements as its JSON mesh, and each boundary group's node set, element
//! set and surface hold exactly that group's edges.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn freemesh(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_freemesh"))
        .args(args)
        .output()
        .expect("the binary runs")
}

fn tmp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("freemesh-inp-tests-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

/// A deck read back: keyword lines with their data lines.
struct Deck {
    blocks: Vec<(String, Vec<Vec<String>>)>,
}

impl Deck {
    fn read(path: &Path) -> Deck {
        let text = std::fs::read_to_string(path).unwrap();
        let mut blocks: Vec<(String, Vec<Vec<String>>)> = Vec::new();
        for line in text.lines() {
            if line.starts_with("**") {
                continue;
            }
            if line.starts_with('*') {
                blocks.push((line.to_string(), Vec::new()));
            } else {
                let fields = line.split(',').map(|f| f.trim().to_string()).collect();
                blocks
                    .last_mut()
                    .expect("data after a keyword")
                    .1
                    .push(fields);
            }
        }
        Deck { blocks }
    }

    fn block(&self, keyword: &str) -> &[Vec<String>] {
        &self
            .blocks
            .iter()
            .find(|b| b.0 == keyword)
            .unwrap_or_else(|| panic!("no {keyword}"))
            .1
    }

    /// The ids of a set, 0-based.
    fn set(&self, keyword: &str) -> BTreeSet<usize> {
        self.block(keyword)
            .iter()
            .flatten()
            .map(|s| s.parse::<usize>().unwrap() - 1)
            .collect()
    }
}

struct JsonMesh {
    nodes: Vec<[f64; 2]>,
    quads: Vec<Vec<usize>>,
    elements: Option<Vec<Vec<usize>>>,
    /// group -> boundary edges
    groups: BTreeMap<String, Vec<(usize, usize)>>,
}

fn json_mesh(path: &Path) -> JsonMesh {
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    let ids = |q: &serde_json::Value| -> Vec<usize> {
        q.as_array()
            .unwrap()
            .iter()
            .map(|n| n.as_u64().unwrap() as usize)
            .collect()
    };
    let mut groups: BTreeMap<String, Vec<(usize, usize)>> = BTreeMap::new();
    for e in v["boundary"].as_array().unwrap() {
        let n = ids(&e["nodes"]);
        groups
            .entry(e["group"].as_str().unwrap().to_string())
            .or_default()
            .push((n[0], n[1]));
    }
    JsonMesh {
        nodes: v["nodes"]
            .as_array()
            .unwrap()
            .iter()
            .map(|p| [p[0].as_f64().unwrap(), p[1].as_f64().unwrap()])
            .collect(),
        quads: v["quads"].as_array().unwrap().iter().map(ids).collect(),
        elements: v
            .get("elements")
            .map(|e| e.as_array().unwrap().iter().map(ids).collect()),
        groups,
    }
}

fn run(domain: &str, extra: &[&str], stem: &str) -> (Deck, JsonMesh) {
    let (inp, json) = (tmp(&format!("{stem}.inp")), tmp(&format!("{stem}.json")));
    let mut args = vec![
        "mesh",
        domain,
        "-o",
        inp.to_str().unwrap(),
        "-o",
        json.to_str().unwrap(),
    ];
    args.extend(extra);
    let o = freemesh(&args);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    (Deck::read(&inp), json_mesh(&json))
}

/// The nodes and faces of each element: face k joins corners k and k+1.
fn face_nodes(q: &[usize], face: usize) -> (usize, usize) {
    let (a, b) = (q[face - 1], q[face % 4]);
    (a.min(b), a.max(b))
}

fn check_deck(deck: &Deck, mesh: &JsonMesh, element_type: &str, per: usize) {
    // nodes: the same coordinates, numbered from 1
    let nodes = deck.block("*NODE, NSET=NALL");
    assert_eq!(nodes.len(), mesh.nodes.len());
    for (i, n) in nodes.iter().enumerate() {
        assert_eq!(n[0], (i + 1).to_string());
        let (x, y): (f64, f64) = (n[1].parse().unwrap(), n[2].parse().unwrap());
        // serde_json reads floats to within an ulp, not always exactly
        let [u, v] = mesh.nodes[i];
        assert!(
            (x - u).abs() <= 1e-15 * (1.0 + u.abs()) && (y - v).abs() <= 1e-15 * (1.0 + v.abs()),
            "node {}: ({x}, {y}) != ({u}, {v})",
            i + 1
        );
    }
    // elements: the JSON's, numbered from 1
    let elements = deck.block(&format!("*ELEMENT, TYPE={element_type}, ELSET=EALL"));
    assert_eq!(elements.len(), mesh.quads.len());
    for (i, e) in elements.iter().enumerate() {
        assert_eq!(e.len(), per + 1);
        let ids: Vec<usize> = e[1..]
            .iter()
            .map(|s| s.parse::<usize>().unwrap() - 1)
            .collect();
        let want = match &mesh.elements {
            Some(rows) => &rows[i],
            None => &mesh.quads[i],
        };
        assert_eq!(&ids, want, "element {}", i + 1);
    }
    // each group: its edges' nodes (with their middles), the elements
    // on them, each of their faces on the group
    for (group, edges) in &mesh.groups {
        let label = group.replace(' ', "_");
        let edge_set: BTreeSet<(usize, usize)> =
            edges.iter().map(|&(a, b)| (a.min(b), a.max(b))).collect();
        let mut want_nodes: BTreeSet<usize> = edges.iter().flat_map(|&(a, b)| [a, b]).collect();
        if let Some(rows) = &mesh.elements {
            for (q, row) in rows.iter().enumerate() {
                for k in 0..4 {
                    if edge_set.contains(&face_nodes(&mesh.quads[q], k + 1)) {
                        want_nodes.insert(row[4 + k]);
                    }
                }
            }
        }
        assert_eq!(
            deck.set(&format!("*NSET, NSET={label}")),
            want_nodes,
            "{group}"
        );
        let faces = deck.block(&format!("*SURFACE, NAME={label}_S, TYPE=ELEMENT"));
        let mut covered = BTreeSet::new();
        let mut on_group = BTreeSet::new();
        for f in faces {
            let e: usize = f[0].parse::<usize>().unwrap() - 1;
            let face: usize = f[1].strip_prefix('S').unwrap().parse().unwrap();
            let edge = face_nodes(&mesh.quads[e], face);
            assert!(
                edge_set.contains(&edge),
                "{group}: face S{face} of element {} is not on it",
                e + 1
            );
            covered.insert(edge);
            on_group.insert(e);
        }
        assert_eq!(covered, edge_set, "{group}: every edge is a face");
        assert_eq!(
            deck.set(&format!("*ELSET, ELSET={label}")),
            on_group,
            "{group}"
        );
    }
}

#[test]
fn the_deck_holds_the_mesh_and_a_set_and_surface_per_group() {
    let (deck, mesh) = run("tests/inputs/plate-hole.json", &[], "plate-hole");
    assert_eq!(mesh.groups.keys().collect::<Vec<_>>(), ["hole 1", "outer"]);
    check_deck(&deck, &mesh, "CPS4", 4);
}

#[test]
fn an_inner_line_is_a_surface_of_the_faces_on_both_sides() {
    let domain = tmp("plate-line-domain.json");
    std::fs::write(
        &domain,
        r#"{"size": 0.5, "outer": {"points": [[0, 0], [6, 0], [6, 4], [0, 4]]},
            "lines": [{"points": [[1, 1], [3, 1], [3, 3]]}]}"#,
    )
    .unwrap();
    let (deck, mesh) = run(domain.to_str().unwrap(), &[], "plate-line");
    check_deck(&deck, &mesh, "CPS4", 4);
    let faces = deck.block("*SURFACE, NAME=line_1_S, TYPE=ELEMENT");
    assert_eq!(faces.len(), 2 * mesh.groups["line 1"].len());
}

#[test]
fn second_order_decks_have_cps8_and_s9r5_elements_with_middles_in_the_sets() {
    let (deck, mesh) = run(
        "tests/inputs/plate-hole.json",
        &["--order", "2"],
        "plate-hole-8",
    );
    check_deck(&deck, &mesh, "CPS8", 8);
    let (deck, mesh) = run(
        "tests/inputs/plate-hole.json",
        &["--order", "2", "--serendipity", "false"],
        "plate-hole-9",
    );
    check_deck(&deck, &mesh, "S9R5", 9);
}

#[test]
fn a_parted_domain_has_an_element_set_a_region_as_the_json_has_them() {
    let (inp, json) = (tmp("partition.inp"), tmp("partition.json"));
    let out = freemesh(&[
        "mesh",
        "tests/partitions/partition.json",
        "-o",
        inp.to_str().unwrap(),
        "-o",
        json.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let deck = Deck::read(&inp);
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let regions: Vec<u64> = v["regions"]
        .as_array()
        .expect("two regions in the JSON")
        .iter()
        .map(|r| r.as_u64().unwrap())
        .collect();
    for r in 1..=2u64 {
        let want: BTreeSet<usize> = (0..regions.len()).filter(|&q| regions[q] == r).collect();
        assert!(!want.is_empty());
        assert_eq!(deck.set(&format!("*ELSET, ELSET=region_{r}")), want);
    }
}
