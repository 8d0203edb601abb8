//! The paper's quality bounds on the public benchmark domains (`domains/`
//! and `hard/`), as the outside judge (`../shared/bench/judge --require
//! quality`) checks them:
//! every corner in [45, 135] (at an input corner sharper than 45 degrees,
//! down to that corner's angle), aspect ratio and taper at most 10, and
//! neighbours' sizes within a factor 2.
//!
//! The same runs keep the README's figures honest: its "Measured" table
//! (our columns; Gmsh's need Gmsh and are not measured here) and the
//! blade example's figures in the README and `examples/kb/README.md` are
//! measured again, and a figure that no longer holds fails the test with
//! the row as it now reads.

use freemesh::{
    mesh_domain, mesh_free_then_blocks, Domain, KnowledgeBase, Mesh, NodeKind, Options,
};
use std::path::PathBuf;

/// The interior angle of each corner of each element, in degrees.
fn corner_angles(mesh: &Mesh, q: usize) -> [f64; 4] {
    let p = mesh.quad_points(q);
    std::array::from_fn(|i| {
        let a = p[(i + 1) % 4] - p[i];
        let b = p[(i + 3) % 4] - p[i];
        let deg = a.perp_dot(b).atan2(a.dot(b)).to_degrees();
        if deg < 0.0 {
            deg + 360.0
        } else {
            deg
        }
    })
}

/// Where a corner may go down to: 45 degrees, or at a boundary node the
/// domain's own angle there (the sum of its elements' corners) if that
/// is sharper.
fn smallest_allowed(mesh: &Mesh) -> Vec<f64> {
    let mut sum = vec![0.0; mesh.nodes().len()];
    for q in 0..mesh.quads().len() {
        for (i, a) in corner_angles(mesh, q).into_iter().enumerate() {
            sum[mesh.quads()[q][i] as usize] += a;
        }
    }
    (0..mesh.nodes().len())
        .map(|n| match mesh.kinds()[n] {
            NodeKind::Boundary => sum[n].min(45.0),
            NodeKind::Interior => 45.0,
        })
        .collect()
}

/// The judge's public set: `domains/` and `hard/`, sorted by name.
fn public_domains() -> Vec<PathBuf> {
    let mut files = Vec::new();
    for dir in ["../shared/bench/domains", "../shared/bench/hard"] {
        let mut here: Vec<PathBuf> = std::fs::read_dir(dir)
            .unwrap_or_else(|e| panic!("{dir} beside the clone: {e}"))
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|x| x == "json"))
            .collect();
        here.sort();
        files.extend(here);
    }
    files
}

/// The smallest taper any quadrilateral can have at a tip of `tip`
/// degrees whose other corners stay at or under 135: the kite with 135 at
/// its sides, sin(45 - tip/2) / sin(tip/2). Under 7.56 degrees it is
/// above 10, so no mesh meets the paper's taper bound there.
fn best_tip_taper(tip: f64) -> f64 {
    let h = (tip / 2.0).to_radians();
    (std::f64::consts::FRAC_PI_4 - h).sin() / h.sin()
}

/// Public domains the program does not yet mesh within the bounds (none
/// today: chamfered-head, short before small loops were closed whole by
/// `closing_way/2`, is within; README "Measured").
const KNOWN_SHORT: [&str; 0] = [];

