//! The text of the knowledge base's protocol, the one place it is
//! written and read: the host's questions as Prolog query text, the
//! engine's answer terms decoded into the host's types (actions,
//! patterns, settings), and the Prolog text of those types (the trace
//! shows actions as the KB writes them).
//!
//! Numbers go out as the engine reads them back exactly: angles in whole
//! degrees, ratios in hundredths or thousandths, floats always with a dot.

use scryer_prolog::Term;
use std::collections::BTreeMap;
use std::fmt::{self, Write as _};

use crate::kb::error::KbError;
use crate::kb::vocabulary::{
    Action, Context, Corner, ElementEdge, ElementNode, FrontFacts, Relation,
};

/// One answer's bindings.
pub type Bindings = BTreeMap<String, Term>;

/// Renders a term as Prolog text (atoms quoted when needed).
pub fn term_text(t: &Term) -> String {
    let mut s = String::new();
    write_term(&mut s, t);
    s
}

fn atom_needs_quotes(a: &str) -> bool {
    let mut ch = a.chars();
    match ch.next() {
        None => true,
        Some(c) if c.is_ascii_lowercase() => {
            !a.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
        }
        _ => {
            !matches!(a, "[]" | "!" | ";" | "{}" | "," | "|")
                && !a.chars().all(|c| "+-*/\\^<>=~:.?@#&$".contains(c))
        }
    }
}

fn write_term(s: &mut String, t: &Term) {
    match t {
        Term::Integer(i) => {
            let _ = write!(s, "{i}");
        }
        Term::Rational(r) => {
            let _ = write!(s, "{r}");
        }
        Term::Float(f) => s.push_str(&fmt_float(*f)),
        Term::Atom(a) => {
            if atom_needs_quotes(a) {
                let _ = write!(s, "'{}'", a.replace('\\', "\\\\").replace('\'', "\\'"));
            } else {
                s.push_str(a);
            }
        }
        Term::String(st) => {
            let _ = write!(s, "{st:?}");
        }
        Term::List(l) => {
            s.push('[');
            for (i, x) in l.iter().enumerate() {
                if i > 0 {
                    s.push(',');
                }
                write_term(s, x);
            }
            s.push(']');
        }
        Term::Compound(f, args) => {
            if args.len() == 2 && matches!(f.as_str(), "/" | ":" | "-" | "=" | "+" | "*") {
                write_term(s, &args[0]);
                s.push_str(f);
                write_term(s, &args[1]);
                return;
            }
            write_term(s, &Term::Atom(f.clone()));
            s.push('(');
            for (i, x) in args.iter().enumerate() {
                if i > 0 {
                    s.push_str(", ");
                }
                write_term(s, x);
            }
            s.push(')');
        }
        Term::Var(v) => s.push_str(v),
        _ => s.push_str("_"),
    }
}

/// A float as Prolog text (always with a dot, exponents as `1.0e-5`).
pub fn fmt_float(f: f64) -> String {
    if !f.is_finite() {
        return "0.0".into();
    }
    if let Some(s) = fmt_thousandths(f) {
        return s;
    }
    let s = format!("{f:?}");
    if s.contains('e') && !s.contains('.') {
        s.replacen('e', ".0e", 1)
    } else {
        s
    }
}

/// `fmt_float` of a number that is a whole number of thousandths (the
/// mesher's angles and rounded ratios), written from the integer: the
/// same text as the shortest form Rust writes, for a fraction of its cost.
fn fmt_thousandths(f: f64) -> Option<String> {
    let k = (f * 1000.0).round();
    if k.abs() >= 1e12 || k / 1000.0 != f {
        return None;
    }
    let k = k as i64;
    let (whole, mut frac) = ((k / 1000).abs(), (k % 1000).abs());
    let sign = if f < 0.0 || (f == 0.0 && f.is_sign_negative()) {
        "-"
    } else {
        ""
    };
    let mut digits = 3;
    while digits > 1 && frac % 10 == 0 {
        frac /= 10;
        digits -= 1;
    }
    Some(format!("{sign}{whole}.{frac:0digits$}"))
}

/// The numeric value of a number term.
pub fn term_number(t: &Term) -> Option<f64> {
    match t {
        Term::Integer(i) => i.to_string().parse().ok(),
        Term::Float(f) => Some(*f),
        Term::Rational(r) => {
            let s = r.to_string();
            match s.split_once('/') {
                Some((a, b)) => Some(a.trim().parse::<f64>().ok()? / b.trim().parse::<f64>().ok()?),
                None => s.parse().ok(),
            }
        }
        _ => None,
    }
}

