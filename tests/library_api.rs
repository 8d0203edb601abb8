//! The library's public face: what a caller can give it, and what it
//! gives back, without a panic: text that does not parse, options out of
//! range, a domain that is not one, a run the rules cannot finish.

use freemesh::{
    angle_bins, angle_histogram, measure_quality, mesh_domain, read_mesh, render, Domain,
    DomainError, Error, Format, KnowledgeBase, Mesh, More, OptionError, Options, RunOption,
    UserAnswer,
};

/// Every answer of a query a user typed, the way the REPL asks for them.
fn answers(kb: &mut KnowledgeBase, text: &str) -> Vec<UserAnswer> {
    let mut all = Vec::new();
    kb.user_query(text, 1_000_000, &mut |a| {
        all.push(a);
        true
    });
    all
}

#[test]
fn a_query_that_does_not_parse_is_one_error_answer_never_a_panic() {
    let mut kb = KnowledgeBase::builtin().unwrap();
    for text in [
        "foo(",
        "X = ",
        ")",
        "X = [1, 2",
        "'unterminated",
        "\"unterminated",
        "a :- b :- c",
        "X = f(,)",
        "X is 1 +",
        "X = \u{1F600}(",
        "(((((((((((",
        ". . .",
    ] {
        let got = answers(&mut kb, text);
        assert!(
            matches!(got.as_slice(), [UserAnswer::Error(_)]),
            "{text:?} gave {got:?}"
        );
    }
    // the engine is still whole after them
    assert_eq!(
        answers(&mut kb, "X = 7"),
        vec![UserAnswer::Bindings(
            vec![("X".into(), "7".into())],
            More::No
        )]
    );
}

#[test]
fn an_exception_or_a_runaway_in_a_users_query_is_an_error_answer() {
    let mut kb = KnowledgeBase::builtin().unwrap();
    let thrown = answers(&mut kb, "throw(oops)");
    assert!(
        matches!(thrown.as_slice(), [UserAnswer::Error(_)]),
        "{thrown:?}"
    );
    let looping = answers(&mut kb, "length(L, N), N < 0");
    match looping.as_slice() {
        [UserAnswer::Error(e)] => assert!(e.contains("inference limit"), "{e}"),
        other => panic!("a runaway gave {other:?}"),
    }
}

#[test]
fn a_domain_is_made_only_validated() {
    // too few points, a crossing, no size, text that is not JSON: errors
    let cases = [
        r#"{"size": 1, "outer": {"points": [[0,0],[1,0]]}}"#,
        r#"{"size": 1, "outer": {"points": [[0,0],[2,2],[2,0],[0,2]]}}"#,
        r#"{"size": 1, "outer": "#,
        r#"{"outer": {"points": [[0,0],[1,0],[1,1],[0,1]]}}"#,
    ];
    for text in cases {
        assert!(Domain::from_json_str(text).is_err(), "{text} was accepted");
    }
    assert!(matches!(
        Domain::from_json_str(r#"{"size": 1, "outer": "#),
        Err(DomainError::Json { .. })
    ));
    // an odd fixed segment total is found where the boundary is
    // discretised: an error of the run, not a panic
    let odd = Domain::from_json_str(
        r#"{"size": 1, "outer": {"points": [[0,0],[1,0],[1,1]], "segments": [1,1,1]}}"#,
    )
    .unwrap();
    let mut kb = KnowledgeBase::builtin().unwrap();
    let run = mesh_domain(&odd, &mut kb, &Options::default(), &mut |_| {});
    assert!(matches!(run, Err(Error::Domain(_))), "{run:?}");

    let d = Domain::from_json_str(
        r#"{"name": "ring", "size": 0.5, "max_size": 2,
            "outer": {"circle": {"center": [0, 0], "radius": 2}},
            "holes": [{"circle": {"center": [0, 0], "radius": 1}}]}"#,
    )
    .unwrap();
    assert_eq!(d.name(), "ring");
    assert_eq!(d.size(), 0.5);
    assert_eq!(d.max_size(), Some(2.0));
    assert_eq!(d.hole_count(), 1);
    assert!(
        (d.area() - 3.0 * std::f64::consts::PI).abs() < 1e-9,
        "{}",
        d.area()
    );
    // a key the format does not know is refused, naming it
    let e = Domain::from_json_str(
        r#"{"size": 1, "frobs": 1, "outer": {"circle": {"center": [0, 0], "radius": 2}}}"#,
    )
    .unwrap_err();
    assert!(
        matches!(e, DomainError::UnknownKeys(ref k) if k.len() == 1),
        "{e}"
    );
}

