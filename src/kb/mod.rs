//! The knowledge base: the engine with the rules loaded (`engine.rs`, a
//! second engine beside it for batches, `second_engine.rs`, the loader
//! `loader.pl` that bounds every question, and `user_loader.pl`, loaded
//! when a user's rules come in, that checks a user's file, read from a
//! copy that `user_file.rs` makes), and
//! the protocol the host speaks with it: typed questions
//! (`questions.rs`) in the host's words (`vocabulary.rs`), whose text
//! and answers are written and read in one place (`terms.rs`).

pub mod answer_store;
mod engine;
mod error;
mod questions;
mod second_engine;
mod terms;
mod two_engines;
mod user_file;
mod vocabulary;

pub use engine::{KbStats, KnowledgeBase, More, UserAnswer};
pub use error::KbError;
pub use questions::RetryVariant;
pub use two_engines::SecondEngineLoading;
pub use vocabulary::{
    Action, Context, Corner, Designed, ElementEdge, ElementNode, FrontFacts, PatternKind,
    Redesigned, Relation,
};
