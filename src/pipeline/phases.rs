//! Where a run's time went, stage by stage (`--stats`).

/// Wall time of each phase of a run (seconds).
#[derive(Debug, Default, Clone, Copy)]
pub struct Phases {
    /// Discretising the boundary, cutting lines, the first front.
    pub prepare: f64,
    /// The recursion: features, designs, redesigns, fallbacks.
    pub recursion: f64,
    /// Laplace smoothing and the angle clean-up.
    pub smoothing: f64,
    /// The mesh's check and quality figures.
    pub check: f64,
    /// With `--blocks`: the layouts, their block meshes, and the
    /// finishing of those not kept (the kept one's is in smoothing and
    /// check).
    pub blocks: f64,
    /// Where the best mesh fell short: the meshes of `retry_bound/3`'s
    /// variants (wall time: as many at once as there are cores).
    pub retries: f64,
    /// Where a uniform mesh had many more elements than its area asks
    /// for: the runs of the coarser pass not kept (the first run's where
    /// a coarser mesh is kept, the coarser runs' where it is not; wall
    /// time: two at once where a core is spare).
    pub coarser: f64,
}

impl Phases {
    /// The run's own stages: prepare, recursion, smoothing and check
    /// (not the other meshes made to choose it).
    pub fn own(&self) -> f64 {
        self.prepare + self.recursion + self.smoothing + self.check
    }
}
