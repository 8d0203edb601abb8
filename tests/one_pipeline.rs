//! `mesh`, a batch and the REPL's `:run` go through one pipeline: where
//! the rules and the loop subdivision get stuck, the REPL's `:run` too
//! closes the open loops by the fallback, with the mesh `mesh` makes.

use freemesh::{mesh_domain, Domain, Flow, KnowledgeBase, Options, Repl};

/// A spike of 1 degree: the rules stop by it, the fallback closes the
/// loops they leave open.
const STUCK: &str = "tests/stuck/spike.json";

#[test]
fn the_repls_run_finishes_a_stuck_domain_as_mesh_does() {
    let domain = Domain::from_file(STUCK).unwrap();
    let mut kb = KnowledgeBase::builtin().unwrap();
    let meshed = mesh_domain(&domain, &mut kb, &Options::default(), &mut |_| {}).unwrap();
    assert_eq!(meshed.stats.triangle_fallbacks, 0);
    assert!(meshed.stats.open_loops_closed > 0);

    let mut kb = KnowledgeBase::builtin().unwrap();
    let mut session = Repl::new(&mut kb, None);
    session.load(STUCK).unwrap();
    let mut out = Vec::new();
    assert_eq!(
        session.handle(":run", &mut out, None).unwrap(),
        Flow::Continue
    );
    let text = String::from_utf8(out).unwrap();
    let last = text.lines().last().unwrap_or("");
    assert!(
        last.starts_with("% the mesh is complete")
            && last.ends_with(&meshed.stats.stopped_text())
            && last.contains("open loop"),
        "{last}"
    );
    let counts = format!(
        "{} quads, {} nodes",
        meshed.quality.quads,
        meshed.mesh.nodes().len()
    );
    assert!(last.contains(&counts), "{last} (mesh made {counts})");
}