fn prolog_quoted(s: &str) -> String {
    format!("'{}'", s.replace('\\', "\\\\").replace('\'', "\\'"))
}

/// A term as an atom's text, or else as Prolog text.
pub(super) fn atom_or_text(t: &Term) -> String {
    match t {
        Term::Atom(a) => a.clone(),
        other => term_text(other),
    }
}

/// A `Name = Value` binding of the REPL's answers, as two texts.
pub(super) fn binding_pair(t: &Term) -> Option<(String, String)> {
    match t {
        Term::Compound(f, args) if f == "=" && args.len() == 2 => {
            Some((atom_or_text(&args[0]), atom_or_text(&args[1])))
        }
        _ => None,
    }
}

/// The answer of a bounded question, or the rule at fault as an error.
pub(super) fn fault_to_error(ans: Option<Term>, context: &str) -> Result<Option<Term>, KbError> {
    match &ans {
        Some(Term::Compound(f, args)) if f == "fault" && args.len() == 2 => {
            let why = match &args[1] {
                Term::Compound(r, e) if r == "raised" && e.len() == 1 => {
                    format!("raised {}", term_text(&e[0]))
                }
                _ => "ran past the inference limit (2,000,000 inferences)".to_string(),
            };
            Err(KbError::Rule {
                rule: term_text(&args[0]),
                why,
                context: context.to_string(),
            })
        }
        _ => Ok(ans),
    }
}

impl Action {
    /// Reads an action term (`a1(P1, P2, L2, L4)`, `a2(P2, P4)`, `a3`, `a4`,
    /// `t3(H)`, `shift(1, A)`, `merge(n3, A)`).
    pub fn from_term(t: &Term) -> Option<Action> {
        let nums = |args: &[Term]| -> Option<Vec<f64>> { args.iter().map(term_number).collect() };
        match t {
            Term::Atom(a) if a == "a3" => Some(Action::A3),
            Term::Atom(a) if a == "a4" => Some(Action::A4),
            Term::Compound(f, args) => match (f.as_str(), args.len()) {
                ("a1", 4) => {
                    let v = nums(args)?;
                    Some(Action::A1 {
                        phi1: v[0],
                        phi2: v[1],
                        l2: v[2],
                        l4: v[3],
                    })
                }
                ("a2", 2) => {
                    let v = nums(args)?;
                    Some(Action::A2 {
                        phi2: v[0],
                        phi4: v[1],
                    })
                }
                ("t3", 1) => Some(Action::T3 {
                    height: term_number(&args[0])?,
                }),
                ("r3", 1) => Some(Action::R3 {
                    height: term_number(&args[0])?,
                }),
                ("shift", 2) if term_number(&args[0]) == Some(1.0) => {
                    Some(Action::Shift(Box::new(Action::from_term(&args[1])?)))
                }
                ("merge", 2) => {
                    let c = match &args[0] {
                        Term::Atom(a) if a == "n3" => Corner::N3,
                        Term::Atom(a) if a == "n4" => Corner::N4,
                        _ => return None,
                    };
                    Some(Action::Merge(c, Box::new(Action::from_term(&args[1])?)))
                }
                _ => None,
            },
            _ => None,
        }
    }
}

fn r2(x: f64) -> f64 {
    (x * 100.0).round() / 100.0
}

impl fmt::Display for Action {
    /// Prolog text of the action (parameters rounded to 0.01 for the trace
    /// and for queries).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Action::A1 { phi1, phi2, l2, l4 } => {
                write!(
                    f,
                    "a1({}, {}, {}, {})",
                    fmt_float(r2(*phi1)),
                    fmt_float(r2(*phi2)),
                    fmt_float(r2(*l2)),
                    fmt_float(r2(*l4))
                )
            }
            Action::A2 { phi2, phi4 } => {
                write!(f, "a2({}, {})", fmt_float(r2(*phi2)), fmt_float(r2(*phi4)))
            }
            Action::A3 => write!(f, "a3"),
            Action::A4 => write!(f, "a4"),
            Action::T3 { height } => write!(f, "t3({})", fmt_float(r2(*height))),
            Action::R3 { height } => write!(f, "r3({})", fmt_float(r2(*height))),
            Action::Shift(a) => write!(f, "shift(1, {a})"),
            Action::Merge(c, a) => write!(
                f,
                "merge({}, {a})",
                if *c == Corner::N3 { "n3" } else { "n4" }
            ),
        }
    }
}

