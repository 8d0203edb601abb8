//! The questions the host asks the knowledge base, typed: the host hands
//! in its own values (a context, an action, the relations it measured, a
//! loop's angles) and gets its own types back (a feature and action, a
//! redesign, final patterns, the settings). The text of every question
//! and the reading of every answer is in `terms.rs`; nothing else in the
//! crate writes Prolog.

use scryer_prolog::Term;

use crate::kb::answer_store;
use crate::kb::engine::KnowledgeBase;
use crate::kb::error::KbError;
use crate::kb::second_engine::Question;
use crate::kb::terms::{self, Bindings};
use crate::kb::vocabulary::{
    Action, Context, Designed, FrontFacts, Pattern, PatternKind, Redesigned, Relation,
};
use crate::settings::{ElementBounds, HostBounds, Settings};

/// A retry's name, the bounds it sets, and what a domain needs for it
/// (strategy.pl's `retry_bound/3`, `retry_needs/2`).
pub type RetryVariant = (String, Vec<(String, f64)>, Vec<String>);

impl KnowledgeBase {
    /// The settings (`strategy/1`, `bound/2`), read once for a run.
    pub fn settings(&mut self) -> Result<Settings, KbError> {
        let strategy = self.first_binding(terms::STRATEGY_QUESTION, "S")?;
        let strategy = terms::strategy_answer(strategy)?;
        let rounds = self.bound("redesign_rounds")?;
        let slide = self.bound("boundary_slide")?;
        let polish = self.bound("polish_rings")?;
        let unfold = self.bound("unfold_crowded_corners")?;
        let four = self.bound("split_into_four")?;
        let element = ElementBounds::new(
            self.bound("lower_corner")?,
            self.bound("upper_corner")?,
            self.bound("max_aspect")?,
            self.bound("max_taper")?,
            self.bound("max_size_jump")?,
        )
        .and_then(|e| e.with_boundary_slide(slide))
        .and_then(|e| e.with_polish_rings(polish))
        .and_then(|e| e.with_unfold_crowded_corners(unfold))
        .and_then(|e| e.with_split_into_four(four))
        .map_err(|why| KbError::Answer {
            query: "bound/2".into(),
            answer: why,
            expected: "a usable set of element bounds".into(),
        })?;
        let mut host = [0.0; HostBounds::NAMES.len()];
        for (v, name) in host.iter_mut().zip(HostBounds::NAMES) {
            *v = self.bound(name)?;
        }
        let host = HostBounds::new(host).map_err(|why| KbError::Answer {
            query: "bound/2".into(),
            answer: why,
            expected: "a usable set of host thresholds".into(),
        })?;
        Ok(Settings::new(strategy, rounds, element, host))
    }

    /// The other bounds a free mesh that falls short is tried again with
    /// (`retry_bound(Variant, Name, Value)`, strategy.pl): each variant
    /// with its bounds, in the order the KB names them, and what a domain
    /// needs for it to be tried (`retry_needs(Variant, What)`).
    pub fn retry_variants(&mut self) -> Result<Vec<RetryVariant>, KbError> {
        let mut variants: Vec<RetryVariant> = Vec::new();
        for b in self.run(terms::RETRY_BOUND_QUESTION)? {
            let (Some(v), Some(n), Some(x)) = (b.get("V"), b.get("N"), b.get("X")) else {
                continue;
            };
            let value = bound_value(x, "retry_bound/3")?;
            let (v, n) = (terms::term_text(v), terms::term_text(n));
            match variants.iter_mut().find(|(w, _, _)| *w == v) {
                Some((_, bounds, _)) => bounds.push((n, value)),
                None => variants.push((v, vec![(n, value)], vec![])),
            }
        }
        for b in self.run(terms::RETRY_NEEDS_QUESTION)? {
            let (Some(v), Some(w)) = (b.get("V"), b.get("W")) else {
                continue;
            };
            let v = terms::term_text(v);
            if let Some((_, _, needs)) = variants.iter_mut().find(|(u, _, _)| *u == v) {
                needs.push(terms::term_text(w));
            }
        }
        Ok(variants)
    }

    /// `f` run on this engine with `bounds` in place of the bounds of
    /// those names, every bound put back after: it answers as an engine
    /// built with them would (the memo dropped before and after,
    /// a second engine given the same bounds), without the time a new
    /// engine takes to build (the coarser pass's variants on the run's own
    /// engine).
    pub fn with_bounds_in_place<R>(
        &mut self,
        bounds: &[(String, f64)],
        f: impl FnOnce(&mut KnowledgeBase) -> R,
    ) -> Result<R, KbError> {
        self.change_bounds(&terms::push_bounds_question(bounds))?;
        self.in_place
            .push(bounds.iter().map(|b| b.0.clone()).collect());
        let r = f(self);
        self.in_place.pop();
        self.change_bounds(terms::POP_BOUNDS)?;
        Ok(r)
    }

