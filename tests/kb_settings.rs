//! A `--kb` file that sets one setting changes that one alone: the other
//! bounds keep their built-in values (kb/strategy.pl), so a file holding
//! only `bound(upper_corner, 140).` meshes like the built-in rules do.

use std::path::PathBuf;
use std::process::Command;

#[test]
fn a_file_setting_one_bound_meshes_every_benchmark_domain() {
    let out = std::env::temp_dir().join(format!("freemesh-one-bound-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&out);
    std::fs::create_dir_all(&out).unwrap();
    let mut domains: Vec<PathBuf> = std::fs::read_dir("../shared/bench/domains")
        .expect("../shared/bench/domains beside the clone")
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "json"))
        .collect();
    domains.sort();
    assert!(domains.len() >= 9);
    let o = Command::new(env!("CARGO_BIN_EXE_freemesh"))
        .args(["mesh", "../shared/bench/domains/*.json", "--kb"])
        .arg("tests/kb/upper-corner-140.pl")
        .arg("-o")
        .arg(out.join("{stem}.json"))
        .output()
        .expect("the binary runs");
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{stderr}");
    assert!(!stderr.contains("error"), "{stderr}");
    for d in &domains {
        let stem = d.file_stem().unwrap().to_string_lossy();
        let mesh: serde_json::Value = serde_json::from_str(
            &std::fs::read_to_string(out.join(format!("{stem}.json")))
                .unwrap_or_else(|e| panic!("{stem}: no mesh written ({e}): {stderr}")),
        )
        .unwrap();
        let quads = mesh["quads"].as_array().map_or(0, Vec::len);
        assert!(quads > 0, "{stem}: no quads");
    }
}

#[test]
fn a_file_setting_one_bound_leaves_the_others_as_they_were() {
    // the features the KB sees change with U_c (b1 needs both angles at
    // least U_c): an edge between corners of 138 degrees shows b3 under
    // the file's 140 and b1 under the built-in 135
    let ask = |kb: &[&str]| {
        let mut args = vec!["repl"];
        for f in kb {
            args.extend(["--kb", f]);
        }
        let mut child = Command::new(env!("CARGO_BIN_EXE_freemesh"))
            .args(&args)
            .stdin(std::process::Stdio::piped())
            .stdout(std::process::Stdio::piped())
            .spawn()
            .expect("the binary runs");
        use std::io::Write;
        child
            .stdin
            .take()
            .unwrap()
            .write_all(
                b"context_feature(ctx(180, 180, 138, 138, 180, 1, 1, 1), F).\n\
                  bound(lower_corner, L), bound(redesign_rounds, R), bound(near_node, K).\n",
            )
            .unwrap();
        let o = child.wait_with_output().unwrap();
        assert!(o.status.success());
        String::from_utf8_lossy(&o.stdout).into_owned()
    };
    let built_in = ask(&[]);
    let one = ask(&["tests/kb/upper-corner-140.pl"]);
    assert!(built_in.contains("F = b1"), "{built_in}");
    assert!(one.contains("F = b3"), "{one}");
    assert!(!one.contains("F = b1"), "{one}");
    let others = "L = 45, R = 4, K = 0.5.";
    assert!(built_in.contains(others), "{built_in}");
    assert!(one.contains(others), "{one}");
}

/// The upper corner a `--kb` file sets, as the REPL reads it, and whether
/// the copy of the file the engine read is gone with the process.
fn upper_corner_with(file: &str) -> (String, bool) {
    use std::io::Write;
    let mut child = Command::new(env!("CARGO_BIN_EXE_freemesh"))
        .args(["repl", "--kb", file])
        .stdin(std::process::Stdio::piped())
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("the binary runs");
    let copies = format!("freemesh-kb-{}-", child.id());
    child
        .stdin
        .take()
        .unwrap()
        .write_all(b"bound(upper_corner, U).\n")
        .unwrap();
    let o = child.wait_with_output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let gone = std::fs::read_dir(std::env::temp_dir())
        .unwrap()
        .filter_map(|e| e.ok())
        .all(|e| !e.file_name().to_string_lossy().starts_with(&copies));
    (String::from_utf8_lossy(&o.stdout).into_owned(), gone)
}

#[test]
fn a_file_whose_last_line_is_a_comment_is_read_whole() {
    // the engine alone reads a comment after the last clause as a syntax
    // error; the file's setting must be in place, and the copy it reads
    // instead gone with the process
    let (stdout, gone) = upper_corner_with("tests/kb/ends-in-a-comment.pl");
    assert!(stdout.contains("U = 140"), "{stdout}");
    assert!(gone, "a copy of the file left in the temporary folder");
}

#[test]
fn a_file_that_starts_with_a_byte_order_mark_is_read() {
    let (stdout, _) = upper_corner_with("tests/kb/starts-with-a-bom.pl");
    assert!(stdout.contains("U = 140"), "{stdout}");
}