impl fmt::Display for Context {
    /// The context term `ctx(T7, T4, T1, T2, T5, L5, L6, R)`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let n = &self.0;
        write!(
            f,
            "ctx({}, {}, {}, {}, {}, {}, {}, {})",
            n[0],
            n[1],
            n[2],
            n[3],
            n[4],
            fmt_float(n[5]),
            fmt_float(n[6]),
            fmt_float(n[7])
        )
    }
}

/// The design question for a context, in as few tokens as the engine's
/// reader allows (reading the query text is half the engine's cost): the
/// five whole-degree angles packed in base 1000, the two length ratios and
/// the grading ratio in hundredths; `fm_design_packed/5` of the loader
/// unpacks them into the same `ctx/8` term. Contexts it cannot pack
/// exactly are asked as text.
pub(super) fn design_question(ctx: &Context) -> String {
    match design_item(ctx) {
        DesignItem::Packed(p) => format!("fm_design_packed({p},R)."),
        DesignItem::Text => design_question_text(ctx),
    }
}

/// A context as the loader's `fm_design_packed/5` reads it (`P,H5,H6,HR`),
/// or `Text` where it cannot be packed exactly.
enum DesignItem {
    Packed(String),
    Text,
}

fn design_item(ctx: &Context) -> DesignItem {
    let n = &ctx.0;
    let angles_packable = n[..5]
        .iter()
        .all(|&a| a.fract() == 0.0 && (0.0..1000.0).contains(&a));
    let hundredths = |x: f64| {
        let h = (x * 100.0).round();
        (h.abs() < 1e15 && h / 100.0 == x).then_some(h as i64)
    };
    match (
        angles_packable,
        hundredths(n[5]),
        hundredths(n[6]),
        hundredths(n[7]),
    ) {
        (true, Some(h5), Some(h6), Some(hr)) => {
            let packed = n[..5].iter().fold(0i64, |p, &a| p * 1000 + a as i64);
            DesignItem::Packed(format!("{packed},{h5},{h6},{hr}"))
        }
        _ => DesignItem::Text,
    }
}

/// The design questions of several contexts as one query (`fm_designs/2`
/// of the loader): the engine reads and compiles one query for the batch
/// instead of one an edge. Each item is packed as in `design_question`.
pub(super) fn designs_question(contexts: &[Context]) -> String {
    let items: Vec<String> = contexts
        .iter()
        .map(|c| match design_item(c) {
            DesignItem::Packed(p) => format!("p({p})"),
            DesignItem::Text => format!("c({c})"),
        })
        .collect();
    format!("fm_designs([{}],R).", items.join(","))
}

/// The answers of `designs_question`, in order: each item's answer, None
/// where the edge shows no feature (`none`); None for the whole when the
/// answer is not a list of the batch's length.
pub(super) fn designs_answer(ans: Option<Term>, n: usize) -> Option<Vec<Option<Term>>> {
    let Some(Term::List(items)) = ans else {
        return None;
    };
    (items.len() == n).then(|| {
        items
            .into_iter()
            .map(|t| match t {
                Term::Atom(a) if a == "none" => None,
                t => Some(t),
            })
            .collect()
    })
}

/// The design question with the context written out.
pub(super) fn design_question_text(ctx: &Context) -> String {
    format!("fm_design({ctx}, R).")
}

/// An answer `d(Feature, Action)` to a design question, read: the feature
/// and the action term.
pub(super) fn design_answer(ans: &Term) -> Option<(String, &Term)> {
    match ans {
        Term::Compound(d, args) if d == "d" && args.len() == 2 => {
            Some((term_text(&args[0]), &args[1]))
        }
        _ => None,
    }
}

/// An answer `d(Feature, Action)` as two texts, for people to read.
pub(super) fn design_answer_text(ans: &Option<Term>) -> (Option<String>, Option<String>) {
    match ans {
        Some(Term::Compound(_, args)) if args.len() == 2 => {
            (Some(term_text(&args[0])), Some(term_text(&args[1])))
        }
        _ => (None, None),
    }
}