    /// The bounds in place of bound/2's in a run graded by a max_size
    /// (`graded_bound/2`, kb/strategy.pl), in the KB's order.
    pub fn graded_bounds(&mut self) -> Result<Vec<(String, f64)>, KbError> {
        let mut bounds = Vec::new();
        for b in self.run(terms::GRADED_BOUND_QUESTION)? {
            let (Some(n), Some(x)) = (b.get("N"), b.get("X")) else {
                continue;
            };
            bounds.push((terms::term_text(n), bound_value(x, "graded_bound/2")?));
        }
        Ok(bounds)
    }

    /// `with_bounds_in_place` for those of `bounds` that no outer call
    /// has in place (a retry's own bounds win over a run's), and which
    /// they were; nothing changed where there are none.
    pub fn with_bounds_not_in_place<R>(
        &mut self,
        bounds: &[(String, f64)],
        f: impl FnOnce(&mut KnowledgeBase) -> R,
    ) -> Result<(R, Vec<(String, f64)>), KbError> {
        let placed: Vec<(String, f64)> = bounds
            .iter()
            .filter(|(n, _)| !self.in_place.iter().flatten().any(|m| m == n))
            .cloned()
            .collect();
        if placed.is_empty() {
            return Ok((f(self), placed));
        }
        let r = self.with_bounds_in_place(&placed, f)?;
        Ok((r, placed))
    }

    /// Whether `bounds` would change a bound in place now (a variant
    /// whose every bound already has its value would mesh the run
    /// again, mesh for mesh).
    pub fn would_change_a_bound(&mut self, bounds: &[(String, f64)]) -> Result<bool, KbError> {
        for (name, value) in bounds {
            // (a name bound/2 does not give a number is the variant's
            // own: it changes what the rules read)
            let now = self.first_binding(&terms::bound_question(name), "V")?;
            if now.as_ref().and_then(terms::term_number) != Some(*value) {
                return Ok(true);
            }
        }
        Ok(false)
    }

    fn bound(&mut self, name: &str) -> Result<f64, KbError> {
        let t = self.first_binding(&terms::bound_question(name), "V")?;
        terms::bound_answer(name, t)
    }

    fn first_binding(&mut self, query: &str, var: &str) -> Result<Option<Term>, KbError> {
        Ok(self
            .run(query)?
            .into_iter()
            .next()
            .and_then(|mut b| b.remove(var)))
    }

    /// The design of each context, in order: the feature and action, or
    /// None where the edge shows no feature. Not memoised here: the
    /// caller keeps the answers by context. Where a second engine is
    /// ready, both take the questions one by one (the answers do not
    /// depend on who gives them); else the batch is one query, which the
    /// engine reads and compiles once.
    pub fn designs(&mut self, contexts: &[Context]) -> Vec<Result<Option<Designed>, KbError>> {
        // the answer store first, question by question: what it lacks is
        // asked, and kept by question, however it was batched
        let questions: Vec<String> = contexts.iter().map(terms::design_question).collect();
        let mut designs: Vec<Option<Result<Option<Designed>, KbError>>> = contexts
            .iter()
            .zip(&questions)
            .map(|(ctx, q)| {
                let r = self.stored_first(q)?;
                Some(read_design(ctx, terms::fault_to_error(r, "")))
            })
            .collect();
        let missing: Vec<usize> = (0..contexts.len())
            .filter(|&i| designs[i].is_none())
            .collect();
        let asked: Vec<Context> = missing.iter().map(|&i| contexts[i].clone()).collect();
        for (i, design) in missing.into_iter().zip(self.designs_asked(&asked)) {
            designs[i] = Some(design);
        }
        designs.into_iter().flatten().collect()
    }

    /// The first answer's `R` to `query` (asked for one answer) if the
    /// store has it; nothing is asked of the engine.
    pub(super) fn stored_first(&mut self, query: &str) -> Option<Option<Term>> {
        let answers = answer_store::get(self.store_key(1, query)?)?;
        self.stats.stored_answers += 1;
        Some(answers.into_iter().next().and_then(|mut b| b.remove("R")))
    }

