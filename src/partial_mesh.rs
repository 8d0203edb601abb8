//! The state of the recursion, Ω_n = ⟨Q_i, Ω_{n−i}⟩ (Eq. 1): the elements
//! made so far and the remaining domain's front, with the record of how
//! they came to be (the trace and the counters). Every stage of the
//! recursion (initial design, redesign, final patterns, the fallbacks)
//! works on it.

use glam::DVec2;
use rustc_hash::{FxHashMap as HashMap, FxHashSet as HashSet};

use crate::front::{Front, Fv};
use crate::geometry::{orient2d, segments_intersect, SegmentRelation};
use crate::input::boundary::Discretised;
use crate::mesh::{Mesh, NodeKind};
use crate::report::trace::{Angles, By, TraceStep, Veto};
use crate::settings::{ElementBounds, HostBounds};
use crate::size_field::SizeField;

/// Counters of one meshing run.
#[derive(Debug, Default, Clone, Copy)]
pub struct MeshStats {
    /// Elements made by design actions.
    pub designed: usize,
    /// Elements made by final patterns and by the fallback's rings.
    pub closed: usize,
    /// Of those, elements made by rings.
    pub ring_elements: usize,
    /// Rings made (counted among the fallback splits too).
    pub rings: usize,
    /// Elements of the last resort's mesh (0 unless it was taken).
    pub triangle_elements: usize,
    /// Designs the host's validity check refused (each in the trace).
    pub vetoes: usize,
    /// Loop splits by the fallback.
    pub fallback_splits: usize,
    /// Redesign rules fired.
    pub redesigns: usize,
    /// Merges of a new corner with a front node (fronts meeting).
    pub merges: usize,
    /// Elements taken back to give a stuck loop room.
    pub unmeshed: usize,
    /// Elements made inside the loops the rules and the loop subdivision
    /// left open (see fallback/stuck_loops.rs).
    pub loop_triangle_elements: usize,
    /// The open loops so closed.
    pub open_loops_closed: usize,
    /// The rules' elements split to carry that fallback's halving.
    pub chord_split_elements: usize,
    /// Runs the rules could not finish, meshed whole by the last resort
    /// (triangles split into quads, see fallback/triangles.rs).
    pub triangle_fallbacks: usize,
    /// Edges flipped by the clean-up (cleanup.rs).
    pub cleanup_flips: usize,
    /// Elements collapsed by the clean-up.
    pub cleanup_collapses: usize,
    /// Hexagons split into three by the clean-up.
    pub cleanup_splits: usize,
    /// Moves of easing that slid a boundary node along its straight
    /// input edge (`bound(boundary_slide, S)`).
    pub boundary_slides: usize,
    /// Elements a graded mesh lost to collapses and merges where it was
    /// finer than its size field asks (`bound(graded_collapse_below, F)`).
    pub coarsened: usize,
    /// Regions round elements past the bounds that polishing brought
    /// nearer them (`bound(polish_rings, R)`).
    pub polished: usize,
    /// Input edges given one segment count with the edges they face
    /// across a wall thinner than `bound(thin_wall, K)` element sizes.
    pub thin_wall_edges: usize,
    /// Inner lines' edges given segments of their gap to another part of
    /// the boundary nearer than `bound(line_gap, F)` element sizes.
    pub near_line_edges: usize,
    /// With `--blocks`, the blocks meshed as mapping elements (the other
    /// counts are then the block layout's); 0 otherwise.
    pub blocks: usize,
}

impl MeshStats {
    /// How many elements each maker made (for `Chord`, loop splits; for
    /// `Unmesh`, elements taken back), in the order of `By`. After the
    /// last resort only its elements count: the rules' attempt is gone.
    pub fn made_by(&self) -> [(By, usize); 6] {
        let t = self.triangle_elements;
        let of = |n: usize| if t > 0 { 0 } else { n };
        [
            (By::Rule, of(self.designed)),
            (By::Pattern, of(self.closed - self.ring_elements)),
            (By::Chord, of(self.fallback_splits - self.rings)),
            (By::Ring, of(self.ring_elements)),
            (By::Unmesh, of(self.unmeshed)),
            (By::Triangles, t + of(self.loop_triangle_elements)),
        ]
    }

    /// What the summary says where the rules stopped short: ` (the rules
    /// stopped: ...)`, or nothing.
    pub fn stopped_text(&self) -> String {
        if self.triangle_fallbacks > 0 {
            " (the rules stopped: meshed whole by the triangle fallback)".into()
        } else if self.open_loops_closed > 0 {
            format!(
                " (the rules stopped: {} open loop{} closed by triangles, {} elements split along their rows)",
                self.open_loops_closed,
                if self.open_loops_closed == 1 { "" } else { "s" },
                self.chord_split_elements
            )
        } else {
            String::new()
        }
    }