impl ElementNode {
    fn name(self) -> &'static str {
        match self {
            ElementNode::N1 => "n1",
            ElementNode::N2 => "n2",
            ElementNode::N3 => "n3",
            ElementNode::N4 => "n4",
        }
    }
}

impl ElementEdge {
    fn name(self) -> &'static str {
        match self {
            ElementEdge::E23 => "e23",
            ElementEdge::E34 => "e34",
            ElementEdge::E41 => "e41",
        }
    }
}

impl fmt::Display for Relation {
    /// The relation's term in `redesign/5` (kb/redesign.pl); lengths are
    /// relative to the element's mean edge, which is 1.0.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let x = fmt_float;
        match *self {
            Relation::OuterCorner { node, deg } => {
                write!(f, "outer_corner({}, {})", node.name(), x(deg))
            }
            Relation::RemainingCorner { node, deg } => {
                write!(f, "remaining_corner({}, {})", node.name(), x(deg))
            }
            Relation::InnerCorner { node, deg } => {
                write!(f, "inner_corner({}, {})", node.name(), x(deg))
            }
            Relation::CornerNode { corner, distance } => {
                write!(
                    f,
                    "corner_node({}, {}, {})",
                    corner.name(),
                    x(distance),
                    x(1.0)
                )
            }
            Relation::CornerSegment {
                corner,
                vertical,
                horizontal,
            } => write!(
                f,
                "corner_segment({}, {}, {}, {})",
                corner.name(),
                x(vertical),
                x(horizontal),
                x(1.0)
            ),
            Relation::EdgePoint {
                edge,
                vertical,
                horizontal,
                angle,
            } => write!(
                f,
                "edge_point({}, {}, {}, {}, {})",
                edge.name(),
                x(vertical),
                x(horizontal),
                x(1.0),
                x(angle)
            ),
        }
    }
}

/// The redesign question: the rule that corrects `action` over the edge
/// of `ctx`, given the relations measured.
pub(super) fn redesign_question(ctx: &Context, action: &Action, relations: &[Relation]) -> String {
    let rels: Vec<String> = relations.iter().map(|r| r.to_string()).collect();
    format!("fm_redesign({ctx}, {action}, [{}], R).", rels.join(", "))
}

/// An answer to the redesign question: the rule's name and the new
/// action's term.
pub(super) fn redesign_answer(ans: &Term) -> Option<(String, &Term)> {
    match ans {
        Term::Compound(_, args) if args.len() >= 2 => Some((term_text(&args[0]), &args[1])),
        _ => None,
    }
}

/// The angles of a six-segment loop as a Prolog list's items.
pub(super) fn angle_list(angles: &[f64]) -> String {
    angles
        .iter()
        .map(|a| fmt_float(*a))
        .collect::<Vec<_>>()
        .join(", ")
}

/// The final-patterns question for a loop's angles (`angle_list`).
pub(super) fn patterns_question(list: &str) -> String {
    format!("fm_patterns([{list}], R).")
}

/// The closing-ways question for a loop of `segments`.
pub(super) fn closing_ways_question(segments: usize) -> String {
    format!("fm_closing_ways({segments}, R).")
}

/// An answer to the closing-ways question: the ways' names, in the KB's
/// order (terms that are not atoms left out).
pub(super) fn closing_ways_answer(ans: Option<Term>) -> Vec<String> {
    let Some(Term::Compound(_, mut ws)) = ans else {
        return Vec::new();
    };
    let Some(Term::List(ways)) = ws.pop() else {
        return Vec::new();
    };
    ways.iter()
        .filter_map(|w| match w {
            Term::Atom(a) => Some(a.clone()),
            _ => None,
        })
        .collect()
}

/// An answer to the final-patterns question: each pattern term's name,
/// the node it starts at (mod 6) and its text, in the KB's order; terms
/// that are not a pattern with a start node are left out.
pub(super) fn patterns_answer(ans: Option<Term>) -> Vec<(String, usize, String)> {
    let Some(Term::Compound(_, mut ps)) = ans else {
        return Vec::new();
    };
    let Some(Term::List(pats)) = ps.pop() else {
        return Vec::new();
    };
    pats.iter()
        .filter_map(|pat| {
            let Term::Compound(name, args) = pat else {
                return None;
            };
            let k = args.first().and_then(term_number)?;
            Some((name.clone(), k as usize % 6, term_text(pat)))
        })
        .collect()
}

