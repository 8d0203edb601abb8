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
    /// The bounds an element is judged by after the recursion: what
    /// smoothing and clean-up aim for and what the summary reports.
    pub element: ElementBounds,
    /// The thresholds the host applies in the recursion.
    pub host: HostBounds,
}

impl Settings {
    /// The settings of a strategy (feature names in the order they are
    /// tried), a number of redesign rounds (negative: none) and the
    /// element bounds.
    pub fn new(
        strategy: Vec<String>,
        redesign_rounds: f64,
        element: ElementBounds,
        host: HostBounds,
    ) -> Settings {
        let rank = strategy
            .into_iter()
            .enumerate()
            .map(|(i, f)| (f, i as u32))
            .collect();
        Settings {
            rank,
            redesign_rounds: redesign_rounds.max(0.0) as usize,
            element,
            host,
        }
    }

    /// A feature's place in the strategy; a feature the strategy does not
    /// list comes after every listed one.
    pub fn rank(&self, feature: &str) -> u32 {
        *self.rank.get(feature).unwrap_or(&u32::MAX)
    }
}

/// The bounds on an element's corners, shape and size against its
/// neighbours (`bound(lower_corner, _)`, `upper_corner`, `max_aspect`,
/// `max_taper`, `max_size_jump`): the targets of smoothing and clean-up,
/// and the window the quality summary counts.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ElementBounds {
    /// The smallest good corner (degrees, below 90).
    pub lower_corner: f64,
    /// The largest good corner (degrees, above 90).
    pub upper_corner: f64,
    /// The largest good aspect ratio.
    pub max_aspect: f64,
    /// The largest good taper.
    pub max_taper: f64,
    /// The largest good size jump between neighbours (square root of
    /// their area ratio).
    pub max_size_jump: f64,
    /// cos² of the lower corner, for telling a corner inside the window
    /// without trigonometry (rounded to 1e-12, so 45 degrees gives 0.5
    /// exactly).
    pub cos2_lower: f64,
    /// cos² of the upper corner, likewise.
    pub cos2_upper: f64,
    /// `boundary_slide`: easing and the polish may slide a boundary node
    /// inside an input edge along it (straight or arc), keeping at least
    /// this share of the way between its neighbours from either (0: no
    /// boundary node moves).
    pub boundary_slide: f64,
    /// `polish_rings`: the free nodes within this many rings of elements
    /// round an element still past the bounds after smoothing and
    /// clean-up move together to bring it within (0: never; see
    /// smoothing/polish.rs).
    pub polish_rings: f64,
    /// `unfold_crowded_corners`: 1: the clean-up's flip or collapse that
    /// takes an element from a crowded boundary corner (two elements or
    /// more sharing a corner under their count times the lower corner)
    /// and that its local smoothing leaves folded over is smoothed again
    /// from its free nodes' neighbours' mean (cleanup.rs); 0: never.
    pub unfold_crowded_corners: f64,
    /// `split_into_four`: 1: the clean-up may split a lone element spanning
    /// two edges of a tight arc and its neighbour into four round two new
    /// nodes (cleanup/hexagon.rs); 0: never.
    pub split_into_four: f64,
}

/// The built-in `bound(boundary_slide, _)` (kb/strategy.pl).
pub const BOUNDARY_SLIDE: f64 = 0.2;

/// The built-in `bound(polish_rings, _)` (kb/strategy.pl).
pub const POLISH_RINGS: f64 = 2.0;

/// A switch's value, 0 or 1, or a sentence saying it is neither.
fn on_or_off(name: &str, on: f64) -> Result<(), String> {
    if on == 0.0 || on == 1.0 {
        Ok(())
    } else {
        Err(format!("bound({name}, {on}) must be 0 or 1"))
    }
}

/// The built-in `bound(unfold_crowded_corners, _)` (kb/strategy.pl).
pub const UNFOLD_CROWDED_CORNERS: f64 = 1.0;

/// The built-in `bound(split_into_four, _)` (kb/strategy.pl).
pub const SPLIT_INTO_FOUR: f64 = 1.0;