    /// The summary's words for `made_by` and the vetoes: `by rule 700,
    /// pattern 98, ...; 3 vetoes`.
    pub fn made_by_text(&self) -> String {
        let parts: Vec<String> = self
            .made_by()
            .iter()
            .map(|(by, n)| format!("{} {n}", by.name()))
            .collect();
        let made = format!("by {}; {} vetoes", parts.join(", "), self.vetoes);
        if self.blocks > 0 {
            format!("in {} mapped blocks, laid out {made}", self.blocks)
        } else {
            made
        }
    }
}

/// What the trace says of the elements that close a loop.
pub struct Closing<'a> {
    /// The feature (`final4`, `final6`, `stuck`).
    pub feature: &'a str,
    /// The action (the pattern, `quad`, `ring`).
    pub action: String,
    /// The angles seen.
    pub angles: Angles,
    /// Who made them.
    pub by: By,
}

/// The elements made so far and the remaining domain.
pub struct PartialMesh {
    /// The mesh built so far.
    pub mesh: Mesh,
    /// The remaining domain.
    pub front: Front,
    /// The inference trace (kept when `record_trace`).
    pub trace: Vec<TraceStep>,
    /// The host's thresholds (`bound/2`, see settings.rs).
    pub host: HostBounds,
    /// The element bounds (`bound/2`): the final patterns' corner window.
    pub bounds: ElementBounds,
    /// The designs the validity check refused (kept when `record_trace`).
    pub vetoes: Vec<Veto>,
    /// Whether steps are recorded in `trace` (they are always counted).
    pub record_trace: bool,
    /// Steps of the inference so far.
    steps: usize,
    /// Counters.
    pub stats: MeshStats,
    /// Past this many elements the run is a runaway.
    pub max_elements: usize,
    /// No element edge shorter than this: a third of the shortest input
    /// segment, so elements cannot shrink without end.
    pub min_edge: f64,
    /// A buffer for the front's spatial queries.
    pub scratch: Vec<Fv>,
    /// Check every new element against all others (`Options::self_check`;
    /// quadratic, for debugging the rules).
    pub debug_check: bool,
    /// Loops the design rules gave up on: only the fallback works on them
    /// (and on the loops split from them), so the rules cannot remesh a
    /// region they already failed in.
    pub fallback_only: HashSet<u32>,
    /// The element on the left of each directed element edge, kept as
    /// elements come and go once the fallback first asks it (zipping
    /// slits, taking back a layer); most runs never do.
    edge_owner: Option<HashMap<(u32, u32), u32>>,
    /// The area of the domain (what the finished mesh must cover).
    pub area: f64,
    /// Whether a loop that a take-back leaves must enclose an area (a
    /// region on its left): with lines that end on a loop, a loop can pass
    /// a hole's ring and the take-back part that ring off on its own,
    /// which no rule or fallback closes. Only for such domains: on for all
    /// (with the merges'), 844 of the 1055 random domains of the README
    /// were within the bounds against 852. (A merge is held to it on
    /// every domain, see `Mesher::commit_element`.)
    pub guard_loop_areas: bool,
    /// The inner lines' segments, both ways: the domain lies on both
    /// sides of them (see `parts_a_line_seam`).
    line_segments: rustc_hash::FxHashSet<(u32, u32)>,
    /// The size aimed for at each place, in a graded run (None: uniform).
    pub size_field: Option<SizeField>,
    /// The run's size (the boundary's, where no segment count is fixed).
    pub size: f64,
}

impl PartialMesh {
    /// The start of a run on a discretised domain with boundary size
    /// `size` and area `area`: no element, the front the boundary; and
    /// the number of elements expected.
    pub fn new(disc: Discretised, size: f64, area: f64) -> (PartialMesh, usize) {
        let guard_loop_areas = disc.lines_meet;
        let mut front = Front::new(&disc.front_loops[0], size);
        for more in &disc.front_loops[1..] {
            front.add_loop(more, &[]);
        }
        front.index_all(&disc.mesh.nodes);
        let boundary_len: usize = disc.front_loops.iter().map(Vec::len).sum();
        let estimate = (area / (size * size)).max(1.0) + boundary_len as f64;
        let shortest = disc
            .mesh
            .boundary
            .iter()
            .map(|e| (disc.mesh.nodes[e.a as usize] - disc.mesh.nodes[e.b as usize]).length())
            .fold(size, f64::min);
        // the run's tables sized for the elements expected: growing them
        // step by step copies them over and over
        let expected = estimate.min(4e6) as usize;
        let mut mesh = disc.mesh;
        let line_segments = mesh
            .boundary
            .iter()
            .filter(|e| mesh.groups[e.group as usize].starts_with("line "))
            .flat_map(|e| [(e.a, e.b), (e.b, e.a)])
            .collect();
        mesh.quads.reserve(expected + expected / 8);
        mesh.nodes.reserve(expected + expected / 8);
        front.reserve(expected + expected / 8);
        let pm = PartialMesh {
            mesh,
            front,
            trace: Vec::new(),
            vetoes: Vec::new(),
            host: HostBounds::default(),
            bounds: ElementBounds::default(),
            record_trace: true,
            steps: 0,
            stats: MeshStats::default(),
            max_elements: (estimate * 4.0) as usize + 1000,
            min_edge: shortest / 3.0,
            scratch: Vec::new(),
            debug_check: false,
            fallback_only: Default::default(),
            edge_owner: None,
            area,
            guard_loop_areas,
            line_segments,
            size_field: None,
            size,
        };
        (pm, expected)
    }

