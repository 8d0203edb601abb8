//! `mesh`, a batch and the REPL's `:run` go through one pipeline: where
//! the rules and the loop subdivision get stuck, the REPL's `:run` too
//! finishes the domain by the last resort, with the mesh `mesh` makes.

use freemesh::{mesh_domain, Domain, Flow, KnowledgeBase, Options, Repl};

/// A rounded slot round a tiny hole (random domain 243 of the long run):
/// the rules stop on it, the triangle fallback meshes it.
const STUCK: &str = "tests/stuck/spike.json";

#[test]
fn the_repls_run_finishes_a_stuck_domain_as_mesh_does() {
    let domain = Domain::from_file(STUCK).unwrap();
    let mut kb = KnowledgeBase::builtin().unwrap();
    let meshed = mesh_domain(&domain, &mut kb, &Options::default(), &mut |_| {}).unwrap();
    assert_eq!(meshed.stats.triangle_fallbacks, 1);

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
            && last.ends_with("(the rules stopped: meshed whole by the triangle fallback)"),
        "{last}"
    );
    let counts = format!(
        "{} quads, {} nodes",
        meshed.quality.quads,
        meshed.mesh.nodes().len()
    );
    assert!(last.contains(&counts), "{last} (mesh made {counts})");
}
