//! The keys the domain format knows (domain-format.md), and the keys of a
//! file it does not, each with the key probably meant.

use serde_json::Value;

/// The keys of each object of the format (domain-format.md, 1.1: `tags`,
/// a circle's `tag` and a line's `crack` are known keys).
const TOP_KEYS: &[&str] = &["name", "size", "max_size", "outer", "holes", "lines"];
const CHAIN_KEYS: &[&str] = &["points", "bulges", "segments", "tags", "circle", "crack"];
const CIRCLE_KEYS: &[&str] = &["center", "radius", "segments", "tag"];

/// Every key of the domain's objects that the format does not know, as
/// "where: key (did you mean ...?)".
pub(crate) fn unknown_keys(v: &Value) -> Vec<String> {
    fn check(v: &Value, at: &str, known: &[&str], out: &mut Vec<String>) {
        let Some(obj) = v.as_object() else { return };
        for k in obj.keys() {
            if known.contains(&k.as_str()) {
                continue;
            }
            let near = known
                .iter()
                .min_by_key(|c| edit_distance(k, c))
                .filter(|c| edit_distance(k, c) <= 2);
            let at = if at.is_empty() {
                String::new()
            } else {
                format!("{at}.")
            };
            out.push(match near {
                Some(c) => format!("{at}{k} (did you mean {c}?)"),
                None => format!("{at}{k}"),
            });
        }
    }
    let mut out = Vec::new();
    check(v, "", TOP_KEYS, &mut out);
    let chain = |c: &Value, at: String, out: &mut Vec<String>| {
        check(c, &at, CHAIN_KEYS, out);
        if let Some(circle) = c.get("circle") {
            check(circle, &format!("{at}.circle"), CIRCLE_KEYS, out);
        }
    };
    if let Some(o) = v.get("outer") {
        chain(o, "outer".into(), &mut out);
    }
    for list in ["holes", "lines"] {
        if let Some(items) = v.get(list).and_then(Value::as_array) {
            for (i, c) in items.iter().enumerate() {
                chain(c, format!("{list}[{i}]"), &mut out);
            }
        }
    }
    out
}

/// Levenshtein distance, for suggesting the key meant.
fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut prev = row[0];
        row[0] = i + 1;
        for (j, &cb) in b.iter().enumerate() {
            let cur = row[j + 1];
            row[j + 1] = (prev + usize::from(ca != cb)).min(row[j] + 1).min(cur + 1);
            prev = cur;
        }
    }
    row[b.len()]
}