impl Default for ElementBounds {
    /// The paper's bounds: corners in [45, 135], aspect ratio and taper
    /// 10, size jump 2.
    fn default() -> ElementBounds {
        ElementBounds::new(45.0, 135.0, 10.0, 10.0, 2.0)
            .expect("the built-in element bounds are consistent")
    }
}

impl ElementBounds {
    /// The bounds, or a sentence saying which is out of range: the corner
    /// window must hold a right angle (0 < lower < 90 < upper < 180), the
    /// others be at least 1.
    pub fn new(
        lower_corner: f64,
        upper_corner: f64,
        max_aspect: f64,
        max_taper: f64,
        max_size_jump: f64,
    ) -> Result<ElementBounds, String> {
        if !(lower_corner > 0.0 && lower_corner < 90.0) {
            return Err(format!(
                "bound(lower_corner, {lower_corner}) must be above 0 and below 90"
            ));
        }
        if !(upper_corner > 90.0 && upper_corner < 180.0) {
            return Err(format!(
                "bound(upper_corner, {upper_corner}) must be above 90 and below 180"
            ));
        }
        for (name, v) in [
            ("max_aspect", max_aspect),
            ("max_taper", max_taper),
            ("max_size_jump", max_size_jump),
        ] {
            if !(v >= 1.0 && v.is_finite()) {
                return Err(format!("bound({name}, {v}) must be a number of at least 1"));
            }
        }
        let cos2 = |deg: f64| {
            let c = deg.to_radians().cos();
            (c * c * 1e12).round() / 1e12
        };
        Ok(ElementBounds {
            lower_corner,
            upper_corner,
            max_aspect,
            max_taper,
            max_size_jump,
            cos2_lower: cos2(lower_corner),
            cos2_upper: cos2(upper_corner),
            boundary_slide: BOUNDARY_SLIDE,
            polish_rings: POLISH_RINGS,
            unfold_crowded_corners: UNFOLD_CROWDED_CORNERS,
            split_into_four: SPLIT_INTO_FOUR,
        })
    }

    /// These bounds for the finish of a block layout of more than
    /// `bound(layout_sizes_free_over, K)` elements: its blocks judged by their corners
    /// and taper alone. Each block is divided to the element size, so its
    /// aspect ratio and its size against its neighbours are not its
    /// elements' (a long block gets more elements along it); its corners
    /// are theirs, and a tapered block's elements are as tapered.
    pub fn for_layout(self) -> ElementBounds {
        // (a bound no block comes near; finite, so that sums and squares
        // of it stay numbers)
        const NONE: f64 = 1e9;
        ElementBounds {
            max_aspect: NONE,
            max_size_jump: NONE,
            ..self
        }
    }

    /// These bounds with `bound(polish_rings, rings)`, or a sentence
    /// saying it is out of range (a whole number from 0 to 4).
    pub fn with_polish_rings(self, rings: f64) -> Result<ElementBounds, String> {
        if !((0.0..=4.0).contains(&rings) && rings.fract() == 0.0) {
            return Err(format!(
                "bound(polish_rings, {rings}) must be a whole number from 0 to 4"
            ));
        }
        Ok(ElementBounds {
            polish_rings: rings,
            ..self
        })
    }

    /// These bounds with `bound(unfold_crowded_corners, on)`, or a
    /// sentence saying it is out of range (0 or 1).
    pub fn with_unfold_crowded_corners(self, on: f64) -> Result<ElementBounds, String> {
        on_or_off("unfold_crowded_corners", on)?;
        Ok(ElementBounds {
            unfold_crowded_corners: on,
            ..self
        })
    }

    /// These bounds with `bound(split_into_four, on)`, or a sentence
    /// saying it is out of range (0 or 1).
    pub fn with_split_into_four(self, on: f64) -> Result<ElementBounds, String> {
        on_or_off("split_into_four", on)?;
        Ok(ElementBounds {
            split_into_four: on,
            ..self
        })
    }

    /// These bounds with `bound(boundary_slide, share)`, or a sentence
    /// saying it is out of range (0 to below a half).
    pub fn with_boundary_slide(self, share: f64) -> Result<ElementBounds, String> {
        if !(0.0..0.5).contains(&share) {
            return Err(format!(
                "bound(boundary_slide, {share}) must be at least 0 and below 0.5"
            ));
        }
        Ok(ElementBounds {
            boundary_slide: share,
            ..self
        })
    }