    /// Keeps `r` as the first answer's `R` to `query` (found by a batch
    /// that asked it among others): a later run finds it however it
    /// batches its questions.
    pub(super) fn keep_first(&mut self, query: &str, r: Option<&Term>) {
        if let Some(key) = self.store_key(1, query) {
            let answer = r.map(|t| Bindings::from([("R".to_string(), t.clone())]));
            answer_store::put(key, &Vec::from_iter(answer));
        }
    }

    /// `designs` of the contexts the store lacks, asked of the engine.
    fn designs_asked(&mut self, contexts: &[Context]) -> Vec<Result<Option<Designed>, KbError>> {
        if contexts.is_empty() {
            return Vec::new();
        }
        if self.second_engine_ready() && contexts.len() > 1 {
            return self.designs_one_by_one(contexts);
        }
        if contexts.len() == 1 {
            let answer = self.ask_bounded_fresh(&terms::design_question(&contexts[0]), "");
            return vec![read_design(&contexts[0], answer)];
        }
        let answer = self.ask_bounded_fresh(&terms::designs_question(contexts), "");
        match answer
            .ok()
            .and_then(|a| terms::designs_answer(a, contexts.len()))
        {
            Some(items) => contexts
                .iter()
                .zip(items)
                .map(|(ctx, a)| {
                    self.keep_first(&terms::design_question(ctx), a.as_ref());
                    read_design(ctx, terms::fault_to_error(a, ""))
                })
                .collect(),
            // a batch that threw: asked one by one, so that the error is
            // the edge's own
            None => self.designs_one_by_one(contexts),
        }
    }

    /// `designs` a question an edge, shared with a second engine when one
    /// is ready.
    fn designs_one_by_one(
        &mut self,
        contexts: &[Context],
    ) -> Vec<Result<Option<Designed>, KbError>> {
        // the context as text is for messages: written only for one
        let questions: Vec<Question> = contexts
            .iter()
            .map(|c| (terms::design_question(c), String::new()))
            .collect();
        let answers = self.ask_bounded_fresh_all(questions);
        contexts
            .iter()
            .zip(answers)
            .map(|(ctx, answer)| read_design(ctx, answer))
            .collect()
    }

    /// The feature and action the KB gives a context, as text for people
    /// (`freemesh features`): None where the edge shows no feature.
    pub fn design_text(
        &mut self,
        ctx: &Context,
    ) -> Result<(Option<String>, Option<String>), KbError> {
        let text = ctx.to_string();
        let ans = self.ask_bounded(&terms::design_question_text(ctx), &text)?;
        Ok(terms::design_answer_text(&ans))
    }

    /// The redesign rule that corrects `action` over the edge of `ctx`
    /// given the relations the host measured, or None when none fires.
    pub fn redesign(
        &mut self,
        ctx: &Context,
        action: &Action,
        relations: &[Relation],
    ) -> Result<Option<Redesigned>, KbError> {
        let query = terms::redesign_question(ctx, action, relations);
        let Some(ans) = self.ask_bounded(&query, &ctx.to_string())? else {
            return Ok(None);
        };
        let Some((rule, new)) = terms::redesign_answer(&ans) else {
            return Ok(None);
        };
        match Action::from_term(new).filter(Action::is_sound) {
            Some(action) => Ok(Some(Redesigned { rule, action })),
            None => Err(KbError::Answer {
                query: format!("redesign rule {rule}"),
                answer: terms::term_text(new),
                expected: "a known, sound action".into(),
            }),
        }
    }

    /// The final patterns that close a six-segment loop with these angles
    /// (whole degrees, in loop order), best first.
    pub fn final_patterns(&mut self, angles: &[f64]) -> Result<Vec<Pattern>, KbError> {
        let list = terms::angle_list(angles);
        let ans = self.ask_bounded(&terms::patterns_question(&list), &format!("[{list}]"))?;
        Ok(terms::patterns_answer(ans)
            .into_iter()
            .filter_map(|(name, start, text)| {
                let kind = match name.as_str() {
                    "pattern1" => PatternKind::One,
                    "pattern2" => PatternKind::Two,
                    "pattern3" => PatternKind::Three,
                    _ => return None,
                };
                Some(Pattern { kind, start, text })
            })
            .collect())
    }

    /// The ways `closing_way/2` allows to close a loop of `segments` the
    /// rules are stuck on (kb/patterns.pl): `quad`, `inset`, `hub`,
    /// `chord`, `path`; other answers are left out.
    pub fn closing_ways(&mut self, segments: usize) -> Result<Vec<String>, KbError> {
        let ans = self.ask_bounded(
            &terms::closing_ways_question(segments),
            &format!("a loop of {segments} segments"),
        )?;
        Ok(terms::closing_ways_answer(ans))
    }