#[test]
fn an_option_out_of_range_is_a_typed_error_naming_the_option() {
    let domain = Domain::from_file("tests/inputs/square.json").unwrap();
    let mut kb = KnowledgeBase::builtin().unwrap();
    let mut run = |opts: Options| mesh_domain(&domain, &mut kb, &opts, &mut |_| {});
    match run(Options::default().with_max_size(Some(f64::NAN))) {
        Err(Error::Option(OptionError::NotPositive { option, value })) => {
            assert_eq!(option, RunOption::MaxSize);
            assert!(value.is_nan());
        }
        other => panic!("max_size NaN gave {other:?}"),
    }
    match run(Options::default().with_size(Some(0.0))) {
        Err(Error::Option(OptionError::NotPositive { option, value })) => {
            assert_eq!((option, value), (RunOption::Size, 0.0));
        }
        other => panic!("size 0 gave {other:?}"),
    }
    match run(Options::default().with_size(Some(1e-9))) {
        Err(Error::Option(OptionError::TooManyElements { size, limit, .. })) => {
            assert_eq!((size, limit), (1e-9, 5_000_000));
        }
        other => panic!("size 1e-9 gave {other:?}"),
    }
    // the library's words name the option, not a command-line flag
    let e = run(Options::default().with_size(Some(-2.0))).unwrap_err();
    assert_eq!(e.to_string(), "size must be a positive number, got -2");
}

/// The loop the rules leave open in the spike: its triangles paired into
/// quads (fallback/pairs.rs) leave fewer elements than splitting each in
/// three, which halves every loop edge and the rows across from them.
#[test]
fn an_open_loop_closed_by_pairs_has_fewer_elements_than_one_split_in_three() {
    let domain = Domain::from_file("tests/stuck/spike.json").unwrap();
    let mut paired = KnowledgeBase::builtin().unwrap();
    let mut split = KnowledgeBase::builtin().unwrap();
    split.consult_file("tests/kb/no-triangle-pairs.pl").unwrap();
    let a = mesh_domain(&domain, &mut paired, &Options::default(), &mut |_| {}).unwrap();
    let b = mesh_domain(&domain, &mut split, &Options::default(), &mut |_| {}).unwrap();
    let last = |r: &freemesh::MeshResult| r.trace.last().unwrap().action.clone();
    assert!(last(&a).starts_with("loop_triangle_pairs("), "{}", last(&a));
    assert!(last(&b).starts_with("loop_triangle_split("), "{}", last(&b));
    assert!(
        a.mesh.quads().len() < b.mesh.quads().len(),
        "{} paired, {} split",
        a.mesh.quads().len(),
        b.mesh.quads().len()
    );
}

#[test]
fn a_run_the_rules_cannot_finish_hands_back_where_it_stopped() {
    let domain = Domain::from_file("tests/stuck/spike.json").unwrap();
    let mut kb = KnowledgeBase::builtin().unwrap();
    let result = mesh_domain(&domain, &mut kb, &Options::default(), &mut |_| {}).unwrap();
    // only the loops the rules left open are meshed by the fallback
    assert_eq!(result.stats.triangle_fallbacks, 0);
    assert!(result.stats.open_loops_closed > 0);
    assert!(result.stats.designed > 0);
    let stopped = result
        .stopped_short
        .expect("the state where the rules stopped");
    assert!(!stopped.reason.is_empty());
    assert!(
        stopped.picture.starts_with("<svg"),
        "{}",
        &stopped.picture[..40]
    );
    assert!(!stopped.trace.is_empty());
    // the rules' trace, and a last step saying what closed the loops
    let last = result.trace.last().unwrap();
    assert_eq!(last.feature, "stuck");
    assert!(
        last.action.starts_with("loop_triangle_pairs("),
        "{}",
        last.action
    );
    assert!(result.trace.len() > 1);
}