/// The question whether an angle (deg) is a concave point.
pub(super) fn concave_question(angle: f64) -> String {
    format!("angle_concave({}).", fmt_float(angle))
}

/// The statement of the live front as facts (`fm_front_set/4`, kb/front.pl).
pub(super) fn front_facts_statement(facts: &FrontFacts) -> String {
    let f = fmt_float;
    let nodes: Vec<String> = facts
        .nodes
        .iter()
        .map(|(n, p)| format!("xy({n}, {}, {})", f(p.x), f(p.y)))
        .collect();
    let edges: Vec<String> = facts
        .edges
        .iter()
        .map(|(a, b)| format!("e({a}, {b})"))
        .collect();
    let angles: Vec<String> = facts
        .angles
        .iter()
        .map(|(n, theta)| format!("a({n}, {})", f(*theta)))
        .collect();
    let ctxs: Vec<String> = facts
        .contexts
        .iter()
        .map(|(a, b, from, ctx)| format!("c({a}-{b}, {from}, {ctx})"))
        .collect();
    format!(
        "fm_front_set([{}], [{}], [{}], [{}]).",
        nodes.join(","),
        edges.join(","),
        angles.join(","),
        ctxs.join(",")
    )
}

/// The question for the strategy, and its answer read: feature names in
/// the order they are tried.
pub(super) const STRATEGY_QUESTION: &str = "strategy(S).";

pub(super) fn strategy_answer(t: Option<Term>) -> Result<Vec<String>, KbError> {
    match t {
        Some(Term::List(items)) => items
            .iter()
            .map(|x| match x {
                Term::Atom(a) => Ok(a.clone()),
                other => Err(KbError::Answer {
                    query: "strategy/1".into(),
                    answer: term_text(other),
                    expected: "a feature name".into(),
                }),
            })
            .collect(),
        other => Err(KbError::Answer {
            query: "strategy/1".into(),
            answer: other
                .map(|t| term_text(&t))
                .unwrap_or_else(|| "nothing".into()),
            expected: "a list of feature names".into(),
        }),
    }
}

/// The question for a numeric setting `bound(Name, V)`.
pub(super) fn bound_question(name: &str) -> String {
    format!("bound({name}, V).")
}

/// The answer to `bound_question`, read as a number.
pub(super) fn bound_answer(name: &str, t: Option<Term>) -> Result<f64, KbError> {
    t.as_ref()
        .and_then(term_number)
        .ok_or_else(|| KbError::Answer {
            query: format!("bound({name}, _)"),
            answer: t.map(|t| term_text(&t)).unwrap_or_else(|| "nothing".into()),
            expected: "a number".into(),
        })
}

/// The REPL's query: the user's text as character codes, read and run
/// inside `catch/3` by the loader, at most `limit` inferences an answer.
pub(super) fn user_query_question(text: &str, limit: u64) -> String {
    let codes: Vec<String> = text.chars().map(|c| (c as u32).to_string()).collect();
    format!("fm_repl_query([{}], {limit}, A).", codes.join(","))
}

/// A predicate of each built-in file, asked once the engine is built: a
/// file that did not load leaves its predicate missing.
pub(super) const BUILT_IN_PROBES: &[&str] = &[
    "strategy(_)",
    "point_segment_near(0, 0, 1)",
    "context_feature(ctx(180,180,180,180,180,1,1,1), _)",
    "context_design(ctx(180,180,180,180,180,1,1,1), _, _)",
    "violation(outer_corner(n1, 10), _)",
    "loop_patterns([90,90,180,90,90,180], _)",
    "fm_known_action_(a3)",
    "\\+ edge_feature(_, _)",
];

/// A probe of `BUILT_IN_PROBES` as a query.
pub(super) fn probe_question(probe: &str) -> String {
    format!("{probe}.")
}

/// Marks the engine as holding the built-in rules alone: its questions
/// run without the inference bound (the loader's `fm_only_built_in_rules_`).
pub(super) const ONLY_BUILT_IN_RULES: &str = "assertz(fm_only_built_in_rules_).";

/// The variants of bounds a free mesh that falls short is tried again
/// with (strategy.pl).
pub(super) const RETRY_BOUND_QUESTION: &str = "retry_bound(V, N, X).";

