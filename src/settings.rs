//! The settings of a run, read from the knowledge base once
//! (`strategy/1` and `bound/2` of kb/strategy.pl) and handed to the
//! stages that use them.

use rustc_hash::FxHashMap as HashMap;

/// The settings the KB declares for a run.
#[derive(Debug, Clone)]
pub struct Settings {
    /// Each feature's place in the recursion strategy (0 first).
    rank: HashMap<String, u32>,
    /// How many times at most the redesign rules correct one element
    /// (`bound(redesign_rounds, N)`).
    pub redesign_rounds: usize,
}

impl Settings {
    /// The settings of a strategy (feature names in the order they are
    /// tried) and a number of redesign rounds (negative: none).
    pub fn new(strategy: Vec<String>, redesign_rounds: f64) -> Settings {
        let rank = strategy
            .into_iter()
            .enumerate()
            .map(|(i, f)| (f, i as u32))
            .collect();
        Settings {
            rank,
            redesign_rounds: redesign_rounds.max(0.0) as usize,
        }
    }

    /// A feature's place in the strategy; a feature the strategy does not
    /// list comes after every listed one.
    pub fn rank(&self, feature: &str) -> u32 {
        *self.rank.get(feature).unwrap_or(&u32::MAX)
    }
}
