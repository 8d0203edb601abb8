//! Thin walls (src/input/thin_walls.rs): edges facing each other across a
//! wall thinner than `bound(thin_wall, 2)` element sizes get one segment
//! count, and the rules fill the wall with one structured row; a KB that
//! sets the bound to 0 switches it off.

use freemesh::{mesh_domain, Domain, KnowledgeBase, MeshResult, Options};

/// A tube of wall `t` at size 0.1: circles of radius 1 and 1 - t, each
/// three arcs of 120 degrees.
fn tube(t: f64) -> Domain {
    let ring = |r: f64| {
        let p: Vec<String> = (0..3)
            .map(|k| {
                let a = k as f64 * 2.0 * std::f64::consts::PI / 3.0;
                format!("[{}, {}]", r * a.cos(), r * a.sin())
            })
            .collect();
        format!(
            "{{\"points\": [{}], \"bulges\": [0.57735, 0.57735, 0.57735]}}",
            p.join(", ")
        )
    };
    Domain::from_json_str(&format!(
        "{{\"size\": 0.1, \"outer\": {}, \"holes\": [{}]}}",
        ring(1.0),
        ring(1.0 - t)
    ))
    .unwrap()
}

fn mesh(domain: &Domain, kb_file: Option<&str>) -> MeshResult {
    let mut kb = KnowledgeBase::builtin().unwrap();
    if let Some(f) = kb_file {
        kb.consult_file(f).unwrap();
    }
    mesh_domain(domain, &mut kb, &Options::default(), &mut |_| {}).unwrap()
}

#[test]
fn a_tube_thinner_than_two_elements_is_one_row_of_near_rectangles() {
    // 0.14 thick: 21 segments an arc outside, 18 inside, unless matched
    // (their mean length over the size: 19)
    let r = mesh(&tube(0.14), None);
    assert_eq!(r.stats.thin_wall_edges, 6);
    // one row: as many quads as segments round one circle
    assert_eq!(r.mesh.quads().len(), 57);
    let q = &r.quality;
    assert!(q.min_angle > 80.0 && q.max_angle < 100.0, "{q:?}");
}

#[test]
fn a_kb_that_sets_thin_wall_to_0_keeps_each_circles_count() {
    let r = mesh(&tube(0.14), Some("tests/kb/no-thin-walls.pl"));
    assert_eq!(r.stats.thin_wall_edges, 0);
    // 63 segments outside, 54 inside: a transition squeezed into the wall
    assert_ne!(r.mesh.quads().len(), 57);
    assert!(r.quality.max_angle > 100.0, "{:?}", r.quality);
}

#[test]
fn a_thick_tube_and_a_channels_short_ends_are_left_alone() {
    // half a unit thick: five sizes, no wall
    assert_eq!(mesh(&tube(0.5), None).stats.thin_wall_edges, 0);
    // a C of wall 0.13: the flanges and the web face their inner sides
    // (6 edges); the two ends of the flanges face nothing
    let c = Domain::from_json_str(
        r#"{"size": 0.1, "outer": {"points": [[0,0],[2,0],[2,0.13],[0.13,0.13],[0.13,1.07],[2,1.07],[2,1.2],[0,1.2]]}}"#,
    )
    .unwrap();
    let r = mesh(&c, None);
    assert_eq!(r.stats.thin_wall_edges, 6);
    // the corners of the C: 45 and 135 (a hair either way in floating point)
    let q = &r.quality;
    assert!(
        q.min_angle > 45.0 - 1e-9 && q.max_angle < 135.0 + 1e-9,
        "{q:?}"
    );
}

/// A V-shaped wall one segment thick whose sides have unequal fixed
/// counts (8 against 25 segments along one leg, 6 against 7 along the
/// other; a random domain of the wall family): the elements where the
/// counts change are closed by six-segment patterns, and smoothing once
/// slid their centre node onto a boundary node, an edge of 0.004 beside
/// edges of 24 between two corners of 90 (taper 6,424: convex, every
/// corner in the window). Smoothing no longer takes an element's aspect
/// or taper past the bounds for a corner, nor a closing pattern puts an
/// edge of nothing.
#[test]
fn smoothing_does_not_slide_a_node_onto_its_neighbour_in_a_thin_wall() {
    let d = Domain::from_json_str(
        &std::fs::read_to_string("tests/walls/v-wall-unequal-counts.json").unwrap(),
    )
    .unwrap();
    let mut kb = KnowledgeBase::builtin().unwrap();
    let r = freemesh::mesh_free_then_blocks(&d, None, &mut kb, &Options::default(), &mut |_| {})
        .unwrap();
    let q = &r.quality;
    assert!(q.max_taper < 20.0 && q.max_aspect < 20.0, "{q:?}");
    let shortest = r
        .mesh
        .quads()
        .iter()
        .flat_map(|e| (0..4).map(move |i| (e[i], e[(i + 1) % 4])))
        .map(|(a, b)| (r.mesh.nodes()[a as usize] - r.mesh.nodes()[b as usize]).length())
        .fold(f64::INFINITY, f64::min);
    assert!(shortest > 0.05 * d.size(), "shortest edge {shortest}");
}
