//! What can go wrong in the knowledge base: loading a file, or a question
//! whose rule throws, runs away or answers what the host cannot use.

/// An error of the knowledge base: loading a file or answering a query.
#[derive(Debug, thiserror::Error)]
pub enum KbError {
    /// A KB file could not be read.
    #[error("{path}: cannot read: {message}")]
    Read {
        /// The file.
        path: String,
        /// Why.
        message: String,
    },
    /// A KB file has a clause the KB refuses (syntax error, unknown action...).
    #[error("{path}:{line}: {reason}")]
    Clause {
        /// The file.
        path: String,
        /// Its line (0 when unknown).
        line: u64,
        /// What is wrong, in Prolog's words.
        reason: String,
    },
    /// A query raised an exception in a rule.
    #[error("knowledge base: {query} raised {error}")]
    Query {
        /// The predicate asked.
        query: String,
        /// The exception term.
        error: String,
    },
    /// A rule threw or ran past the inference limit while meshing.
    #[error("knowledge base: the rule {rule} {why} on {context}")]
    Rule {
        /// The rule at fault (`feature(b6)`, `feature_action(b6)`, ...).
        rule: String,
        /// What it did.
        why: String,
        /// The question it was asked (the edge's context, ...).
        context: String,
    },
    /// A query answered with something the host cannot use.
    #[error("knowledge base: {query} answered {answer}, which is not {expected}")]
    Answer {
        /// The predicate asked.
        query: String,
        /// What it answered.
        answer: String,
        /// What was expected.
        expected: String,
    },
}
