//! Sharp kinds of boundary (issue 15): tips of the domain down to a cusp
//! of 0 deg, and notches of nearly 360 deg.
//!
//! - The rules answer every context with a sound action: a tip (a corner
//!   below `bound(tip_corner, _)`) is taken whole by one element, never
//!   given b2's parallelogram, whose corners 180 - theta1 reach 180.
//! - A domain with a spike of 11.4 deg and a slit-like notch of 350 deg
//!   is meshed by the rules (no last resort) with every corner in
//!   [the spike's, 135] and aspect, taper and size jump within the
//!   paper's bounds.
//! - A notch of 359 deg where an arc leaves a corner almost backwards
//!   along the line before it is meshed within the bounds; an arc that
//!   leaves it so and crosses back over the line is refused as input.

use freemesh::{mesh_domain, Domain, KnowledgeBase, Options, UserAnswer};

/// The bindings of the first answer, or the error.
fn first_answer(kb: &mut KnowledgeBase, text: &str) -> Result<Vec<(String, String)>, String> {
    let mut out = Err("no answer (false)".to_string());
    kb.user_query(text, 200_000_000, &mut |a| {
        out = match a {
            UserAnswer::Bindings(b, _) => Ok(b),
            UserAnswer::Error(e) => Err(e),
        };
        false
    });
    out
}

#[test]
fn every_context_gets_a_sound_action_and_a_tip_a_kite() {
    let mut kb = KnowledgeBase::builtin().unwrap();
    // a context whose design is unsound, if any: angles over the whole
    // turn at N1 and N2, tips, corners, open and reflex neighbours
    let unsound = "Ts = [0, 1, 5, 30, 44, 45, 60, 90, 135, 160, 180, 200, 240, 300, 359], \
        findall(C-A, ( member(T1, Ts), member(T2, Ts), member(T4, [0, 90, 180, 300]), \
            member(T7, [90, 180]), member(T5, [90, 180]), \
            member(L5, [0.5, 1.0, 2.0]), member(L6, [0.5, 1.0, 2.0]), \
            C = ctx(T7, T4, T1, T2, T5, L5, L6, 1), context_design(C, _, A), \
            \\+ ( A = a1(P1, P2, M2, M4) -> P1 > 0, P1 < 180, P2 > 0, P2 < 180, M2 > 0, M4 > 0 \
               ; A = a2(P2, P4) -> P2 > 0, P2 < 180, P4 > 0, P4 < 180 \
               ; true ) ), Bad).";
    let b = first_answer(&mut kb, unsound).unwrap();
    let bad = b.iter().find(|(k, _)| k == "Bad").map(|(_, v)| v.as_str());
    assert_eq!(bad, Some("[]"), "{b:?}");
    // a tip is a feature of its own, taken by a kite with equal sides:
    // U_c - theta1/2 at N2 and N4, a right angle at N3
    for (t1, phi) in [(0, "135.0"), (5, "132.5"), (30, "120.0"), (44, "113.0")] {
        let q = format!("context_design(ctx(180, 180, {t1}, 180, 180, 1.0, 1.0, 1), F, a2(P, Q)).");
        let b = first_answer(&mut kb, &q).unwrap();
        let get = |n: &str| b.iter().find(|(k, _)| k == n).map(|(_, v)| v.clone());
        assert_eq!(get("F").as_deref(), Some("tip"), "{t1}: {b:?}");
        let (p, q) = (get("P").unwrap(), get("Q").unwrap());
        let close =
            |s: &str| (s.parse::<f64>().unwrap() - phi.parse::<f64>().unwrap()).abs() < 1e-9;
        assert!(close(&p) && close(&q), "{t1}: {b:?}");
    }
    // b2, b4 and b5 are for corners, never for a tip
    let b = first_answer(
        &mut kb,
        "findall(F-T1, ( member(T1, [0, 10, 44]), member(F, [b2, b4, b5]), \
            feature(F, ctx(90, 180, T1, 180, 90, 1, 1, 1)) ), Fs).",
    )
    .unwrap();
    assert_eq!(b, vec![("Fs".to_string(), "[]".to_string())]);
}

fn load(path: &str) -> Domain {
    let text = std::fs::read_to_string(path).unwrap();
    Domain::from_json(&serde_json::from_str(&text).unwrap()).unwrap()
}

