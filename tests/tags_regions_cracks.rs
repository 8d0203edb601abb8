//! Domain format 1.1 in the mesher and the writers: edge tags as named
//! groups, lines that end on a loop or on each other (partitions,
//! T-junctions) with a region a part, and cracks cut open.

use std::collections::HashMap;
use std::path::PathBuf;
use std::process::Command;

use freemesh::{mesh_domain, Domain, KnowledgeBase, Mesh, Options};
use glam::DVec2;

fn mesh_of(path: &str) -> Mesh {
    let domain = Domain::from_file(path).expect("a valid test domain");
    let mut kb = KnowledgeBase::builtin().expect("the built-in KB loads");
    mesh_domain(&domain, &mut kb, &Options::default(), &mut |_| {})
        .expect("the test domain meshes")
        .mesh
}

fn tmp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("freemesh-1-1-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

fn centroid(m: &Mesh, q: usize) -> DVec2 {
    m.quad_points(q).iter().sum::<DVec2>() / 4.0
}

fn polygon_area(p: &[DVec2]) -> f64 {
    (0..p.len())
        .map(|i| p[i].perp_dot(p[(i + 1) % p.len()]))
        .sum::<f64>()
        / 2.0
}

/// The area of each region's quads.
fn region_areas(m: &Mesh) -> Vec<f64> {
    let mut out = vec![0.0; m.region_count() as usize];
    for q in 0..m.quads().len() {
        out[m.regions()[q] as usize] += polygon_area(&m.quad_points(q));
    }
    out
}

/// The boundary edges of the group named `name`, as point pairs.
fn group(m: &Mesh, name: &str) -> Vec<(DVec2, DVec2)> {
    let g = m
        .groups()
        .iter()
        .position(|x| x == name)
        .expect("the group exists");
    m.group_edges()[g]
        .iter()
        .map(|&(a, b)| (m.nodes()[a as usize], m.nodes()[b as usize]))
        .collect()
}

/// A Gmsh MSH 4.1 file read back: each physical group's name with the
/// node pairs (line elements) or node lists (quads) of its entities.
fn read_msh_groups(text: &str) -> HashMap<String, Vec<Vec<DVec2>>> {
    let section = |name: &str| -> Vec<&str> {
        let start = text.find(&format!("${name}\n")).expect("the section") + name.len() + 2;
        let end = text[start..].find(&format!("$End{name}")).unwrap() + start;
        text[start..end].lines().collect()
    };
    let nums = |l: &str| -> Vec<f64> { l.split_whitespace().map(|x| x.parse().unwrap()).collect() };
    let mut names: HashMap<(usize, usize), String> = HashMap::new();
    for l in &section("PhysicalNames")[1..] {
        let (dim_tag, name) = l.split_at(l.find('"').unwrap());
        let v = nums(dim_tag);
        names.insert(
            (v[0] as usize, v[1] as usize),
            name.trim_matches('"').to_string(),
        );
    }
    // entity (dim, tag) -> its physical tags
    let ents = section("Entities");
    let counts = nums(ents[0]);
    let mut physical: HashMap<(usize, usize), Vec<usize>> = HashMap::new();
    for (k, l) in ents[1..].iter().enumerate() {
        let dim = if k < counts[1] as usize { 1 } else { 2 };
        let v = nums(l);
        let n = v[7] as usize;
        physical.insert(
            (dim, v[0] as usize),
            v[8..8 + n].iter().map(|&t| t as usize).collect(),
        );
    }
    let nodes_sec = section("Nodes");
    let n = nums(nodes_sec[0])[1] as usize;
    let coords: Vec<DVec2> = nodes_sec[2 + n..2 + 2 * n]
        .iter()
        .map(|l| {
            let v = nums(l);
            DVec2::new(v[0], v[1])
        })
        .collect();
    let mut out: HashMap<String, Vec<Vec<DVec2>>> = HashMap::new();
    let els = section("Elements");
    let mut i = 1;
    while i < els.len() {
        let head = nums(els[i]);
        let (dim, ent, count) = (head[0] as usize, head[1] as usize, head[3] as usize);
        for l in &els[i + 1..i + 1 + count] {
            let pts: Vec<DVec2> = nums(l)[1..]
                .iter()
                .map(|&t| coords[t as usize - 1])
                .collect();
            for &p in &physical[&(dim, ent)] {
                out.entry(names[&(dim, p)].clone())
                    .or_default()
                    .push(pts.clone());
            }
        }
        i += 1 + count;
    }
    out
}

#[test]
fn tagged_edges_are_named_groups_in_the_msh_read_back() {
    let out = tmp("tagged.msh");
    let o = Command::new(env!("CARGO_BIN_EXE_freemesh"))
        .args(["mesh", "tests/partitions/tagged-plate.json", "-o"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    // tags, tag and crack are keys of the format: no warning
    assert!(!String::from_utf8_lossy(&o.stderr).contains("unknown"));
    let groups = read_msh_groups(&std::fs::read_to_string(&out).unwrap());
    // (a uniform run kept in blocks adds a group a block, `block K`:
    // tests/blocks.rs)
    let mut names: Vec<&str> = groups
        .keys()
        .map(String::as_str)
        .filter(|n| !n.starts_with("block "))
        .collect();
    names.sort_unstable();
    // `hole 1` has no edge left: the circle's edges are all `bore`
    assert_eq!(names, ["bore", "domain", "fixed", "load", "outer"]);
    let all = |name: &str, on: &dyn Fn(DVec2) -> bool| {
        groups[name]
            .iter()
            .all(|e| e.len() == 2 && e.iter().all(|&p| on(p)))
    };
    // bottom (x in 0..4, y = 0) and left (x = 0) edges are `fixed`
    assert!(all("fixed", &|p| p.x == 0.0 || p.y == 0.0));
    assert_eq!(groups["fixed"].len(), 16 + 8);
    assert!(all("load", &|p| p.x == 4.0));
    assert_eq!(groups["load"].len(), 8);
    // the untagged top edge stays in its loop's group, every segment of
    // it (its count is derived from the size: the blocks' interval
    // assignment may take one fewer than the free mesh's 16)
    assert!(all("outer", &|p| p.y == 2.0));
    let top_sides = groups["domain"]
        .iter()
        .flat_map(|q| (0..4).map(move |k| (q[k], q[(k + 1) % 4])))
        .filter(|(a, b)| a.y == 2.0 && b.y == 2.0)
        .count();
    assert!((15..=16).contains(&top_sides), "{top_sides}");
    assert_eq!(groups["outer"].len(), top_sides);
    assert!(all("bore", &|p| ((p - DVec2::new(1.5, 1.0)).length()
        - 0.4)
        .abs()
        < 1e-9));
    assert!(groups["domain"].iter().all(|q| q.len() == 4));
}

#[test]
fn the_json_and_vtk_outputs_carry_the_tags() {
    let (json, vtk) = (tmp("tagged.json"), tmp("tagged.vtk"));
    let o = Command::new(env!("CARGO_BIN_EXE_freemesh"))
        .args(["mesh", "tests/partitions/tagged-plate.json", "-o"])
        .arg(&json)
        .arg("-o")
        .arg(&vtk)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let loads: Vec<&serde_json::Value> = v["boundary"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|e| e["group"] == "load")
        .collect();
    assert_eq!(loads.len(), 8);
    assert!(loads.iter().all(|e| e["on"] == "outer"));
    let vtk = std::fs::read_to_string(&vtk).unwrap();
    let quads = v["quads"].as_array().unwrap().len();
    let edges = v["boundary"].as_array().unwrap().len();
    assert!(vtk.contains(&format!("CELL_DATA {}", quads + edges)));
    let load = vtk
        .split("SCALARS load int 1\nLOOKUP_TABLE default\n")
        .nth(1)
        .unwrap();
    let ones = load
        .lines()
        .take(quads + edges)
        .filter(|l| *l == "1")
        .count();
    assert_eq!(ones, 8);
}

#[test]
fn a_line_across_the_plate_parts_it_in_two_regions() {
    let m = mesh_of("tests/partitions/partition.json");
    assert_eq!(m.region_count(), 2);
    // each region lies on one side of the line (1.5, 0) -> (2.5, 2)
    let (a, b) = (DVec2::new(1.5, 0.0), DVec2::new(2.5, 2.0));
    let side = |q: usize| (b - a).perp_dot(centroid(&m, q) - a) > 0.0;
    for q in 0..m.quads().len() {
        assert_eq!(side(q), side(0) == (m.regions()[q] == m.regions()[0]));
    }
    let left = polygon_area(&[DVec2::ZERO, a, b, DVec2::new(0.0, 2.0)]);
    let mut areas = region_areas(&m);
    areas.sort_by(f64::total_cmp);
    let mut want = [left, 8.0 - left];
    want.sort_by(f64::total_cmp);
    assert!((areas[0] - want[0]).abs() < 1e-9 && (areas[1] - want[1]).abs() < 1e-9);
    // the line's edges are element edges, all in its tag's group
    let edges = group(&m, "interface");
    assert!(!edges.is_empty());
    for (p, q) in edges {
        assert!((b - a).perp_dot(p - a).abs() < 1e-9 && (b - a).perp_dot(q - a).abs() < 1e-9);
    }
}

#[test]
fn a_t_junction_gives_three_regions() {
    let m = mesh_of("tests/partitions/t-junction.json");
    assert_eq!(m.region_count(), 3);
    let mut areas = region_areas(&m);
    areas.sort_by(f64::total_cmp);
    for (got, want) in areas.iter().zip([2.0, 2.0, 4.0]) {
        assert!((got - want).abs() < 1e-9, "{areas:?}");
    }
    // the junction (2, 1) is one node, shared by the two lines
    let at = |p: DVec2| m.nodes().iter().filter(|&&n| n == p).count();
    assert_eq!(at(DVec2::new(2.0, 1.0)), 1);
}

#[test]
fn lines_that_meet_enclose_a_region_and_join_a_hole_without_a_cut() {
    let m = mesh_of("tests/partitions/lines-meet.json");
    assert_eq!(m.region_count(), 2);
    let triangle = polygon_area(&[
        DVec2::new(0.0, 0.5),
        DVec2::new(1.5, 1.5),
        DVec2::new(0.0, 2.5),
    ])
    .abs();
    let areas = region_areas(&m);
    assert!(
        areas.iter().any(|a| (a - triangle).abs() < 1e-9),
        "{areas:?}"
    );
}

#[test]
fn an_edge_crack_opens_with_two_nodes_at_each_point_but_the_tip() {
    let m = mesh_of("tests/partitions/edge-crack.json");
    let at = |p: DVec2| {
        m.nodes()
            .iter()
            .filter(|&&n| (n - p).length() < 1e-12)
            .count()
    };
    // the crack runs from (0, 1) on the outer loop to its tip at (2, 1)
    for k in 0..8 {
        assert_eq!(
            at(DVec2::new(k as f64 * 0.25, 1.0)),
            2,
            "x = {}",
            k as f64 * 0.25
        );
    }
    assert_eq!(at(DVec2::new(2.0, 1.0)), 1);
    // each face is a group; + is the side left of the line's direction
    let above = group(&m, "crack 1 +");
    let below = group(&m, "crack 1 -");
    assert_eq!((above.len(), below.len()), (8, 8));
    let nodes_of = |q: usize| m.quads()[q].to_vec();
    for q in 0..m.quads().len() {
        let c = centroid(&m, q);
        // no element above the crack shares a crack node with one below,
        // but at the tip
        if c.x < 2.0 && c.y > 1.0 {
            for r in 0..m.quads().len() {
                let d = centroid(&m, r);
                if d.x < 2.0 && d.y < 1.0 {
                    for n in nodes_of(q) {
                        let p = m.nodes()[n as usize];
                        if nodes_of(r).contains(&n) {
                            assert_eq!(p, DVec2::new(2.0, 1.0), "quads {q} and {r} share {p}");
                        }
                    }
                }
            }
        }
    }
    // a crack's faces are boundary: no region parts there, the tip holds
    assert_eq!(m.region_count(), 1);
}

#[test]
fn a_domain_without_the_new_keys_writes_no_new_groups() {
    let m = mesh_of("tests/inputs/plate-hole.json");
    assert_eq!(m.groups(), ["outer", "hole 1"]);
    assert_eq!(m.region_count(), 1);
    let msh = freemesh::render(&m, None, "plate", freemesh::Format::Msh);
    assert!(!msh.contains("region"));
    let vtk = freemesh::render(&m, None, "plate", freemesh::Format::Vtk);
    assert!(!vtk.contains("CELL_DATA"));
    let json = freemesh::render(&m, None, "plate", freemesh::Format::Json);
    assert!(!json.contains("regions"));
}

fn refusal(text: &str) -> String {
    let v: serde_json::Value = serde_json::from_str(text).unwrap();
    Domain::from_json(&v).expect_err("refused").to_string()
}

#[test]
fn bad_tags_cracks_and_junctions_are_refused_naming_the_fault() {
    let square = r#""size": 0.5, "outer": {"points": [[0,0],[4,0],[4,4],[0,4]]"#;
    let cases = [
        (
            format!(r#"{{{square}, "tags": ["a", "b"]}}}}"#),
            "outer.tags: expected 4 entries",
        ),
        (
            format!(r#"{{{square}, "tags": ["a", 3, "", null]}}}}"#),
            "outer.tags[1]: expected a string",
        ),
        (
            format!(r#"{{{square}, "crack": true}}}}"#),
            "outer.crack: only an inner line can be a crack",
        ),
        (
            format!(r#"{{{square}}}, "lines": [{{"points": [[1,1],[2,2]], "crack": "yes"}}]}}"#),
            "lines[0].crack: expected true or false",
        ),
        (
            format!(r#"{{{square}}}, "holes": [{{"circle": {{"center": [2,2], "radius": 1, "tag": 7}}}}]}}"#),
            "holes[0].circle.tag: expected a string",
        ),
        // a line that crosses the outer loop: still refused
        (
            format!(r#"{{{square}}}, "lines": [{{"points": [[2,2],[6,2]]}}]}}"#),
            "outer and lines[0] cross or touch",
        ),
        // a line along an edge of the loop
        (
            format!(r#"{{{square}}}, "lines": [{{"points": [[0,1],[0,3],[1,3]]}}]}}"#),
            "cross or touch",
        ),
        // a line that ends on the loop from outside
        (
            format!(r#"{{{square}}}, "lines": [{{"points": [[4,2],[6,2]]}}]}}"#),
            "lines[0] lies outside the outer loop",
        ),
        // two lines that cross other than at an end
        (
            format!(
                r#"{{{square}}}, "lines": [{{"points": [[1,1],[3,3]]}}, {{"points": [[1,3],[3,1]]}}]}}"#
            ),
            "lines[0] and lines[1] cross or touch",
        ),
        // a line ending in the middle of an edge with one fixed segment
        (
            r#"{"size": 0.5, "outer": {"points": [[0,0],[4,0],[4,4],[0,4]], "segments": [1,0,0,0]}, "lines": [{"points": [[2,0],[2,2]]}]}"#.to_string(),
            "lines[0] ends in the middle of outer edge 0",
        ),
    ];
    for (text, expect) in &cases {
        let got = refusal(text);
        assert!(
            got.contains(expect),
            "{text}\n  gave: {got}\n  want: {expect}"
        );
    }
}

#[test]
fn a_line_ending_on_a_loop_vertex_or_edge_is_accepted_as_a_corner_of_both() {
    let v: serde_json::Value = serde_json::from_str(
        r#"{"size": 0.5, "outer": {"points": [[0,0],[4,0],[4,4],[0,4]], "tags": ["b", "", "", ""]},
            "lines": [{"points": [[2,0],[2,2]]}, {"points": [[4,4],[3,3]]}]}"#,
    )
    .unwrap();
    let d = Domain::from_json(&v).unwrap();
    let mut kb = KnowledgeBase::builtin().unwrap();
    let m = mesh_domain(&d, &mut kb, &Options::default(), &mut |_| {})
        .unwrap()
        .mesh;
    // both ends are corners: nodes of the mesh
    assert!(m.nodes().contains(&DVec2::new(2.0, 0.0)));
    assert!(m.nodes().contains(&DVec2::new(4.0, 4.0)));
    // the bottom edge split at (2, 0), each half keeping the tag
    let bottom = group(&m, "b");
    let length: f64 = bottom.iter().map(|(p, q)| (*q - *p).length()).sum();
    assert!((length - 4.0).abs() < 1e-9, "{length}");
    assert!(bottom.iter().all(|(p, q)| p.y == 0.0 && q.y == 0.0));
}

#[test]
fn a_line_end_written_with_six_decimals_ends_on_the_edge_it_is_that_near() {
    // a T-junction and an end on a wall, each within 1e-6 of the scale
    let v: serde_json::Value = serde_json::from_str(
        r#"{"size": 0.181, "outer": {"points": [[0, 0], [5.12861015435538, 0], [5.12861015435538, 3.876251833281688], [0, 3.876251833281688]]},
            "lines": [{"points": [[1.799548, 0.0], [5.12861, 1.573744]]}, {"points": [[3.464079, 0.786872], [0.0, 1.889927]]}]}"#,
    )
    .unwrap();
    // the line ends snap onto the wall and onto the first line: three regions
    let d = Domain::from_json(&v).unwrap();
    let mut kb = KnowledgeBase::builtin().unwrap();
    let r = mesh_domain(&d, &mut kb, &Options::default(), &mut |_| {}).unwrap();
    assert_eq!(r.mesh.region_count(), 3);
}

/// A seeded generator (xorshift) for the random partitions below.
struct Rng(u64);

impl Rng {
    fn unit(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
    fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.unit()
    }
}

#[test]
fn random_partitions_cracks_and_t_junctions_mesh_into_their_regions() {
    for seed in 1..=12u64 {
        let mut rng = Rng(0x9e37_79b9_7f4a_7c15 ^ seed.wrapping_mul(0x2545_f491_4f6c_dd1d));
        let (w, h) = (rng.range(3.0, 6.0), rng.range(2.0, 4.0));
        let corners = [[0.0, 0.0], [w, 0.0], [w, h], [0.0, h]];
        // a point inside edge k of the rectangle, written with six decimals
        let mut on = |k: usize| {
            let (a, b) = (corners[k], corners[(k + 1) % 4]);
            let t = rng.range(0.25, 0.75);
            let r = |x: f64| (x * 1e6).round() / 1e6;
            [r(a[0] + (b[0] - a[0]) * t), r(a[1] + (b[1] - a[1]) * t)]
        };
        let (p, q) = (on(0), on(2));
        let kind = seed % 4;
        let (lines, regions) = match kind {
            // bottom to top: two regions
            0 => (serde_json::json!([{"points": [p, q]}]), 2),
            // a crack from the bottom edge to the middle: one region
            1 => (
                serde_json::json!([{"points": [p, [w / 2.0, h / 2.0]], "crack": true}]),
                1,
            ),
            // a T: bottom to top, and from its middle to the right edge
            2 => {
                let m = [(p[0] + q[0]) / 2.0, (p[1] + q[1]) / 2.0];
                (
                    serde_json::json!([{"points": [p, q]}, {"points": [m, on(1)]}]),
                    3,
                )
            }
            // two lines meeting inside, bottom to top
            _ => {
                let c = [w * rng.range(0.35, 0.65), h * rng.range(0.35, 0.65)];
                (
                    serde_json::json!([{"points": [p, c]}, {"points": [c, q]}]),
                    2,
                )
            }
        };
        let v = serde_json::json!({"size": rng.range(0.15, 0.3), "outer": {"points": corners}, "lines": lines});
        let domain = Domain::from_json(&v).unwrap_or_else(|e| panic!("seed {seed}: {e}\n{v}"));
        let mut kb = KnowledgeBase::builtin().unwrap();
        let r = mesh_domain(&domain, &mut kb, &Options::default(), &mut |_| {})
            .unwrap_or_else(|e| panic!("seed {seed}: {e}\n{v}"));
        let m = &r.mesh;
        assert_eq!(m.region_count(), regions, "seed {seed}: {v}");
        // (an edge a rounded end lands on bends by up to a millionth)
        let total: f64 = region_areas(m).iter().sum();
        assert!((total - w * h).abs() < 1e-6 * w * h, "seed {seed}: {total}");
        // every line segment is an element edge (a crack's, twice)
        let mut edges = std::collections::HashSet::new();
        for q in m.quads() {
            for k in 0..4 {
                edges.insert((q[k].min(q[(k + 1) % 4]), q[k].max(q[(k + 1) % 4])));
            }
        }
        assert!(
            m.boundary()
                .iter()
                .all(|e| edges.contains(&(e.a.min(e.b), e.a.max(e.b)))),
            "seed {seed}"
        );
    }
}