/// What a domain needs for a retry to be tried (strategy.pl).
pub(super) const RETRY_NEEDS_QUESTION: &str = "retry_needs(V, W).";

/// The bounds of a run graded by a max_size.
pub(super) const GRADED_BOUND_QUESTION: &str = "graded_bound(N, X).";

/// Sets `bounds` in place of the bounds of those names, the bounds
/// before saved (`fm_bounds_push/1` of the loader).
pub(super) fn push_bounds_question(bounds: &[(String, f64)]) -> String {
    let pairs: Vec<String> = bounds
        .iter()
        .map(|(name, value)| format!("{name}-{}", fmt_float(*value)))
        .collect();
    format!("fm_bounds_push([{}]).", pairs.join(", "))
}

/// Every bound as the last `push_bounds_question` found it.
pub(super) const POP_BOUNDS: &str = "fm_bounds_pop.";

/// Takes the mark back: a user's rules may come in, bound every question.
pub(super) const NOT_ONLY_BUILT_IN_RULES: &str = "retractall(fm_only_built_in_rules_).";

/// The libraries a person typing queries expects at a Prolog prompt.
pub(super) const QUERY_LIBRARIES: &str =
    "use_module(library(lists)), use_module(library(between)), \
     use_module(library(format)), use_module(library(dif)), \
     use_module(library(error)), use_module(library(si)), \
     use_module(library(lambda)), use_module(library(iso_ext)), \
     use_module(library(charsio)), use_module(library(dcgs)), \
     use_module(library(pairs)), use_module(library(ordsets)), \
     use_module(library(assoc)), use_module(library(freeze)), \
     use_module(library(reif)), use_module(library(time)).";

/// The loader's question that checks and adds a user's file (`Settings`:
/// the predicates the file replaces instead of extending).
pub(super) fn consult_question(abs_path: &str, settings: &[&str]) -> String {
    format!(
        "fm_consult({}, [{}], R).",
        prolog_quoted(abs_path),
        settings.join(", ")
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn thousandths_are_written_as_rust_writes_them() {
        for k in -3_000_000i64..3_000_000 {
            let f = k as f64 / 1000.0;
            assert_eq!(fmt_thousandths(f), Some(format!("{f:?}")), "{k}");
        }
        assert_eq!(fmt_thousandths(-0.0).as_deref(), Some("-0.0"));
        assert_eq!(fmt_thousandths(0.1 + 0.2), None);
        assert_eq!(fmt_float(1e-5), "1.0e-5");
    }

    #[test]
    fn action_terms_round_trip_through_text() {
        let a = Action::Merge(
            Corner::N3,
            Box::new(Action::A2 {
                phi2: 90.0,
                phi4: 85.5,
            }),
        );
        assert_eq!(a.to_string(), "merge(n3, a2(90.0, 85.5))");
    }

    #[test]
    fn a_context_that_packs_exactly_is_asked_packed() {
        let ctx = Context([90.0, 180.0, 270.0, 45.0, 0.0, 1.25, 0.5, 2.5]);
        assert_eq!(
            design_question(&ctx),
            "fm_design_packed(90180270045000,125,50,250,R)."
        );
        let odd = Context([90.0, 180.0, 270.0, 45.0, 0.0, 1.255, 0.5, 1.0]);
        assert_eq!(
            design_question(&odd),
            "fm_design(ctx(90, 180, 270, 45, 0, 1.255, 0.5, 1.0), R)."
        );
    }

    #[test]
    fn relations_are_written_as_redesign_pl_reads_them() {
        let rels = [
            Relation::OuterCorner {
                node: ElementNode::N2,
                deg: 40.0,
            },
            Relation::CornerNode {
                corner: ElementNode::N3,
                distance: 0.25,
            },
            Relation::EdgePoint {
                edge: ElementEdge::E34,
                vertical: 0.5,
                horizontal: 0.125,
                angle: 250.0,
            },
        ];
        let ctx = Context([180.0; 8]);
        assert_eq!(
            redesign_question(&ctx, &Action::A3, &rels),
            "fm_redesign(ctx(180, 180, 180, 180, 180, 180.0, 180.0, 180.0), a3, \
             [outer_corner(n2, 40.0), corner_node(n3, 0.25, 1.0), \
             edge_point(e34, 0.5, 0.125, 1.0, 250.0)], R)."
        );
    }
}