#[test]
fn every_public_domain_is_meshed_within_the_papers_bounds() {
    let files = public_domains();
    assert!(files.len() >= 16, "{files:?}");
    let mut kb = KnowledgeBase::builtin().expect("the built-in KB loads");
    let mut faults = Vec::new();
    let readme = std::fs::read_to_string("README.md").unwrap();
    let mut stale_rows = Vec::new();
    for f in &files {
        let name = f.file_stem().unwrap().to_string_lossy();
        let text = std::fs::read_to_string(f).unwrap();
        let domain = match Domain::from_json(&serde_json::from_str(&text).unwrap()) {
            Ok(d) => d,
            // a loop that crosses itself is not a domain (hard/cusp-arc:
            // tests/sharp_tips.rs shows where it crosses)
            Err(e) if e.to_string().contains("intersects itself") => continue,
            Err(e) => {
                faults.push(format!("{name}: refused: {e}"));
                continue;
            }
        };
        // as `freemesh mesh` (the judge's command) makes it
        let r = mesh_free_then_blocks(&domain, None, &mut kb, &Options::default(), &mut |_| {})
            .unwrap();
        let allowed = smallest_allowed(&r.mesh);
        let mut sharpest_tip: f64 = 180.0;
        for q in 0..r.mesh.quads().len() {
            for (i, a) in corner_angles(&r.mesh, q).into_iter().enumerate() {
                let low = allowed[r.mesh.quads()[q][i] as usize];
                sharpest_tip = sharpest_tip.min(low);
                // the judge reads the nodes from a file: a hair of slack
                if a < low - 1e-6 || a > 135.0 + 1e-6 {
                    faults.push(format!("{name}: element {q} has a corner of {a:.2} deg"));
                }
            }
        }
        let k = &r.quality;
        // where no quad can meet the taper bound, within a quarter of the
        // best one can do (spike-notch: a 4.83 deg spike, best 16.1)
        let taper_bound = 10f64.max(1.25 * best_tip_taper(sharpest_tip));
        if k.max_aspect > taper_bound || k.max_taper > taper_bound || k.max_size_jump > 2.0 {
            faults.push(format!(
                "{name}: aspect {:.2}, taper {:.2} (bound {taper_bound:.2}), size jump {:.3}",
                k.max_aspect, k.max_taper, k.max_size_jump
            ));
        }
        let within =
            k.max_taper <= 10.0 && !faults.iter().any(|f| f.starts_with(&format!("{name}:")));
        stale_rows.extend(readme_row_if_stale(&readme, &name, k, within));
    }
    // known short of the bounds (README "Measured"): still short, or the
    // list and the README are stale
    for name in KNOWN_SHORT {
        assert!(
            faults.iter().any(|f| f.starts_with(&format!("{name}:"))),
            "{name} now meets the bounds: take it off KNOWN_SHORT and the README"
        );
    }
    faults.retain(|f| !KNOWN_SHORT.iter().any(|n| f.starts_with(&format!("{n}:"))));
    assert!(faults.is_empty(), "{}", faults.join("\n"));
    assert!(
        stale_rows.is_empty(),
        "README's Measured table is stale; as measured now:\n{}",
        stale_rows.join("\n")
    );
}

#[test]
fn a_tip_under_seven_and_a_half_degrees_leaves_no_quad_within_the_taper_bound() {
    assert!(best_tip_taper(7.5) > 10.0 && best_tip_taper(7.6) < 10.0);
    // the kite that reaches it: tip, 135 at both sides, the rest opposite
    let tip: f64 = 4.83;
    let h = (tip / 2.0).to_radians();
    let p1 = glam::DVec2::new(h.cos(), -h.sin());
    let t = h.sin() / (std::f64::consts::FRAC_PI_4 - h).sin();
    let dir = (std::f64::consts::FRAC_PI_4 - h).sin_cos();
    let p2 = p1 + t * glam::DVec2::new(dir.1, dir.0);
    let p3 = glam::DVec2::new(p1.x, -p1.y);
    let q = [glam::DVec2::ZERO, p1, p2, p3];
    let corner = |i: usize| {
        let (a, b) = (q[(i + 1) % 4] - q[i], q[(i + 3) % 4] - q[i]);
        a.perp_dot(b).atan2(a.dot(b)).to_degrees()
    };
    assert!((p2.y).abs() < 1e-12, "on the axis");
    assert!((corner(0) - tip).abs() < 1e-9 && (corner(1) - 135.0).abs() < 1e-9);
    let taper = (p1 - q[0]).length() / (p3 - p2).length();
    assert!((taper - best_tip_taper(tip)).abs() < 1e-9, "{taper}");
}