    /// Whether the KB calls a front corner of `angle` degrees concave.
    pub fn is_concave(&mut self, angle: f64) -> Result<bool, KbError> {
        Ok(!self.run(&terms::concave_question(angle))?.is_empty())
    }

    /// States the live front to the KB as facts, replacing the last.
    pub fn publish_front(&mut self, facts: &FrontFacts) -> Result<(), KbError> {
        self.leave_answer_store();
        self.run(&terms::front_facts_statement(facts)).map(|_| ())
    }
}

/// An answer to a design question, read: the rule at fault named with
/// the context, an unknown or unsound action refused.
fn read_design(
    ctx: &Context,
    answer: Result<Option<Term>, KbError>,
) -> Result<Option<Designed>, KbError> {
    let answer = answer.map_err(|e| match e {
        KbError::Rule { rule, why, .. } => KbError::Rule {
            rule,
            why,
            context: ctx.to_string(),
        },
        other => other,
    });
    let Some(ans) = answer? else {
        return Ok(None);
    };
    let (feature, action) = match terms::design_answer(&ans) {
        Some((feature, action)) => (feature, Action::from_term(action)),
        None => (String::new(), None),
    };
    match action.filter(Action::is_sound) {
        Some(action) => Ok(Some(Designed { feature, action })),
        None => Err(KbError::Answer {
            query: format!("feature_action({feature}) on {ctx}"),
            answer: terms::term_text(&ans),
            expected: "d(Feature, Action) with a known, sound action".into(),
        }),
    }
}

/// A bound's value in an answer to `query`: a number, or the KB's error.
fn bound_value(x: &Term, query: &str) -> Result<f64, KbError> {
    terms::term_number(x).ok_or_else(|| KbError::Answer {
        query: query.into(),
        answer: terms::term_text(x),
        expected: "a number".into(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Contexts of every kind a batch holds: packable (whole degrees,
    /// lengths in hundredths), not (a fraction of a degree), and ones that
    /// show no feature or a reflex corner.
    fn contexts() -> Vec<Context> {
        let mut out = Vec::new();
        for t in [45.0, 90.0, 135.0, 180.0, 200.0, 270.0, 300.0, 359.5] {
            out.push(Context([180.0, 180.0, t, 180.0, 180.0, 1.0, 1.0, 1.0]));
            out.push(Context([90.0, 180.0, 90.0, t, 90.0, 0.8, 1.23, 1.0]));
            out.push(Context([120.0, t, 250.0, 60.0, 180.0, 0.333, 2.0, 2.5]));
        }
        out
    }

    fn one_by_one(kb: &mut KnowledgeBase, contexts: &[Context]) -> Vec<String> {
        contexts
            .iter()
            .map(|c| {
                let answer = kb.ask_bounded_fresh(&terms::design_question(c), "");
                format!("{:?}", read_design(c, answer))
            })
            .collect()
    }

    fn batched(kb: &mut KnowledgeBase, contexts: &[Context]) -> Vec<String> {
        kb.designs(contexts)
            .into_iter()
            .map(|d| format!("{d:?}"))
            .collect()
    }

    #[test]
    fn a_batch_of_design_questions_answers_as_each_alone() {
        let mut kb = KnowledgeBase::builtin().unwrap();
        let contexts = contexts();
        let expected = one_by_one(&mut kb, &contexts);
        assert!(
            expected.iter().any(|e| e.contains("Ok(None)")),
            "no featureless edge"
        );
        assert!(expected.iter().any(|e| e.contains("Ok(Some")), "no feature");
        let queries = kb.stats.engine_queries;
        assert_eq!(batched(&mut kb, &contexts), expected);
        assert_eq!(
            kb.stats.engine_queries,
            queries + 1,
            "one query for the batch"
        );
    }

    #[test]
    fn a_rule_at_fault_in_a_batch_is_named_with_its_edge() {
        let mut kb = KnowledgeBase::builtin().unwrap();
        kb.consult_file("tests/kb/throws-on-a-reflex-corner.pl")
            .unwrap();
        let contexts = contexts();
        let expected = one_by_one(&mut kb, &contexts);
        let faults: Vec<&String> = expected.iter().filter(|e| e.contains("raised")).collect();
        assert!(!faults.is_empty());
        assert!(faults
            .iter()
            .all(|e| e.contains("feature(b6)") && e.contains("ctx(")));
        assert_eq!(batched(&mut kb, &contexts), expected);
    }
}