#[test]
fn the_self_check_changes_no_mesh() {
    let domain = Domain::from_file("tests/inputs/plate-hole.json").unwrap();
    let mut kb = KnowledgeBase::builtin().unwrap();
    let plain = mesh_domain(&domain, &mut kb, &Options::default(), &mut |_| {}).unwrap();
    let mut kb = KnowledgeBase::builtin().unwrap();
    let opts = Options {
        self_check: true,
        ..Options::default()
    };
    let checked = mesh_domain(&domain, &mut kb, &opts, &mut |_| {}).unwrap();
    assert_eq!(plain.mesh.nodes(), checked.mesh.nodes());
    assert_eq!(plain.mesh.quads(), checked.mesh.quads());
    assert!(plain.stopped_short.is_none());
}

#[test]
fn the_knowledge_base_lists_its_files_and_counts_its_queries() {
    let mut kb = KnowledgeBase::builtin().unwrap();
    assert_eq!(
        kb.files().first().map(String::as_str),
        Some("kb/strategy.pl")
    );
    let before = kb.stats().engine_queries;
    let domain = Domain::from_file("tests/inputs/square.json").unwrap();
    let r = mesh_domain(&domain, &mut kb, &Options::default(), &mut |_| {}).unwrap();
    assert!(kb.stats().engine_queries > before);
    assert_eq!(
        r.kb_stats.engine_queries,
        kb.stats().engine_queries - before
    );
}

/// A `Mesh` cannot be put together by hand outside the crate (its fields
/// are private: the `compile_fail` examples on `Mesh` show both ways
/// refused), so the functions that take one never meet a node id out of
/// range: a user's mesh is the empty one, a run's, or one read from a
/// file, and the reader refuses a bad id with an error.
#[test]
fn a_mesh_is_made_only_valid() {
    // the empty mesh is one
    let empty = Mesh::default();
    assert!(empty.nodes().is_empty() && empty.quads().is_empty());
    let _ = measure_quality(&empty);
    assert_eq!(angle_bins(&empty).iter().sum::<usize>(), 0);
    let _ = angle_histogram(&empty);
    for format in [
        Format::Msh,
        Format::Vtk,
        Format::Svg,
        Format::Json,
        Format::Inp,
    ] {
        let _ = render(&empty, None, "empty", format);
    }
    // a quad naming a node the file does not have: an error, not a panic
    let dir = std::env::temp_dir().join(format!("freemesh-api-tests-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let bad = dir.join("bad.json");
    std::fs::write(
        &bad,
        r#"{"nodes": [[0, 0], [1, 0], [1, 1], [0, 1]], "quads": [[0, 1, 2, 99]]}"#,
    )
    .unwrap();
    let read = read_mesh(bad.to_str().unwrap());
    assert!(read.is_err(), "a node id out of range was read");
    // the same quad with its ids in range is read, and measured
    let good = dir.join("good.json");
    std::fs::write(
        &good,
        r#"{"nodes": [[0, 0], [1, 0], [1, 1], [0, 1]], "quads": [[0, 1, 2, 3]]}"#,
    )
    .unwrap();
    let read = read_mesh(good.to_str().unwrap()).unwrap();
    assert_eq!(read.mesh.quads(), &[[0, 1, 2, 3]]);
    assert_eq!(read.mesh.nodes().len(), 4);
    assert!((measure_quality(&read.mesh).min_angle - 90.0).abs() < 1e-9);
    let _ = render(&read.mesh, None, "good", Format::Svg);
    let _ = std::fs::remove_dir_all(&dir);
}

/// A star with a short inner line: taking elements back beside the line
/// once parted its two sides off as a loop of two edges, which the front
/// takes for a closed seam, so that neither side got an element and the
/// whole domain went to the triangle fallback.
#[test]
fn an_inner_lines_two_sides_both_get_elements() {
    let domain = Domain::from_file("tests/stuck/star-inner-line.json").unwrap();
    let mut kb = KnowledgeBase::builtin().unwrap();
    let result = mesh_domain(&domain, &mut kb, &Options::default(), &mut |_| {}).unwrap();
    assert_eq!(result.stats.triangle_fallbacks, 0);
    assert_eq!(result.stats.open_loops_closed, 0);
    assert!(result.stats.unmeshed > 0, "the take-back this is about");
    assert!(result.stopped_short.is_none());
}