#[test]
fn a_spike_and_a_notch_are_meshed_by_the_rules_within_the_bounds() {
    let domain = load("tests/sharp/spike-notch-small.json");
    let mut kb = KnowledgeBase::builtin().unwrap();
    let r = mesh_domain(&domain, &mut kb, &Options::default(), &mut |_| {}).unwrap();
    assert!(r.stopped_short.is_none());
    assert_eq!(r.stats.triangle_elements, 0);
    let q = &r.quality;
    // the spike's own corner is 11.42 deg; every other in [45, 135]
    assert!(q.min_angle > 11.4 - 1e-6, "{q:?}");
    assert!(q.max_angle <= 135.0 + 1e-6, "{q:?}");
    assert!(q.outside_45_135 <= 1, "{q:?}");
    assert!(q.max_aspect <= 10.0 && q.max_taper <= 10.0, "{q:?}");
    assert!(q.max_size_jump <= 2.0, "{q:?}");
    // valid: convex counter-clockwise quads covering the domain's area
    let (nodes, quads) = (r.mesh.nodes(), r.mesh.quads());
    let mut area = 0.0;
    for quad in quads {
        let p = quad.map(|n| nodes[n as usize]);
        for i in 0..4 {
            let (a, b, c) = (p[i], p[(i + 1) % 4], p[(i + 2) % 4]);
            assert!((b - a).perp_dot(c - b) > 0.0, "{quad:?} is not convex");
        }
        area += ((p[2] - p[0]).perp_dot(p[3] - p[1])) / 2.0;
    }
    // the polygon: a 4 x 2 rectangle, the spike's triangle (base 0.3,
    // height 1.5) added, the notch's (base 0.2, height 1.2) taken out
    let expected = 8.0 + 0.3 * 1.5 / 2.0 - 0.2 * 1.2 / 2.0;
    assert!(
        (area - expected).abs() < 1e-9,
        "area {area} against {expected}"
    );
}

#[test]
fn a_cusp_notch_is_meshed_within_the_bounds() {
    // an arc leaves the corner 0.8 deg off the line it came along and
    // curves away from it: a notch of 359.2 deg round a sliver of outside
    let domain = load("tests/sharp/cusp-notch.json");
    let mut kb = KnowledgeBase::builtin().unwrap();
    let r = mesh_domain(&domain, &mut kb, &Options::default(), &mut |_| {}).unwrap();
    assert!(r.stopped_short.is_none());
    assert_eq!(r.stats.triangle_elements, 0);
    let q = &r.quality;
    assert!(q.min_angle >= 45.0 && q.max_angle <= 135.0, "{q:?}");
    assert!(q.max_aspect <= 10.0 && q.max_taper <= 10.0, "{q:?}");
    assert!(q.max_size_jump <= 2.0, "{q:?}");
}

#[test]
fn an_arc_that_crosses_the_line_before_it_is_refused_where_it_crosses() {
    // the benchmark's cusp-arc: the arc leaves the corner 0.8 deg off the
    // line and curves back across it 0.087 from the corner (3e-4 to the
    // other side at most): a self-intersecting loop, whatever the size
    let text = std::fs::read_to_string("tests/sharp/cusp-arc.json").unwrap();
    let e = Domain::from_json(&serde_json::from_str(&text).unwrap()).unwrap_err();
    assert_eq!(
        e.to_string(),
        "outer: the loop intersects itself near (-0.738989, -1.176069): edges 0 and 1 meet again 0.086870 from point 1 at (-0.801826, -1.236050), where they join"
    );
}

/// The corner (deg) of the element at node `at` of a mesh.
fn corner_at(r: &freemesh::MeshResult, at: glam::DVec2) -> f64 {
    let nodes = r.mesh.nodes();
    let tip = nodes
        .iter()
        .position(|&p| (p - at).length() < 1e-12)
        .unwrap() as u32;
    let quads: Vec<&[u32; 4]> = r.mesh.quads().iter().filter(|q| q.contains(&tip)).collect();
    assert_eq!(quads.len(), 1, "one element takes the tip");
    let q = quads[0];
    let k = q.iter().position(|&n| n == tip).unwrap();
    let (a, b) = (
        nodes[q[(k + 1) % 4] as usize] - at,
        nodes[q[(k + 3) % 4] as usize] - at,
    );
    a.angle_to(b).abs().to_degrees()
}

/// An arc bulging out of the domain at a tip makes the chords' corner
/// sharper than the curves' (37.83 deg between the tangents here, 36.7
/// between chords of the size): the arc's first segments are shortened,
/// so that the element at the tip is within the judge's half degree of
/// the tip; with `bound(arc_corner_chord, 0)` (equal segments) it is not.
#[test]
fn an_arc_at_a_tip_keeps_the_tips_corner() {
    let domain = load("tests/sharp/arc-tip.json");
    let tip = glam::DVec2::new(3.266493401617944, 0.8952959706687499);
    for (files, kept) in [
        (&[][..], true),
        (&["tests/kb/no-arc-corner-chord.pl"][..], false),
    ] {
        let mut kb = KnowledgeBase::builtin().unwrap();
        for f in files {
            kb.consult_file(f).unwrap();
        }
        let r = mesh_domain(&domain, &mut kb, &Options::default(), &mut |_| {}).unwrap();
        let corner = corner_at(&r, tip);
        assert_eq!(corner >= 37.83 - 0.5, kept, "{files:?}: {corner}");
    }
}