/// The README table's row for a domain, our columns as the judge rounds
/// them (quads, angles, share, scaled Jacobian, aspect, taper, size jump,
/// within the paper's bounds), when the README's row differs from it.
fn readme_row_if_stale(
    readme: &str,
    name: &str,
    q: &freemesh::Quality,
    within_bounds: bool,
) -> Option<String> {
    let measured = format!(
        "| {name} | {} | {:.1} | {:.1} | {:.2} | {:.3} | {:.1} | {:.1} | {:.2} | {} |",
        q.quads,
        q.min_angle,
        q.max_angle,
        q.pct_45_135,
        q.min_scaled_jacobian,
        q.max_aspect,
        q.max_taper,
        q.max_size_jump,
        if within_bounds { "yes" } else { "no" }
    );
    let row = readme
        .lines()
        .find(|l| l.starts_with(&format!("| {name} |")));
    match row {
        Some(r) if r.starts_with(&measured) => None,
        Some(r) => Some(format!("README: {r}\nnow:    {measured}")),
        None => Some(format!("README has no row for {name}; now: {measured}")),
    }
}

#[test]
fn the_blade_examples_figures_are_measured_again() {
    let domain = Domain::from_file("examples/kb/blade.json").unwrap();
    let run = |kb_file: Option<&str>| {
        let mut kb = KnowledgeBase::builtin().expect("the built-in KB loads");
        if let Some(f) = kb_file {
            kb.consult_file(f).unwrap();
        }
        mesh_domain(&domain, &mut kb, &Options::default(), &mut |_| {}).unwrap()
    };
    let (before, after) = (run(None), run(Some("examples/kb/sharp-corner.pl")));
    let (b, a) = (&before.quality, &after.quality);
    let readme = std::fs::read_to_string("README.md").unwrap();
    let sentence = format!(
        "meshes with {} quads instead of {}, taper {:.1} instead of {:.1}",
        a.quads, b.quads, a.max_taper, b.max_taper
    );
    // the sentence may be wrapped anywhere
    let flat = readme.split_whitespace().collect::<Vec<_>>().join(" ");
    assert!(flat.contains(&sentence), "README should say: {sentence}");
    let example = std::fs::read_to_string("examples/kb/README.md").unwrap();
    let changes = |s: &freemesh::MeshStats| {
        let plural = |n: usize, what: &str, many: &str| {
            (n > 0).then(|| format!("{n} {}", if n == 1 { what } else { many }))
        };
        let done: Vec<String> = [
            plural(s.cleanup_flips, "edge flip", "edge flips"),
            plural(s.cleanup_collapses, "element collapse", "element collapses"),
            plural(
                s.cleanup_splits,
                "hexagon split in three",
                "hexagons split in three",
            ),
        ]
        .into_iter()
        .flatten()
        .collect();
        if done.is_empty() {
            "none".to_string()
        } else {
            done.join(", ")
        }
    };
    let rows = [
        format!("| quads | {} | {} |", b.quads, a.quads),
        format!(
            "| angles | {:.1}° .. {:.1}° | {:.1}° .. {:.1}° |",
            b.min_angle, b.max_angle, a.min_angle, a.max_angle
        ),
        format!(
            "| quads with every angle in [45°, 135°] | {:.1}% | {:.1}% |",
            b.pct_45_135, a.pct_45_135
        ),
        format!(
            "| largest taper | {:.2} | {:.2} |",
            b.max_taper, a.max_taper
        ),
        format!(
            "| fallback splits | {} | {} |",
            before.stats.fallback_splits, after.stats.fallback_splits
        ),
        format!(
            "| clean-up changes after smoothing | {} | {} |",
            changes(&before.stats),
            changes(&after.stats)
        ),
    ];
    let stale: Vec<&String> = rows
        .iter()
        .filter(|r| !example.contains(r.as_str()))
        .collect();
    assert!(
        stale.is_empty(),
        "examples/kb/README.md should have these rows:\n{}",
        stale
            .iter()
            .map(|r| r.as_str())
            .collect::<Vec<_>>()
            .join("\n")
    );
}