    /// True iff a corner whose edge vectors have dot product `d` and
    /// squared lengths `aa`, `bb` (convex) is inside the window, as
    /// `d² <= cos² · aa · bb` on the side of a right angle it is on.
    pub fn corner_inside(&self, d: f64, aa: f64, bb: f64) -> bool {
        let c2 = if d > 0.0 {
            self.cos2_lower
        } else {
            self.cos2_upper
        };
        d * d <= c2 * (aa * bb)
    }

    /// True iff a corner is clearly inside the window: as `corner_inside`
    /// with a margin, so that measuring its angle would say the same.
    pub fn corner_clearly_inside(&self, d: f64, aa: f64, bb: f64) -> bool {
        let c2 = if d > 0.0 {
            self.cos2_lower
        } else {
            self.cos2_upper
        };
        d * d < c2 * ((1.0 - 1e-9) * aa * bb)
    }

    /// How far a corner (degrees) is outside the window (0 inside).
    pub fn corner_excess(&self, angle: f64) -> f64 {
        (self.lower_corner - angle)
            .max(angle - self.upper_corner)
            .max(0.0)
    }

    /// True iff a corner (degrees) is inside the window.
    pub fn corner_in_window(&self, angle: f64) -> bool {
        (self.lower_corner..=self.upper_corner).contains(&angle)
    }
}

