//! Snapshots of inference traces: one step per line, so that a change to a
//! rule shows as a readable diff. Review a changed snapshot with
//! `cargo insta review`; CI runs with INSTA_UPDATE=no.

use freemesh::{mesh_domain, Domain, KnowledgeBase, Options};

fn trace_text(path: &std::path::Path) -> String {
    let domain = Domain::from_file(&path.to_string_lossy()).expect("a valid test domain");
    let mut kb = KnowledgeBase::builtin().expect("the built-in KB loads");
    let r = mesh_domain(&domain, &mut kb, &Options::default(), &mut |_| {})
        .expect("the test domain meshes");
    let mut s = format!(
        "{} quads, {} nodes, {} fallback splits\n",
        r.mesh.quads().len(),
        r.mesh.nodes().len(),
        r.stats.fallback_splits
    );
    for t in &r.trace {
        s.push_str(&t.to_text());
        s.push('\n');
    }
    s
}

/// `graded-square.json` has a `max_size`: its trace shows the coarsen
/// rule's t3, four elements a step.
#[test]
fn traces_of_small_domains() {
    insta::glob!("inputs/*.json", |path| {
        insta::assert_snapshot!(trace_text(path));
    });
}
