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

/// `freemesh mesh DOMAIN --stats` without an answer store (every run
/// builds its engine, whatever earlier runs left in the user's): its
/// stderr.
fn stats_of(domain: &str) -> String {
    let out = std::env::temp_dir().join(format!(
        "freemesh-parallel-{}-{}.msh",
        std::process::id(),
        domain.replace('/', "_")
    ));
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_freemesh"))
        .env("FREEMESH_ANSWER_STORE", "off")
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

/// `freemesh mesh DOMAIN` (under `taskset -c 0`, which leaves the process
/// one core, where `one_core`): its mesh and its trace.
fn mesh_and_trace(domain: &str, one_core: bool) -> (Vec<u8>, String) {
    let stem = std::env::temp_dir().join(format!(
        "freemesh-two-at-once-{}-{}-{one_core}",
        std::process::id(),
        domain.replace('/', "_")
    ));
    let (msh, trace) = (stem.with_extension("msh"), stem.with_extension("jsonl"));
    let mut command = if one_core {
        let mut c = std::process::Command::new("taskset");
        c.args(["-c", "0", env!("CARGO_BIN_EXE_freemesh")]);
        c
    } else {
        std::process::Command::new(env!("CARGO_BIN_EXE_freemesh"))
    };
    let o = command
        .args(["mesh", domain, "-o"])
        .arg(&msh)
        .arg("--trace")
        .arg(&trace)
        .output()
        .expect("taskset (util-linux) runs the program on one core");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let read = (
        std::fs::read(&msh).unwrap(),
        std::fs::read_to_string(&trace).unwrap(),
    );
    let _ = (std::fs::remove_file(&msh), std::fs::remove_file(&trace));
    read
}

/// The coarser pass's variants run two at once where a core is spare,
/// and the layouts' block meshes are finished two at once: the mesh and
/// the trace are those of one at a time, on domains whose pass tries
/// several variants (and stops before the last on the first).
#[test]
fn variants_and_block_meshes_two_at_once_give_the_mesh_and_trace_of_one_at_a_time() {
    assert!(
        std::thread::available_parallelism().map_or(1, |n| n.get()) > 1,
        "this test compares two cores with one: it needs two"
    );
    for domain in [
        "tests/counts/coarse-chamfer.json",
        "tests/counts/fine-fixed-sides.json",
    ] {
        let (msh, trace) = mesh_and_trace(domain, false);
        let first = trace.lines().next().unwrap_or_default();
        // (coarser_fine_features is not run: its bounds are bound/2's)
        let variants_run = first.matches("\"coarser coarser_").count();
        assert!(
            variants_run >= 2,
            "{domain}: the pass tries two variants or more: {first}"
        );
        let (msh_one, trace_one) = mesh_and_trace(domain, true);
        assert!(msh == msh_one, "{domain}: the meshes differ");
        assert_eq!(trace, trace_one, "{domain}");
    }
}