/// The thresholds the host applies during the recursion, each a
/// `bound/2` entry of kb/strategy.pl (the names below): the validity
/// check before commit, which relations redesign is shown, and when a
/// final pattern's inner node is searched for.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HostBounds {
    /// `valid_corner`: an element's corners must be in [this, 180 - this]
    /// degrees.
    pub valid_corner: f64,
    /// cos² of `valid_corner`, for telling a corner inside without
    /// trigonometry.
    pub cos2_valid_corner: f64,
    /// `valid_edge`: the shortest element edge, as a share of the edge it
    /// is built on.
    pub valid_edge: f64,
    /// `valid_clearance`: how close a new corner or edge may come to the
    /// front, as a share of the edge it is built on.
    pub valid_clearance: f64,
    /// `min_front_angle`: the sharpest corner an element may leave the
    /// remaining domain (degrees).
    pub min_front_angle: f64,
    /// `relation_corner`: an outer, remaining or inner corner below this
    /// (degrees) is a relation redesign is shown.
    pub relation_corner: f64,
    /// `relation_inner_above`: an inner corner above this (degrees) is a
    /// relation too.
    pub relation_inner_above: f64,
    /// `relation_reach`: front nodes and segments within this many
    /// element sizes of a new corner are relations.
    pub relation_reach: f64,
    /// `centre_search_below`: a final pattern's inner node (Eq. 5, 6)
    /// whose elements have a corner closer than this to 0 or 180 degrees
    /// is moved to the best place of a search.
    pub centre_search_below: f64,
    /// `tip_corner`: a front corner sharper than this (degrees) is a tip,
    /// taken whole by one element; the validity check lets that element's
    /// corner there be as sharp as the tip and its sides across the tip
    /// as short as the tip's wedge makes them.
    pub tip_corner: f64,
    /// `fallback_take_back`: where the rules stop, the elements next to an
    /// open loop with an area under this many element sizes squared are
    /// taken back into it (see fallback/stuck_loops.rs).
    pub fallback_take_back: f64,
    /// `fallback_spacing`: the spacing of the interior points of the open
    /// loops' triangles, in element sizes.
    pub fallback_spacing: f64,
    /// `fallback_pairs`: the spacing of the interior points of an open
    /// loop's triangles when they are paired into quads, in lengths of
    /// the loop's edges (their mean; fallback/pairs.rs); 0: never paired,
    /// always split in three.
    pub fallback_pairs: f64,
    /// `ring_corner_give`: how many degrees of its smallest corner a ring
    /// (fallback/rings.rs) gives up for sizes that fit its neighbours.
    pub ring_corner_give: f64,
    /// `thin_wall`: edges facing each other closer than this many element
    /// sizes get one segment count (see input/thin_walls.rs).
    pub thin_wall: f64,
    /// `size_growth`: in a graded run, how much the size aimed for grows
    /// a unit of distance from the boundary (see size_field.rs).
    pub size_growth: f64,
    /// `block_size`: with `--blocks`, the size of the block layout's
    /// elements, in element sizes (see blocks/mod.rs).
    pub block_size: f64,
    /// `block_arc_step`: with `--blocks`, the layout divides arcs in
    /// steps of at most this many degrees.
    pub block_arc_step: f64,
    /// `four_sided_pairs`: with `--blocks`, a four-sided domain whose
    /// opposite sides' counts differ is also tried in mapped patches round
    /// at most this many pairs of irregular nodes (0: never; see
    /// blocks/four_sided.rs).
    pub four_sided_pairs: f64,
    /// `blocks_when_out_of_bounds`: a free mesh (uniform, without
    /// `--blocks`) with elements outside the bounds is also meshed in
    /// blocks, on the layouts with at most this share of their blocks
    /// free, and the one with fewer elements outside kept (0: never; see
    /// blocks/mod.rs, `mesh_free_then_blocks`).
    pub blocks_when_out_of_bounds: f64,
    /// `retry_sharpest_corner`: the retries of `retry_bound/3` are not
    /// tried on a domain with an input corner sharper than this (deg): no
    /// element at it meets the taper bound, so none would come within
    /// the bounds (see blocks/mod.rs, `mesh_free_then_blocks`); the
    /// element at such a tip is left out of the aspect and taper that
    /// choose among meshes (blocks/score.rs).
    pub retry_sharpest_corner: f64,
    /// `blocks_first`: a uniform run (without `--blocks`, no cracks) is
    /// meshed in blocks first, and where a layout's mesh is within the
    /// bounds it is kept and no free mesh made, unless it has many
    /// elements (`blocks_over_free`) (0: the free mesh first;
    /// see blocks/mod.rs, `mesh_free_then_blocks`).
    pub blocks_first: f64,
    /// `out_of_bounds_step`: where every mesh tried falls short of the
    /// bounds, the one kept has the fewest elements out of bounds, each
    /// counted once more for every this many degrees its worst corner
    /// lies outside the window (0: each once; see blocks/score.rs, `Score`).
    pub out_of_bounds_step: f64,
    /// `coarse_boundary_grading`: without a `max_size`, where fixed
    /// counts make a boundary segment longer than this many times the
    /// size, the interior may grow to the longest segment (0: never; see
    /// pipeline.rs, `coarse_boundary_limit`).
    pub coarse_boundary_grading: f64,
    /// `coarser_when_over`: a uniform run whose mesh has more than this
    /// many times the domain's area over the size squared in elements is
    /// meshed again with the variants `retry_needs(V, many_elements)`
    /// (0: never; see blocks/coarser.rs).
    pub coarser_when_over: f64,
    /// `blocks_over_free`: a blocks mesh within the bounds with more than
    /// this many times the elements the boundary's segment lengths ask
    /// for is compared with the free mesh, and the free mesh kept where
    /// it is within the bounds and the blocks have more than this many
    /// times its elements (0: the blocks kept; see blocks/mod.rs,
    /// `choose_uniform_mesh`).
    pub blocks_over_free: f64,
    /// `uniform_when_graded_short`: a graded mesh that falls short after
    /// its retries is meshed again uniform at the size (blocks, retries
    /// and all), and that mesh kept where it is within the bounds (0:
    /// never; see blocks/retries.rs, `graded_with_retries`).
    pub uniform_when_graded_short: f64,
    /// `coarser_after_four_sided`: where a uniform run's mesh is the
    /// four-sided patches (laid from the boundary's counts alone, no rule
    /// read), the coarser pass is made too only where this is above 0
    /// (see blocks/coarser.rs).
    pub coarser_after_four_sided: f64,
    /// `corner_slack`: in choosing among meshes (blocks, free, retries,
    /// coarser, graded or not), a corner within this many degrees
    /// outside the window counts as within it, the tolerance the judge
    /// measures corners with (0: the window exactly; see
    /// blocks/score.rs, `Score`).
    pub corner_slack: f64,
    /// `layout_steps`: a block layout (the rules at a coarse size) is
    /// given up once it has taken this many steps an expected element,
    /// and 30 more (see blocks/mod.rs, `layout`).
    pub layout_steps: f64,
    /// `arc_corner_chord`: where an arc's first chord at an input corner
    /// would take the element's corner more than this many degrees below
    /// the lower of the corner and the window's lower corner (or above
    /// the upper), the arc's segments grow from a shorter first one (0:
    /// uniform segments; see input/arc_corners.rs).
    pub arc_corner_chord: f64,
    /// `arc_corner_from`: a corner sharper than this many degrees keeps
    /// its arcs' equal segments (see input/arc_corners.rs).
    pub arc_corner_from: f64,
    /// `fallback_reopen_rings`: where the rules' elements lost a boundary
    /// or line segment, the elements within this many rings of it are
    /// meshed again with the segment in place (see pipeline/stuck.rs).
    pub fallback_reopen_rings: f64,
    /// `closing_loop_segments`: where no rule applies, a loop of at most
    /// this many segments is closed whole by the ways of `closing_way/2`
    /// (see final_patterns/closing.rs).
    pub closing_loop_segments: f64,
    /// `closing_strict_margin`: the strict closing of a stuck loop follows
    /// a split only while its parts score within the corner window plus
    /// this many degrees (see final_patterns.rs).
    pub closing_strict_margin: f64,
    /// `closing_strict_size`: the strict closing of a stuck loop keeps an
    /// element on the loop within this factor of the loop's edges it
    /// takes (see final_patterns.rs).
    pub closing_strict_size: f64,
    /// `coarsest_edge`: in a graded run, a transition whose new edge
    /// would be longer than this many times `max_size` is refused (see
    /// recursion/mesher/coarsen.rs).
    pub coarsest_edge: f64,
    /// `uniform_size_band`: in a uniform run, an edge within this factor
    /// of the size reads a grading ratio of 1; beyond it (a fixed segment
    /// count much finer or coarser than the size) its true ratio, so that
    /// the transitions can act (see partial_mesh.rs, `grading_ratio`);
    /// 1 or less: every edge reads 1.
    pub uniform_size_band: f64,
    /// `graded_collapse_below`: after smoothing, an element under this
    /// many times the size the field aims for at its middle is collapsed
    /// or merged where its region stays within the bounds (0: never;
    /// see cleanup/coarsen.rs).
    pub graded_collapse_below: f64,
    /// `weighted_laplace`: 1: Laplace smoothing weighs each neighbour by
    /// the inverse of the size field at the edge's middle, so that it
    /// keeps the grading (0: the plain mean; see smoothing/laplace.rs).
    pub weighted_laplace: f64,
    /// `line_gap`: an inner line's edge nearer another loop or line (one
    /// it does not touch) than this many element sizes gets segments as
    /// long as the gap (0: never; see input/line_gaps.rs).
    pub line_gap: f64,
    /// `line_gap_floor`: those segments are no shorter than this many
    /// element sizes.
    pub line_gap_floor: f64,
    /// `finer_layouts_up_to`: the finer block layouts are made only where
    /// the coarsest has at most this many blocks (see blocks/layouts.rs).
    pub finer_layouts_up_to: f64,
    /// `layout_sizes_free_over`: the finish (smoothing, clean-up, easing)
    /// of a block layout whose rules made more elements than this judges
    /// its blocks by their corners and taper alone, each block being
    /// divided to the element size (see `ElementBounds::for_layout`).
    pub layout_sizes_free_over: f64,
}

