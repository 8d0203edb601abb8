//! The work done in parallel (a second engine answering part of the
//! design questions, smoothing a large mesh in two halves) and a run that
//! keeps no trace leave the mesh and the trace as they are.

use std::time::Duration;

use freemesh::{mesh_domain, Domain, KnowledgeBase, Options};

#[test]
fn a_second_engine_or_no_trace_gives_the_same_mesh_and_trace() {
    let domain = Domain::from_file("examples/multi-connected.json").unwrap();
    let opts = Options::default()
        .with_size(Some(0.05))
        .with_max_size(Some(0.05));
    let mut one = KnowledgeBase::builtin().unwrap();
    let alone = mesh_domain(&domain, &mut one, &opts, &mut |_| {}).unwrap();
    assert!(
        alone.mesh.nodes().len() > 20_000,
        "large enough to be smoothed in halves: {} nodes",
        alone.mesh.nodes().len()
    );
    assert_eq!(alone.kb_stats.second_engine_queries, 0);

    let mut two = KnowledgeBase::builtin().unwrap();
    two.start_second_engine();
    assert!(two.wait_for_second_engine(Duration::from_secs(120)));
    let shared = mesh_domain(&domain, &mut two, &opts, &mut |_| {}).unwrap();
    assert!(shared.kb_stats.second_engine_queries > 0);
    assert_eq!(shared.mesh.nodes(), alone.mesh.nodes());
    assert_eq!(shared.mesh.quads(), alone.mesh.quads());
    assert_eq!(shared.trace, alone.trace);

    let mut three = KnowledgeBase::builtin().unwrap();
    let untraced = mesh_domain(
        &domain,
        &mut three,
        &opts.clone().with_trace(false),
        &mut |_| {},
    )
    .unwrap();
    assert!(untraced.trace.is_empty());
    assert!(!alone.trace.is_empty());
    assert_eq!(untraced.mesh.nodes(), alone.mesh.nodes());
    assert_eq!(untraced.mesh.quads(), alone.mesh.quads());
}

/// `freemesh mesh DOMAIN --stats`: its stderr.
fn stats_of(domain: &str) -> String {
    let out = std::env::temp_dir().join(format!(
        "freemesh-parallel-{}-{}.msh",
        std::process::id(),
        domain.replace('/', "_")
    ));
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_freemesh"))
        .args(["mesh", domain, "--stats", "-o"])
        .arg(&out)
        .output()
        .unwrap();
    let _ = std::fs::remove_file(&out);
    let err = String::from_utf8_lossy(&o.stderr).into_owned();
    assert!(o.status.success(), "{err}");
    err
}

#[test]
fn a_domain_of_a_few_elements_is_meshed_without_a_second_engine_and_a_larger_one_with() {
    // its build would only contend with the first engine's on a small
    // domain (42 elements); a larger one (about 3,000) pays for it
    let small = stats_of("../shared/bench/domains/mapping-unequal.json");
    assert!(small.contains("queries and"), "{small}");
    assert!(!small.contains("answered by a second engine"), "{small}");
    if std::thread::available_parallelism().map_or(1, |n| n.get()) > 1 {
        let larger = stats_of("../shared/bench/hard/flange.json");
        assert!(larger.contains("answered by a second engine"), "{larger}");
    }
}
