//! Who made each element: every trace step names its maker, the counts
//! per maker add up to the steps, and every design the validity check
//! refused is in the trace and counted.

use freemesh::{mesh_domain, trace_json_lines, By, Domain, KnowledgeBase, Options};

#[test]
fn every_step_names_its_maker_and_every_veto_is_traced_and_counted() {
    let domain = Domain::from_file("tests/bounds/plate-holes.json").expect("the plate domain");
    let mut kb = KnowledgeBase::builtin().expect("the built-in KB");
    let r = mesh_domain(&domain, &mut kb, &Options::default(), &mut |_| {}).expect("a mesh");
    // the counts per maker are the trace's steps per maker
    for (by, n) in r.stats.made_by() {
        let steps = r.trace.iter().filter(|t| t.by == by).count();
        assert_eq!(steps, n, "{} steps by {}", steps, by.name());
    }
    assert!(r.stats.made_by()[0] == (By::Rule, r.stats.designed));
    assert!(
        r.stats.designed > r.mesh.quads().len() / 2,
        "most elements by the rules"
    );
    // the vetoes: each in the trace, before the step that came next
    assert_eq!(r.vetoes.len(), r.stats.vetoes);
    assert!(
        !r.vetoes.is_empty(),
        "the plate has designs the check refuses"
    );
    let text = trace_json_lines(&r.trace, &r.vetoes);
    let lines: Vec<serde_json::Value> = text
        .lines()
        .map(|l| serde_json::from_str(l).expect("a JSON line"))
        .collect();
    assert_eq!(lines.len(), r.trace.len() + r.vetoes.len());
    let mut next_step = 1;
    for l in &lines {
        if let Some(v) = l.get("veto") {
            assert_eq!(v["before_step"].as_u64(), Some(next_step));
            for key in ["edge", "action", "reason", "outcome"] {
                assert!(v.get(key).is_some(), "no {key} in {v}");
            }
        } else {
            assert!(l["by"].is_string(), "no by in {l}");
            next_step = l["step"].as_u64().unwrap() + 1;
        }
    }
    assert!(r
        .stats
        .made_by_text()
        .ends_with(&format!("; {} vetoes", r.vetoes.len())));
}