impl Default for HostBounds {
    /// The built-in values (kb/strategy.pl).
    fn default() -> HostBounds {
        HostBounds::new(HostBounds::BUILT_IN).expect("the built-in host bounds are consistent")
    }
}

impl HostBounds {
    /// The built-in values (kb/strategy.pl), in the order of `NAMES`.
    pub const BUILT_IN: [f64; 43] = [
        4.0, 0.25, 0.15, 12.0, 90.0, 120.0, 1.0, 30.0, 45.0, 0.25, 1.5, 10.0, 2.0, 0.6, 4.0, 45.0,
        2.0, 12.0, 10.0, 1.6, 1.2, 0.0, 2.0, 0.5, 8.1, 1.0, 5.0, 1.5, 1.2, 1.0, 1.25, 1.0, 0.0,
        0.5, 3.0, 0.2, 15.0, 0.0, 0.0, 1.0, 0.25, 400.0, 400.0,
    ];

    /// The names of the `bound/2` entries, in the order `new` takes them.
    pub const NAMES: [&'static str; 43] = [
        "valid_corner",
        "valid_edge",
        "valid_clearance",
        "min_front_angle",
        "relation_corner",
        "relation_inner_above",
        "relation_reach",
        "centre_search_below",
        "tip_corner",
        "fallback_take_back",
        "fallback_spacing",
        "ring_corner_give",
        "thin_wall",
        "size_growth",
        "block_size",
        "block_arc_step",
        "fallback_reopen_rings",
        "closing_loop_segments",
        "closing_strict_margin",
        "closing_strict_size",
        "coarsest_edge",
        "uniform_size_band",
        "four_sided_pairs",
        "blocks_when_out_of_bounds",
        "retry_sharpest_corner",
        "blocks_first",
        "out_of_bounds_step",
        "coarse_boundary_grading",
        "coarser_when_over",
        "fallback_pairs",
        "blocks_over_free",
        "uniform_when_graded_short",
        "coarser_after_four_sided",
        "corner_slack",
        "layout_steps",
        "arc_corner_chord",
        "arc_corner_from",
        "graded_collapse_below",
        "weighted_laplace",
        "line_gap",
        "line_gap_floor",
        "finer_layouts_up_to",
        "layout_sizes_free_over",
    ];