    /// Makes the run graded: the size field grows from the boundary's
    /// segments (each loop of the front as it is now) by `growth` a unit
    /// of distance up to `max_size`.
    pub fn grade(&mut self, growth: f64, max_size: f64) {
        let mut segments = Vec::new();
        for l in self.front.live_loops() {
            let fvs = self.front.loop_fvs(l);
            for (i, &fv) in fvs.iter().enumerate() {
                let next = fvs[(i + 1) % fvs.len()];
                segments.push((self.pos(fv), self.pos(next)));
            }
        }
        self.size_field = SizeField::new(segments, growth, max_size);
    }

    /// The grading ratio of the edge from `a` to `b`: the size aimed for at
    /// its middle over its length, in tenths. In a uniform run the size
    /// aimed for is the run's size, and an edge within
    /// `bound(uniform_size_band, _)` of it reads 1 (as most do: their
    /// contexts stay alike), one beyond it its ratio (a fixed segment
    /// count far from the size, for the transitions); with the band at 1
    /// or less (built in) every edge reads 1.
    pub fn grading_ratio(&self, a: DVec2, b: DVec2) -> f64 {
        let band = self.host.uniform_size_band;
        if self.size_field.is_none() && band <= 1.0 {
            return 1.0;
        }
        let l = (b - a).length().max(1e-300);
        let tenths = |r: f64| (r * 10.0).round() / 10.0;
        match &self.size_field {
            Some(f) => tenths(f.at((a + b) * 0.5) / l),
            None => {
                let r = self.size / l;
                if r * band > 1.0 && r < band {
                    1.0
                } else {
                    tenths(r)
                }
            }
        }
    }

    /// Whether parting the loop at occurrences `m` and `o` of one node
    /// (`Front::split_pinch`) would close a two-edge loop, the node and a
    /// neighbour there and back, along an inner line: the front would
    /// take it for a seam between elements, while both of the line's
    /// sides still want theirs.
    pub fn parts_a_line_seam(&self, m: Fv, o: Fv) -> bool {
        let node = self.front.node(m);
        [(m, o), (o, m)].iter().any(|&(u, v)| {
            let b = self.front.next(v);
            self.front.next(b) == u && self.line_segments.contains(&(node, self.front.node(b)))
        })
    }

    /// The signed area a loop encloses (positive: a region on its left).
    pub fn loop_area(&self, l: u32) -> f64 {
        let pts: Vec<DVec2> = self
            .front
            .loop_fvs(l)
            .iter()
            .map(|&f| self.mesh.nodes[self.front.node(f) as usize])
            .collect();
        crate::geometry::polygon_area(&pts)
    }

    /// The position of a front occurrence's node.
    pub fn pos(&self, fv: Fv) -> DVec2 {
        self.mesh.nodes[self.front.node(fv) as usize]
    }

    /// Counts a step of the inference and records it in the trace when
    /// the trace is kept (`make` gets the step's number).
    pub fn note_step(&mut self, make: impl FnOnce(usize) -> TraceStep) {
        self.steps += 1;
        if self.record_trace {
            let step = make(self.steps);
            self.trace.push(step);
        }
    }

    /// Counts a design the validity check refused and records it when the
    /// trace is kept (before the next step).
    pub fn note_veto(&mut self, make: impl FnOnce(usize) -> Veto) {
        self.stats.vetoes += 1;
        if self.record_trace {
            let veto = make(self.steps + 1);
            self.vetoes.push(veto);
        }
    }

    /// Adds an element, noting it as the owner of its edges.
    pub fn push_quad(&mut self, q: [u32; 4]) {
        let qi = self.mesh.quads.len() as u32;
        if let Some(owner) = &mut self.edge_owner {
            own_edges(owner, q, qi);
        }
        self.mesh.quads.push(q);
    }