    /// The bounds in the order of `NAMES`, or a sentence saying which is
    /// out of range (angles within [0, 90) or [0, 180], shares and reach
    /// not negative).
    pub fn new(v: [f64; 43]) -> Result<HostBounds, String> {
        let [valid_corner, valid_edge, valid_clearance, min_front_angle, relation_corner, relation_inner_above, relation_reach, centre_search_below, tip_corner, fallback_take_back, fallback_spacing, ring_corner_give, thin_wall, size_growth, block_size, block_arc_step, fallback_reopen_rings, closing_loop_segments, closing_strict_margin, closing_strict_size, coarsest_edge, uniform_size_band, four_sided_pairs, blocks_when_out_of_bounds, retry_sharpest_corner, blocks_first, out_of_bounds_step, coarse_boundary_grading, coarser_when_over, fallback_pairs, blocks_over_free, uniform_when_graded_short, coarser_after_four_sided, corner_slack, layout_steps, arc_corner_chord, arc_corner_from, graded_collapse_below, weighted_laplace, line_gap, line_gap_floor, finer_layouts_up_to, layout_sizes_free_over] =
            v;
        let ranges = [
            (0.0, 90.0),
            (0.0, f64::MAX),
            (0.0, f64::MAX),
            (0.0, 180.0),
            (0.0, 180.0),
            (0.0, 180.0),
            (0.0, f64::MAX),
            (0.0, 90.0),
            (0.0, 90.0),
            (0.0, f64::MAX),
            (0.1, f64::MAX),
            (0.0, 90.0),
            (0.0, f64::MAX),
            (0.0, f64::MAX),
            (1.0, f64::MAX),
            (1.0, 180.0),
            (0.0, 100.0),
            (0.0, 41.0),
            (0.0, 90.0),
            (1.0, f64::MAX),
            (0.1, f64::MAX),
            (0.0, f64::MAX),
            (0.0, 3.0),
            (0.0, 2.0),
            (0.0, 180.0),
            (0.0, 2.0),
            (0.0, 180.0),
            (0.0, f64::MAX),
            (0.0, f64::MAX),
            (0.0, f64::MAX),
            (0.0, f64::MAX),
            (0.0, f64::MAX),
            (0.0, 2.0),
            (0.0, 5.0),
            (0.0, f64::MAX),
            (0.0, 5.0),
            (0.0, 180.0),
            (0.0, 1.0),
            (0.0, 2.0),
            (0.0, f64::MAX),
            (0.05, 2.0),
            (0.0, f64::MAX),
            (0.0, f64::MAX),
        ];
        for ((name, x), (lo, hi)) in Self::NAMES.iter().zip(v).zip(ranges) {
            if !(x >= lo && x < hi) {
                // (no upper end where any finite number will do)
                let below = if hi == f64::MAX {
                    String::new()
                } else {
                    format!(" and below {hi}")
                };
                return Err(format!("bound({name}, {x}) must be at least {lo}{below}"));
            }
        }
        let c = valid_corner.to_radians().cos();
        Ok(HostBounds {
            valid_corner,
            cos2_valid_corner: c * c,
            valid_edge,
            valid_clearance,
            min_front_angle,
            relation_corner,
            relation_inner_above,
            relation_reach,
            centre_search_below,
            tip_corner,
            fallback_take_back,
            fallback_spacing,
            ring_corner_give,
            thin_wall,
            size_growth,
            block_size,
            block_arc_step,
            fallback_reopen_rings,
            closing_loop_segments,
            closing_strict_margin,
            closing_strict_size,
            coarsest_edge,
            uniform_size_band,
            four_sided_pairs,
            blocks_when_out_of_bounds,
            retry_sharpest_corner,
            blocks_first,
            out_of_bounds_step,
            coarse_boundary_grading,
            coarser_when_over,
            fallback_pairs,
            blocks_over_free,
            uniform_when_graded_short,
            coarser_after_four_sided,
            corner_slack,
            layout_steps,
            arc_corner_chord,
            arc_corner_from,
            graded_collapse_below,
            weighted_laplace,
            line_gap,
            line_gap_floor,
            finer_layouts_up_to,
            layout_sizes_free_over,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A host bound out of its range is named with the range, its upper
    /// end left out where any finite number will do.
    #[test]
    fn a_host_bound_out_of_range_is_named_with_its_range() {
        let at = |name: &str, x: f64| {
            let mut v = HostBounds::BUILT_IN;
            let i = HostBounds::NAMES.iter().position(|n| *n == name).unwrap();
            v[i] = x;
            HostBounds::new(v).unwrap_err()
        };
        assert_eq!(
            at("finer_layouts_up_to", -1.0),
            "bound(finer_layouts_up_to, -1) must be at least 0"
        );
        assert_eq!(
            at("four_sided_pairs", 3.0),
            "bound(four_sided_pairs, 3) must be at least 0 and below 3"
        );
        assert!(HostBounds::new(HostBounds::BUILT_IN).is_ok());
    }

    #[test]
    fn the_paper_window_has_cos_squared_one_half_on_both_sides() {
        let b = ElementBounds::default();
        assert_eq!(b.cos2_lower, 0.5);
        assert_eq!(b.cos2_upper, 0.5);
    }

    #[test]
    fn a_narrower_window_puts_a_corner_of_48_degrees_outside() {
        let b = ElementBounds::new(50.0, 130.0, 10.0, 10.0, 2.0).unwrap();
        let c = 48f64.to_radians();
        // edge vectors (1, 0) and (cos c, sin c)
        assert!(!b.corner_inside(c.cos(), 1.0, 1.0));
        assert!(ElementBounds::default().corner_inside(c.cos(), 1.0, 1.0));
        assert_eq!(b.corner_excess(48.0), 2.0);
    }

    #[test]
    fn the_built_in_valid_corner_gives_the_cosine_squared_of_4_degrees() {
        assert_eq!(
            HostBounds::default().cos2_valid_corner,
            0.995_134_034_370_785_1
        );
    }

    #[test]
    fn a_negative_reach_is_refused() {
        let mut v = HostBounds::BUILT_IN;
        v[6] = -1.0;
        let e = HostBounds::new(v).unwrap_err();
        assert!(e.contains("relation_reach"), "{e}");
    }

    #[test]
    fn a_window_without_a_right_angle_is_refused() {
        let e = ElementBounds::new(95.0, 135.0, 10.0, 10.0, 2.0).unwrap_err();
        assert!(e.contains("lower_corner"), "{e}");
    }
}