    /// Removes element `qi` (the last element takes its place).
    pub fn remove_quad(&mut self, qi: usize) -> [u32; 4] {
        let q = self.mesh.quads.swap_remove(qi);
        if let Some(owner) = &mut self.edge_owner {
            for i in 0..4 {
                let e = (q[i], q[(i + 1) % 4]);
                if owner.get(&e) == Some(&(qi as u32)) {
                    owner.remove(&e);
                }
            }
            if let Some(&moved) = self.mesh.quads.get(qi) {
                own_edges(owner, moved, qi as u32);
            }
        }
        q
    }

    /// The owners of the element edges, gathered the first time they are
    /// asked for and kept from then on.
    pub fn edge_owners(&mut self) -> &HashMap<(u32, u32), u32> {
        let quads = &self.mesh.quads;
        self.edge_owner.get_or_insert_with(|| {
            let mut owner =
                HashMap::with_capacity_and_hasher(4 * quads.len() + 1024, Default::default());
            for (qi, &q) in quads.iter().enumerate() {
                own_edges(&mut owner, q, qi as u32);
            }
            owner
        })
    }

    /// The owners of the element edges if they were gathered.
    pub fn edge_owners_if_kept(&self) -> Option<&HashMap<(u32, u32), u32>> {
        self.edge_owner.as_ref()
    }

    /// Frees what only the recursion needs (the front, its index, the
    /// element edges' owners) once it is done.
    pub fn release_working_state(&mut self) {
        self.front = Front::default();
        self.edge_owner = None;
    }

    /// Closes loop `l` with `quads` (their corners are node ids; the
    /// nodes `new_nodes` are added first), one trace step an element, as
    /// `closing` says.
    pub fn close_with(
        &mut self,
        l: u32,
        quads: Vec<[u32; 4]>,
        new_nodes: &[DVec2],
        closing: Closing,
    ) {
        let Closing {
            feature,
            action,
            angles,
            by,
        } = closing;
        for &c in new_nodes {
            self.mesh.add_node(c, NodeKind::Interior);
        }
        let head = self.front.loop_head(l);
        let edge = [
            self.front.node(head),
            self.front.node(self.front.next(head)),
        ];
        self.front.begin();
        self.front.close_loop(l);
        self.front.commit(&self.mesh.nodes);
        for q in quads {
            self.push_quad(q);
            if self.debug_check {
                self.debug_overlap(self.mesh.quads.len() - 1);
            }
            self.stats.closed += 1;
            if by == By::Ring {
                self.stats.ring_elements += 1;
            }
            self.note_step(|step| TraceStep {
                step,
                edge: edge.map(|x| x as i64),
                angles: angles.clone(),
                feature: feature.into(),
                action: action.clone(),
                by,
                redesign: vec![],
                element: q.iter().map(|&x| x as i64).collect(),
            });
        }
    }

    /// A debugging aid: reports every element element `qi` overlaps.
    pub fn debug_overlap(&self, qi: usize) {
        let p = self.mesh.quad_points(qi);
        for j in 0..qi {
            let r = self.mesh.quad_points(j);
            let inside =
                |x: DVec2, q: &[DVec2; 4]| (0..4).all(|i| orient2d(q[i], q[(i + 1) % 4], x) > 0.0);
            let mut bad = p.iter().any(|&x| inside(x, &r)) || r.iter().any(|&x| inside(x, &p));
            for a in 0..4 {
                for b in 0..4 {
                    if segments_intersect(p[a], p[(a + 1) % 4], r[b], r[(b + 1) % 4])
                        == SegmentRelation::Cross
                    {
                        bad = true;
                    }
                }
            }
            if bad {
                eprintln!(
                    "DEBUG: quad {qi} {:?} overlaps quad {j} {:?} at step {}: {:?} and {:?}",
                    self.mesh.quads[qi],
                    self.mesh.quads[j],
                    self.steps + 1,
                    p.map(|x| (x.x, x.y)),
                    r.map(|x| (x.x, x.y))
                );
            }
        }
    }

    /// Each open loop of the front in loop order, as `each` reads its
    /// occurrences.
    pub fn map_front_loops<T>(&self, each: impl Fn(Fv) -> T) -> Vec<Vec<T>> {
        self.front
            .live_loops()
            .iter()
            .map(|&l| self.front.loop_fvs(l).into_iter().map(&each).collect())
            .collect()
    }
}

/// Notes element `qi` (corners `q`) as the owner of its directed edges.
fn own_edges(owner: &mut HashMap<(u32, u32), u32>, q: [u32; 4], qi: u32) {
    for i in 0..4 {
        owner.insert((q[i], q[(i + 1) % 4]), qi);
    }
}
