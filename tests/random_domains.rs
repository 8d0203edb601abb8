//! Property test: every valid domain gives a valid all-quad mesh.
//!
//! A seeded generator makes random domains in the format of
//! ../shared/domain-format.md: star-shaped and non-convex outer loops with
//! arcs, sharp and reflex corners, holes of several shapes (some close to
//! each other or to the boundary), inner lines, narrow channels and thin
//! slits, fixed and unequal segment counts (segments half to four sizes
//! long), and the kinds that proved hard: spikes of 3 to 40 degrees,
//! notches and cusps up to 358 degrees, chamfered corners, walls thinner
//! than an element, blades with sharp trailing edges, mapped
//! quadrilaterals with unequal fixed counts; models across six decades of
//! scale. A domain the validator refuses is skipped (and counted); every
//! other one must mesh, and its mesh is checked here, independently of the
//! mesher's own check: all quads convex and counter-clockwise, conforming
//! (an edge in at most two quads, the boundary edges in one), covering the
//! domain's area.
//!
//! CI runs a small set (`FREEMESH_RANDOM_DOMAINS`, default 40); the long
//! run documented in the README is
//! `FREEMESH_RANDOM_DOMAINS=1000 cargo test --release --test random_domains`.
//! A failing case prints its seed; `FREEMESH_RANDOM_SEED=N` runs one seed
//! and writes its domain to the temporary directory;
//! `FREEMESH_RANDOM_FROM=N` starts the run at seed N;
//! `FREEMESH_RANDOM_DUMP=DIR` writes every valid domain to DIR, for
//! `../shared/bench/judge --set DIR` (with `FREEMESH_RANDOM_DUMP_ONLY=1`
//! too, it writes them without meshing them). A seed that takes
//! more than five seconds is named.

use freemesh::{mesh_domain, mesh_free_then_blocks, Domain, KnowledgeBase, Options};
use serde_json::{json, Value};
use std::collections::HashMap;
use std::f64::consts::PI;

/// SplitMix64: small, seeded, the same on every platform.
struct Rng(u64);

impl Rng {
    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in [a, b).
    fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
    fn int(&mut self, a: usize, b: usize) -> usize {
        a + (self.next_u64() % (b - a + 1) as u64) as usize
    }
    fn chance(&mut self, p: f64) -> bool {
        self.range(0.0, 1.0) < p
    }
}

type P = [f64; 2];

fn rot(p: P, c: P, a: f64, s: f64) -> P {
    let (x, y) = (p[0] * s, p[1] * s);
    [
        c[0] + x * a.cos() - y * a.sin(),
        c[1] + x * a.sin() + y * a.cos(),
    ]
}

/// The outer loop: one of several families, in a unit-ish frame.
/// Returns its points, bulges and the radius of a disc about the origin
/// that lies inside it (where holes and lines may go).
fn outer_loop(rng: &mut Rng) -> (&'static str, Shape) {
    let family = rng.int(0, 10);
    let name = FAMILIES[family];
    if family >= 5 {
        return (name, hard_shape(family, rng));
    }
    let (pts, bulges, inner) = match family {
        // star-shaped, sharp and reflex corners, some arcs
        0 | 1 => {
            let n = rng.int(3, 11);
            let mut angles: Vec<f64> = (0..n).map(|_| rng.range(0.0, 2.0 * PI)).collect();
            angles.sort_by(f64::total_cmp);
            angles.dedup_by(|a, b| (*a - *b).abs() < 0.15);
            let pts: Vec<P> = angles
                .iter()
                .map(|&a| {
                    let r = rng.range(0.45, 1.0);
                    [r * a.cos(), r * a.sin()]
                })
                .collect();
            let bulges = pts
                .iter()
                .map(|_| {
                    if rng.chance(0.3) {
                        rng.range(-0.3, 0.3)
                    } else {
                        0.0
                    }
                })
                .collect();
            (pts, bulges, 0.15)
        }
        // a rectangle with a narrow channel cut into it
        2 => {
            let w = rng.range(0.03, 0.15);
            let depth = rng.range(0.3, 0.8);
            let x = rng.range(-0.5, 0.5);
            let pts = vec![
                [-1.0, -0.6],
                [x - w / 2.0, -0.6],
                [x - w / 2.0, -0.6 + depth],
                [x + w / 2.0, -0.6 + depth],
                [x + w / 2.0, -0.6],
                [1.0, -0.6],
                [1.0, 0.6],
                [-1.0, 0.6],
            ];
            let n = pts.len();
            (pts, vec![0.0; n], 0.0)
        }
        // an L with a thin slit cut into it from its top edge
        3 => {
            let t = rng.range(0.2, 0.6);
            let slit = rng.range(0.005, 0.03);
            let x = rng.range(-0.8, -0.2);
            let depth = rng.range(0.3, 1.5);
            let pts = vec![
                [-1.0, -1.0],
                [1.0, -1.0],
                [1.0, -1.0 + t],
                [0.0, -1.0 + t],
                [0.0, 1.0],
                [x + slit / 2.0, 1.0],
                [x + slit / 2.0, 1.0 - depth],
                [x - slit / 2.0, 1.0 - depth],
                [x - slit / 2.0, 1.0],
                [-1.0, 1.0],
            ];
            let n = pts.len();
            (pts, vec![0.0; n], 0.0)
        }
        // a disc or a slot with rounded ends (arcs only)
        _ => {
            let h = rng.range(0.1, 0.6);
            let pts = vec![[-1.0, -h], [1.0, -h], [1.0, h], [-1.0, h]];
            (pts, vec![0.0, 1.0, 0.0, 1.0], h * 0.5)
        }
    };
    let shape = Shape {
        pts,
        bulges,
        inner,
        holes: Vec::new(),
        segments: None,
    };
    (name, shape)
}

/// The families' names, in the domain's name (random-SEED-FAMILY) so that
/// a judged set can be read by family.
const FAMILIES: [&str; 11] = [
    "star", "star", "channel", "slit", "slot", "spike", "notch", "chamfer", "wall", "blade",
    "mapped",
];

/// An outer loop in a unit-ish frame, holes of its own (points, bulges),
/// fixed segment counts if the family fixes them, and the radius of a
/// disc about the origin inside it where random holes and lines may go.
struct Shape {
    pts: Vec<P>,
    bulges: Vec<f64>,
    inner: f64,
    holes: Vec<(Vec<P>, Vec<f64>)>,
    segments: Option<Vec<usize>>,
}

impl Shape {
    fn polygon(pts: Vec<P>) -> Shape {
        let n = pts.len();
        Shape {
            pts,
            bulges: vec![0.0; n],
            inner: 0.0,
            holes: Vec::new(),
            segments: None,
        }
    }
}

/// The kinds of boundary that proved hard (issue 15): spikes, notches
/// and cusps, chamfers, thin walls, blades with sharp trailing edges,
/// mapped quadrilaterals with very unequal fixed counts.
fn hard_shape(family: usize, rng: &mut Rng) -> Shape {
    match family {
        // a spike out of a rectangle's top, its tip 3 to 40 degrees
        5 => {
            let tip = rng.range(3.0, 40.0).to_radians();
            let len = rng.range(0.3, 1.2);
            let x = rng.range(-0.5, 0.5);
            let lean = rng.range(-0.6, 0.6);
            let half = len * (tip / 2.0).tan();
            let apex = [x + lean * len, 0.5 + len];
            // the base is wide enough for the tip angle at this lean
            let w = half / (1.0 - lean.abs() * (tip / 2.0).tan()).max(0.2);
            Shape::polygon(vec![
                [-1.0, -0.5],
                [1.0, -0.5],
                [1.0, 0.5],
                [x + w, 0.5],
                apex,
                [x - w, 0.5],
                [-1.0, 0.5],
            ])
        }
        // a notch cut into a rectangle from below, 2 to 30 degrees wide
        // (a corner of 330 to 358 degrees), its sides straight or one an arc
        6 => {
            let open = rng.range(2.0, 30.0).to_radians();
            let depth = rng.range(0.3, 0.8);
            let x = rng.range(-0.5, 0.5);
            let w = depth * (open / 2.0).tan();
            let mut s = Shape::polygon(vec![
                [-1.0, -0.5],
                [x - w, -0.5],
                [x, -0.5 + depth],
                [x + w, -0.5],
                [1.0, -0.5],
                [1.0, 0.5],
                [-1.0, 0.5],
            ]);
            if rng.chance(0.4) {
                // the notch's far side an arc that leaves the tip nearly
                // tangent to the near side and curves away from it: a cusp
                // (its tangent turns from the chord by half its sweep)
                s.bulges[2] = (open * rng.range(0.5, 0.98) / 4.0).tan();
            }
            s
        }
        // a polygon with chamfered corners: short edges at 30 to 60
        // degrees between long ones
        7 => {
            let base: Vec<P> = if rng.chance(0.5) {
                vec![[-1.0, -0.6], [1.0, -0.6], [1.0, 0.6], [-1.0, 0.6]]
            } else {
                vec![
                    [-1.0, -1.0],
                    [1.0, -1.0],
                    [1.0, 0.0],
                    [0.0, 0.0],
                    [0.0, 1.0],
                    [-1.0, 1.0],
                ]
            };
            let n = base.len();
            let mut pts = Vec::new();
            for i in 0..n {
                let (prev, at, next) = (base[(i + n - 1) % n], base[i], base[(i + 1) % n]);
                let turn =
                    (at[0] - prev[0]) * (next[1] - at[1]) - (at[1] - prev[1]) * (next[0] - at[0]);
                if turn > 0.0 && rng.chance(0.8) {
                    // cut the convex corner: the two cuts unequal, so the
                    // chamfer meets the edges at 30 to 60 degrees
                    let c = rng.range(0.04, 0.3);
                    let k = rng.range(0.58, 1.73);
                    let towards = |q: P, d: f64| {
                        let (dx, dy) = (q[0] - at[0], q[1] - at[1]);
                        let l = (dx * dx + dy * dy).sqrt();
                        [at[0] + dx / l * d, at[1] + dy / l * d]
                    };
                    pts.push(towards(prev, c));
                    pts.push(towards(next, (c * k).min(0.45)));
                } else {
                    pts.push(at);
                }
            }
            Shape::polygon(pts)
        }
        // a C-channel or a tube: a wall 0.03 to 0.2 thick (sizes are 0.04
        // to 0.15 here: a wall under one element to five elements wide)
        8 => {
            let t = rng.range(0.03, 0.2);
            if rng.chance(0.5) {
                Shape::polygon(vec![
                    [-1.0, -0.6],
                    [1.0, -0.6],
                    [1.0, -0.6 + t],
                    [-1.0 + t, -0.6 + t],
                    [-1.0 + t, 0.6 - t],
                    [1.0, 0.6 - t],
                    [1.0, 0.6],
                    [-1.0, 0.6],
                ])
            } else {
                // a tube: two circles, each three arcs of 120 degrees (a
                // loop has three points at least)
                let ring = |r: f64| -> Vec<P> {
                    (0..3)
                        .map(|k| {
                            let a = k as f64 * 2.0 * PI / 3.0;
                            [r * a.cos(), r * a.sin()]
                        })
                        .collect()
                };
                let third = (PI / 6.0).tan();
                Shape {
                    pts: ring(1.0),
                    bulges: vec![third; 3],
                    inner: 0.0,
                    holes: vec![(ring(1.0 - t), vec![third; 3])],
                    segments: None,
                }
            }
        }
        // a blade in a box: a lens-shaped hole whose trailing edge is 5 to
        // 40 degrees sharp, close to the box's side or not
        9 => {
            let chord = rng.range(0.8, 1.6);
            let te = rng.range(5.0, 40.0).to_radians();
            // two arcs from the leading to the trailing edge, both bulging
            // out: the lens's corners are the sum of their half sweeps
            let f = rng.range(0.3, 0.7);
            let (upper, lower) = ((f * te / 4.0).tan(), ((1.0 - f) * te / 4.0).tan());
            let y = rng.range(-0.4, 0.4);
            let mut s = Shape::polygon(vec![[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]]);
            // the second arc through its middle point: a loop has three
            // points at least (a positive bulge lies right of travel)
            let middle = [0.0, y + chord / 2.0 * lower];
            let half = (lower.atan() / 2.0).tan();
            s.holes.push((
                vec![[-chord / 2.0, y], [chord / 2.0, y], middle],
                vec![upper, half, half],
            ));
            s
        }
        // a four-sided domain with very unequal fixed counts (mapped
        // elements whose opposite sides differ)
        _ => {
            let mut s = Shape::polygon(vec![
                [-1.0, -0.6],
                [1.0, rng.range(-0.8, -0.4)],
                [rng.range(0.7, 1.2), 0.6],
                [rng.range(-1.2, -0.7), rng.range(0.4, 0.8)],
            ]);
            // each side between half and four times as long a segment as
            // a base length of a fourth to a twelfth of the domain
            let base = 2.0 / rng.range(4.0, 12.0);
            let mut counts: Vec<usize> = (0..4)
                .map(|i| {
                    let (p, q) = (s.pts[i], s.pts[(i + 1) % 4]);
                    fixed_count(dist(p, q) / base, rng)
                })
                .collect();
            if counts.iter().sum::<usize>() % 2 == 1 {
                counts[0] += 1;
            }
            s.segments = Some(counts);
            s
        }
    }
}

fn dist(p: P, q: P) -> f64 {
    (p[0] - q[0]).hypot(p[1] - q[1])
}

/// A fixed segment count for an edge `sizes` sizes long, as an engineer
/// sets one: its segments between half and four times the size (the
/// public mapped domains' span a quarter to 1.2 of the size's count), so
/// that two edges' segments differ up to eightfold. Counts drawn whatever
/// the edge's length (1 to 16 on edges of 3 to 50 sizes) put segments 50
/// sizes long beside segments of one, which no drawing asks for; the
/// misses were there (mapped quads whose sides' segments differed under
/// sixfold: 56 of 56 within the bounds; sixfold or more: 18 of 43).
fn fixed_count(sizes: f64, rng: &mut Rng) -> usize {
    let f = rng.range(0.25f64.ln(), 2f64.ln()).exp();
    ((sizes * f).round() as usize).max(1)
}

fn bulges_of(outer: &Value, i: usize) -> f64 {
    outer["bulges"][i].as_f64().unwrap_or(0.0)
}

fn generate(seed: u64) -> Value {
    let mut rng = Rng(seed.wrapping_mul(0x2545_F491_4F6C_DD1D) ^ 0x5DEE_CE66);
    let (family, shape) = outer_loop(&mut rng);
    let (pts, bulges, inner) = (&shape.pts, &shape.bulges, shape.inner);
    // models across six decades, anywhere in the plane
    let scale = 10f64.powf(rng.range(-3.0, 3.0));
    let centre = [
        rng.range(-100.0, 100.0) * scale,
        rng.range(-50.0, 50.0) * scale,
    ];
    let turn = rng.range(0.0, 2.0 * PI);
    let place = |p: P| rot(p, centre, turn, scale);
    let size = scale * rng.range(0.04, 0.15);
    let mut outer = json!({
        "points": pts.iter().map(|&p| place(p)).collect::<Vec<_>>(),
        "bulges": bulges,
    });
    let n = pts.len();
    if let Some(counts) = &shape.segments {
        outer["segments"] = json!(counts);
    } else if rng.chance(0.2) {
        // fixed and unequal counts on the straight edges (an arc in one or
        // two chords cannot keep its area, whatever the mesher); 0 leaves
        // the arcs' counts to the size
        let bulge_of = |i: usize| bulges_of(&outer, i);
        let mut segs: Vec<usize> = (0..n)
            .map(|i| {
                if bulge_of(i) == 0.0 {
                    fixed_count(dist(pts[i], pts[(i + 1) % n]) * scale / size, &mut rng)
                } else {
                    0
                }
            })
            .collect();
        if segs.iter().all(|&k| k > 0) && segs.iter().sum::<usize>() % 2 == 1 {
            segs[0] += 1;
        }
        outer["segments"] = json!(segs);
    }
    let mut holes: Vec<Value> = shape
        .holes
        .iter()
        .map(|(p, b)| json!({ "points": p.iter().map(|&q| place(q)).collect::<Vec<_>>(), "bulges": b }))
        .collect();
    let mut lines = Vec::new();
    if inner > 0.0 {
        let mut taken: Vec<(P, f64)> = Vec::new();
        for _ in 0..rng.int(0, 3) {
            let r = inner * rng.range(0.15, 0.45);
            let c = [rng.range(-inner, inner), rng.range(-inner, inner)];
            // some holes nearly touch another one
            let gap = if rng.chance(0.3) { 0.02 } else { 0.3 } * r;
            if taken
                .iter()
                .any(|&(q, s)| ((q[0] - c[0]).powi(2) + (q[1] - c[1]).powi(2)).sqrt() < r + s + gap)
            {
                continue;
            }
            taken.push((c, r));
            let hole = match rng.int(0, 2) {
                0 => json!({ "circle": { "center": place(c), "radius": r * scale } }),
                1 => {
                    let a = rng.range(0.0, PI);
                    let sq: Vec<P> = (0..4)
                        .map(|k| {
                            let t = a + k as f64 * PI / 2.0;
                            place([c[0] + r * t.cos(), c[1] + r * t.sin()])
                        })
                        .collect();
                    json!({ "points": sq, "bulges": [0.0, rng.range(-0.4, 0.4), 0.0, 0.0] })
                }
                _ => {
                    let tri: Vec<P> = (0..3)
                        .map(|k| {
                            let t = k as f64 * 2.0 * PI / 3.0 + rng.range(-0.3, 0.3);
                            place([c[0] + r * t.cos(), c[1] + r * t.sin()])
                        })
                        .collect();
                    json!({ "points": tri })
                }
            };
            holes.push(hole);
        }
        if rng.chance(0.3) {
            // an inner line clear of the holes, or none
            let y = rng.range(-inner, inner);
            let (a, b) = (
                [-inner * 0.9, y],
                [inner * 0.9, y + rng.range(-0.2, 0.2) * inner],
            );
            let clear = taken.iter().all(|&(q, s)| {
                let t = (((q[0] - a[0]) * (b[0] - a[0]) + (q[1] - a[1]) * (b[1] - a[1]))
                    / ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2)))
                .clamp(0.0, 1.0);
                let f = [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])];
                ((q[0] - f[0]).powi(2) + (q[1] - f[1]).powi(2)).sqrt() > s * 1.3
            });
            if clear {
                lines.push(json!({ "points": [place(a), place(b)] }));
            }
        }
    }
    json!({
        "name": format!("random-{seed}-{family}"),
        "size": size,
        "outer": outer,
        "holes": holes,
        "lines": lines,
    })
}

/// Checks a mesh from its nodes and quads alone; None when valid.
fn mesh_fault(nodes: &[glam::DVec2], quads: &[[u32; 4]], area: f64) -> Option<String> {
    if quads.is_empty() {
        return Some("no quads".into());
    }
    let mut edges: HashMap<(u32, u32), usize> = HashMap::new();
    let mut total = 0.0;
    for q in quads {
        let p = q.map(|i| nodes[i as usize]);
        for i in 0..4 {
            let (a, b, c) = (p[i], p[(i + 1) % 4], p[(i + 2) % 4]);
            if (b - a).perp_dot(c - b) <= 0.0 {
                return Some(format!("quad {q:?} is not convex and counter-clockwise"));
            }
            total += a.perp_dot(b) / 2.0;
            let k = (q[i].min(q[(i + 1) % 4]), q[i].max(q[(i + 1) % 4]));
            *edges.entry(k).or_insert(0) += 1;
        }
    }
    if edges.values().any(|&c| c > 2) {
        return Some("an edge is shared by three quads".into());
    }
    if (total - area).abs() > 1e-6 * area.abs().max(1e-300) {
        return Some(format!("the quads cover {total}, the domain {area}"));
    }
    None
}

/// The area inside the loops' edges (groups below `loops`: the outer loop
/// counter-clockwise, holes clockwise): what the quads must cover.
fn boundary_area(mesh: &freemesh::Mesh, loops: u32) -> f64 {
    mesh.boundary()
        .iter()
        .filter(|e| e.group < loops)
        .map(|e| mesh.nodes()[e.a as usize].perp_dot(mesh.nodes()[e.b as usize]) / 2.0)
        .sum()
}

/// A boundary edge that no quad has as an edge, if any: a loop's edge in
/// its direction (the domain on its left), an inner line's either way.
fn boundary_not_followed(mesh: &freemesh::Mesh, loops: u32) -> Option<(u32, u32)> {
    let mut quad_edges = std::collections::HashSet::new();
    for q in mesh.quads() {
        for i in 0..4 {
            quad_edges.insert((q[i], q[(i + 1) % 4]));
        }
    }
    mesh.boundary()
        .iter()
        .find(|e| {
            !quad_edges.contains(&(e.a, e.b))
                && (e.group < loops || !quad_edges.contains(&(e.b, e.a)))
        })
        .map(|e| (e.a, e.b))
}

#[test]
fn random_valid_domains_give_valid_all_quad_meshes() {
    random_run(None, 40, false);
}

/// Seeds whose rules' mesh lost an inner-line or boundary segment (no
/// element has it: a loop parted off along a line, then a cut zipped):
/// the elements round the segments are meshed again with the segments in
/// place, the rest kept, never the whole domain by the triangle fallback.
/// (Seeds 426 and 458 were here too: since rd_unmerge and the final
/// patterns' choice their rules' mesh has, besides, an edge shared by
/// three elements (426) or a six-segment loop no pattern closes (458);
/// see the next test.)
#[test]
fn a_lost_line_segment_is_mended_round_it_not_by_meshing_the_whole_domain_again() {
    meshed_valid_and_not_whole(&[437, 680, 740, 828, 864, 883]);
}

/// Seeds where, in one pass of the fallbacks, a loop's elements taken
/// back took in a second open loop, and the second, gone from the front,
/// was closed after all from its old nodes: a ring on a loop already
/// ringed (an edge shared by three elements: 222, 893; 176 beside a
/// loop of four no fallback closed) or a loop the triangles could not
/// close (458), each meshed whole by the triangle fallback until the pass
/// skipped the loops no longer on the front.
#[test]
fn a_loop_taken_in_by_another_is_not_closed_again_from_its_old_nodes() {
    meshed_valid_and_not_whole(&[176, 222, 458, 893]);
}

/// Seed 1: a slot with a circular hole a quarter of its size. A merge
/// parted the hole's ring off on its own (a loop round no area), the
/// rules placed elements inside the hole and the whole domain went to
/// the triangle fallback; a merge now never leaves such a loop.
#[test]
fn a_merge_never_parts_off_a_holes_ring_on_its_own() {
    meshed_valid_and_not_whole(&[1]);
}

/// The mesh is valid (conforming, convex, the domain's area) and every
/// boundary and line segment is an element's edge; `what` names it.
fn assert_sound(mesh: &freemesh::Mesh, domain: &Domain, what: &str) {
    let loops = 1 + domain.hole_count() as u32;
    let area = boundary_area(mesh, loops);
    assert_eq!(mesh_fault(mesh.nodes(), mesh.quads(), area), None, "{what}");
    assert_eq!(boundary_not_followed(mesh, loops), None, "{what}");
}

/// Meshes each seed's domain and checks the mesh (valid, every boundary
/// and line segment an element's edge) and that the rules' elements were
/// kept: no seed meshed whole by the triangle fallback.
fn meshed_valid_and_not_whole(seeds: &[u64]) {
    let mut kb = KnowledgeBase::builtin().expect("the built-in KB loads");
    for &seed in seeds {
        let domain = Domain::from_json(&generate(seed)).expect("a valid domain");
        let r = mesh_domain(&domain, &mut kb, &Options::default(), &mut |_| {})
            .unwrap_or_else(|e| panic!("seed {seed}: {e}"));
        assert_sound(&r.mesh, &domain, &format!("seed {seed}"));
        assert_eq!(
            r.stats.triangle_fallbacks,
            0,
            "seed {seed} meshed whole by the fallback: {:?}",
            r.stopped_short.as_ref().map(|s| &s.reason)
        );
    }
}

/// Within the paper's bounds as the judge reads them: corners in
/// [min(45, sharpest input corner) - 0.5, 135.5], aspect, taper and size
/// jump within theirs.
fn within_bounds(q: &freemesh::Quality, sharpest_input: f64) -> bool {
    q.min_angle >= sharpest_input.min(45.0) - 0.5
        && q.max_angle <= 135.5
        && q.max_aspect <= 10.0
        && q.max_taper <= 10.0
        && q.max_size_jump <= 2.0
}

/// The polish slides boundary nodes along their input edges too, with
/// the free nodes round them (`bound(boundary_slide, 0.2)`): a star
/// (seed 5435, a corner of 39 degrees left by the clean-up) and a spike
/// of 28.7 degrees (seed 5261, a corner of 144 next to the tip), both of
/// the fresh draw, come within every bound; with boundary nodes held
/// where the division put them (tests/kb/no-boundary-slide.pl) they do
/// not, nor did they with easing's slides alone, before the polish slid.
#[test]
fn the_polish_slides_boundary_nodes_into_the_bounds() {
    for (seed, sharpest) in [(5435u64, 60.3), (5261, 28.7)] {
        let domain = Domain::from_json(&generate(seed)).unwrap();
        let mesh = |files: &[&str]| {
            let mut kb = KnowledgeBase::builtin().unwrap();
            for f in files {
                kb.consult_file(f).unwrap();
            }
            // the command line's way: blocks, retries and the coarser pass
            mesh_free_then_blocks(&domain, None, &mut kb, &Options::default(), &mut |_| {}).unwrap()
        };
        let held = mesh(&["tests/kb/no-boundary-slide.pl"]);
        let slid = mesh(&[]);
        assert!(
            !within_bounds(&held.quality, sharpest),
            "seed {seed} within the bounds with its boundary nodes held: {:?}",
            held.quality
        );
        assert!(
            within_bounds(&slid.quality, sharpest),
            "seed {seed} slid: {:?}",
            slid.quality
        );
    }
}

/// With the free mesh first (`bound(blocks_first, 0)`), a free mesh with
/// elements outside the bounds is meshed again in blocks, and the better
/// kept, saying so in the trace's first step: a star with a coarse fixed
/// count (seed 777) and a four-sided domain of unequal fixed counts (151)
/// come out within the bounds, where their free meshes are not; with
/// bound(blocks_when_out_of_bounds, 0) the free mesh is kept, the same as
/// mesh_domain's.
#[test]
fn a_free_mesh_out_of_bounds_is_meshed_again_in_blocks_and_the_better_kept() {
    let opts = Options::default().with_trace(true);
    // (unpolished: polishing brings seed 777's free mesh within)
    let mut kb = KnowledgeBase::builtin().expect("the built-in KB loads");
    // (the band off and crowded corners judged folded, as when these
    // seeds were chosen: with the band, 777's free mesh is within the
    // bounds; with crowded corners unfolded, 151's)
    for f in [
        "tests/kb/free-first.pl",
        "tests/kb/no-polish.pl",
        "tests/kb/band-off.pl",
        "tests/kb/no-unfold-crowded-corners.pl",
    ] {
        kb.consult_file(f).expect("the file loads");
    }
    let mut off = KnowledgeBase::builtin().expect("the built-in KB loads");
    for f in [
        "tests/kb/no-blocks-when-out-of-bounds.pl",
        "tests/kb/no-polish.pl",
        "tests/kb/band-off.pl",
        "tests/kb/no-unfold-crowded-corners.pl",
    ] {
        off.consult_file(f).expect("the file loads");
    }
    for seed in [777, 151] {
        let domain = Domain::from_json(&generate(seed)).expect("a valid domain");
        // every corner of these domains is at least 45 degrees
        let free = mesh_domain(&domain, &mut kb, &opts, &mut |_| {}).expect("meshed");
        assert!(
            !within_bounds(&free.quality, 45.0),
            "seed {seed}: {:?}",
            free.quality
        );
        let r = mesh_free_then_blocks(&domain, None, &mut kb, &opts, &mut |_| {}).expect("meshed");
        assert!(
            within_bounds(&r.quality, 45.0),
            "seed {seed}: {:?}",
            r.quality
        );
        let first = &r.trace[0];
        assert_eq!(first.feature, "block", "seed {seed}");
        assert!(
            first.action.starts_with("layout(") || first.action.starts_with("four_sided("),
            "seed {seed}: {}",
            first.action
        );
        // the free mesh's words first (after the grading's, where a
        // coarse fixed count grades the run)
        let free_words = first.redesign.iter().position(|t| t.starts_with("free: "));
        assert!(
            free_words
                .is_some_and(|i| i == usize::from(first.redesign[0].starts_with("no max_size"))),
            "seed {seed}: {:?}",
            first.redesign
        );
        assert_sound(&r.mesh, &domain, &format!("seed {seed}"));
        let kept =
            mesh_free_then_blocks(&domain, None, &mut off, &opts, &mut |_| {}).expect("meshed");
        assert_eq!(kept.mesh.quads(), free.mesh.quads(), "seed {seed}");
        // the same steps, but for a first one telling of the grading
        let told = usize::from(kept.trace[0].feature == "block");
        assert_eq!(kept.trace.len() - told, free.trace.len(), "seed {seed}");
    }
}

/// Where neither the free mesh nor the blocks are within the bounds, a
/// domain with fixed segment counts is meshed again by the bounds of
/// `retry_bound/3` (strategy.pl: at the size, the refining transition
/// on): a star whose edges have counts coarser than the size (seed
/// 1000; seed 45, a chamfer, until smoothing kept shapes within their
/// bounds and its blocks came within them), graded for them and short of
/// the bounds so, comes within the bounds so, and the trace's first step
/// says it.
#[test]
fn a_domain_with_coarse_fixed_counts_is_retried_with_refining_on() {
    let opts = Options::default().with_trace(true);
    let domain = Domain::from_json(&generate(1000)).expect("a valid domain");
    // with the band on (built in) the first run's blocks are within the
    // bounds, no retry needed; with it off, as when the seed was chosen,
    // the retries' mechanism is what brings it within them
    let mut on = KnowledgeBase::builtin().expect("the built-in KB loads");
    let first_run =
        mesh_free_then_blocks(&domain, None, &mut on, &opts, &mut |_| {}).expect("meshed");
    assert!(
        within_bounds(&first_run.quality, 45.0),
        "{:?}",
        first_run.quality
    );
    assert!(!first_run.trace[0].action.starts_with("retry("));
    let mut kb = KnowledgeBase::builtin().expect("the built-in KB loads");
    kb.consult_file("tests/kb/band-off.pl").expect("consulted");
    let free = mesh_domain(&domain, &mut kb, &opts, &mut |_| {}).expect("meshed");
    assert!(!within_bounds(&free.quality, 45.0), "{:?}", free.quality);
    let r = mesh_free_then_blocks(&domain, None, &mut kb, &opts, &mut |_| {}).expect("meshed");
    assert!(within_bounds(&r.quality, 45.0), "{:?}", r.quality);
    let first = &r.trace[0];
    assert!(
        first.action.starts_with("retry(refine_fixed_counts"),
        "{}: {:?}",
        first.action,
        first.redesign
    );
    assert!(
        first.redesign.iter().any(|t| t.starts_with(
            "retry refine_fixed_counts (bound(uniform_size_band, 1.5), bound(refine_ratio, 0.45), bound(coarse_boundary_grading, 0))"
        )),
        "{:?}",
        first.redesign
    );
    assert_sound(&r.mesh, &domain, "seed 1000");
}

/// A domain without fixed counts is retried too, by the variants that do
/// not need them (`retry_needs/2`), in the KB's order until one is within
/// the bounds: a slot (seed 533) whose free mesh and blocks leave
/// elements outside does not come within them when the fronts may leave
/// no corner under 20 deg, but does when they merge only within 0.4 of
/// the size. refine_fixed_counts, which needs fixed counts, is not tried.
/// (Seed 912 was here too, kept by no_sharp_front_corners, until easing
/// that keeps in-window elements in put its blocks within the bounds.)
#[test]
fn a_domain_without_fixed_counts_is_retried_by_the_variants_it_may_take() {
    for (seed, kept, before) in [(533, "fronts_merge_nearer", &["no_sharp_front_corners"][..])] {
        let opts = Options::default().with_trace(true);
        let mut kb = KnowledgeBase::builtin().expect("the built-in KB loads");
        // the retries alone: no coarser mesh tried after them
        kb.consult_file("tests/kb/no-coarser.pl")
            .expect("consulted");
        // (the band off and crowded corners judged folded, as when the
        // seed was chosen: with either, the first run is within the
        // bounds)
        kb.consult_file("tests/kb/band-off.pl").expect("consulted");
        kb.consult_file("tests/kb/no-unfold-crowded-corners.pl")
            .expect("consulted");
        let domain = Domain::from_json(&generate(seed)).expect("a valid domain");
        let free = mesh_domain(&domain, &mut kb, &opts, &mut |_| {}).expect("meshed");
        // out of the bounds as the program counts them: a corner past
        // [45, 135] by any amount (the judge lets half a degree pass)
        assert!(
            free.quality.outside_45_135 > 0 || !within_bounds(&free.quality, 45.0),
            "{seed}: {:?}",
            free.quality
        );
        let t0 = std::time::Instant::now();
        let r = mesh_free_then_blocks(&domain, None, &mut kb, &opts, &mut |_| {}).expect("meshed");
        let wall = t0.elapsed().as_secs_f64();
        assert!(within_bounds(&r.quality, 45.0), "{seed}: {:?}", r.quality);
        // the stages' times (the retries apart, the kept mesh's own
        // counted once) add up to no more than the call took
        let ph = &r.phases;
        let stages = [
            ph.prepare,
            ph.recursion,
            ph.smoothing,
            ph.check,
            ph.blocks,
            ph.retries,
        ];
        assert!(stages.iter().all(|&t| t >= 0.0), "{seed}: {ph:?}");
        assert!(ph.blocks > 0.0 && ph.retries > 0.0, "{seed}: {ph:?}");
        assert!(
            stages.iter().sum::<f64>() <= wall + 1e-3,
            "{seed}: {ph:?} in {wall} s"
        );
        let first = &r.trace[0];
        assert_eq!(
            first.action,
            format!("retry({kept})"),
            "{seed}: {:?}",
            first.redesign
        );
        let retried: Vec<&str> = first
            .redesign
            .iter()
            .filter_map(|t| t.strip_prefix("retry "))
            .filter_map(|t| t.split(' ').next())
            .collect();
        let mut expected = before.to_vec();
        expected.push(kept);
        // blocks under a variant are listed under its name too
        let mut seen = retried.clone();
        seen.dedup();
        assert_eq!(seen, expected, "{seed}: {:?}", first.redesign);
        assert_sound(&r.mesh, &domain, &format!("seed {seed}"));
    }
}

/// Seed's domain meshed free, then in blocks and retried where it falls
/// short, with its trace.
fn free_then_blocks(seed: u64) -> freemesh::MeshResult {
    free_then_blocks_with(seed, &[])
}

/// `free_then_blocks` with these KB files consulted after the built-in.
fn free_then_blocks_with(seed: u64, files: &[&str]) -> freemesh::MeshResult {
    let opts = Options::default().with_trace(true);
    let mut kb = KnowledgeBase::builtin().expect("the built-in KB loads");
    for f in files {
        kb.consult_file(f).expect("the file loads");
    }
    let domain = Domain::from_json(&generate(seed)).expect("a valid domain");
    mesh_free_then_blocks(&domain, None, &mut kb, &opts, &mut |_| {}).expect("meshed")
}

/// No retry where an input corner is too sharp for any element at it to
/// meet the taper bound (`bound(retry_sharpest_corner, 8.1)`): a spike of
/// 5 deg (seed 1048) stays outside the bounds, its trace saying why no
/// retry was made, and none was (unpolished: polished, its blocks are
/// past the bounds at the tip alone, and kept with no retry either).
#[test]
fn a_domain_with_a_spike_too_sharp_for_the_bounds_is_not_retried() {
    let polished = free_then_blocks(1048);
    assert!(
        !within_bounds(&polished.quality, 4.0),
        "{:?}",
        polished.quality
    );
    let said = &polished.trace[0].redesign;
    assert!(!said.iter().any(|t| t.starts_with("retry ")), "{said:?}");
    let r = free_then_blocks_with(1048, &["tests/kb/no-polish.pl"]);
    assert!(!within_bounds(&r.quality, 4.0), "{:?}", r.quality);
    let said = &r.trace[0].redesign;
    assert!(
        said.iter()
            .any(|t| t.starts_with("no retry: an input corner of 5.0 deg")),
        "{said:?}"
    );
    assert!(!said.iter().any(|t| t.starts_with("retry ")), "{said:?}");
}

/// An input corner split between elements excuses none of them: in a
/// four-sided domain of counts 3, 1, 2 and 8 (tests/bounds/
/// split-corner-mapped.json, the generator's seed 419 before its counts
/// followed the edges' lengths) the blocks split an 83-degree corner into
/// two of 41.5, and the count of elements outside the bounds that picks
/// the mesh has them (it once took them for a sharp input corner taken
/// whole, and kept the mesh as within). Crowded corners are judged as
/// folded here (`tests/kb/no-unfold-crowded-corners.pl`): unfolded, the
/// clean-up gives that corner one element and the layout's mesh is
/// within the bounds (below). The folded run is without the clean-up's
/// split into four too (`tests/kb/no-split-into-four.pl`): with it, that
/// layout's mesh is within the bounds, folded as it is.
#[test]
fn a_split_input_corner_under_the_window_counts_as_outside() {
    let text = std::fs::read_to_string("tests/bounds/split-corner-mapped.json").expect("the file");
    let domain = Domain::from_json(&serde_json::from_str(&text).expect("JSON")).expect("valid");
    let opts = Options::default().with_trace(true);
    let mut unfolded = KnowledgeBase::builtin().expect("the built-in KB loads");
    let u =
        mesh_free_then_blocks(&domain, None, &mut unfolded, &opts, &mut |_| {}).expect("meshed");
    assert!(
        u.trace[0]
            .redesign
            .iter()
            .any(|t| t.starts_with("blocks of 2 element sizes: 0 elements out of bounds")),
        "{:?}",
        u.trace[0].redesign
    );
    assert!(within_bounds(&u.quality, 45.0), "{:?}", u.quality);
    let mut kb = KnowledgeBase::builtin().expect("the built-in KB loads");
    for file in [
        "tests/kb/no-unfold-crowded-corners.pl",
        "tests/kb/no-split-into-four.pl",
    ] {
        kb.consult_file(file).expect("consulted");
    }
    let r = mesh_free_then_blocks(&domain, None, &mut kb, &opts, &mut |_| {}).expect("meshed");
    let said = &r.trace[0].redesign;
    let layout = said
        .iter()
        .find(|t| t.starts_with("blocks of 2 element sizes: "))
        .expect("the layout of 2 sizes tried");
    // the two halves of the corner among them (5 since smoothing keeps
    // shapes within their bounds, 2 before)
    let out: usize = layout
        .trim_start_matches("blocks of 2 element sizes: ")
        .split(' ')
        .next()
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("{said:?}"));
    assert!(
        out >= 2 && layout.contains(" elements out of bounds"),
        "{said:?}"
    );
    if within_bounds(&r.quality, 45.0) {
        return;
    }
    // outside, so the retries were made
    assert!(said.iter().any(|t| t.starts_with("retry ")), "{said:?}");
}

/// A four-sided domain of counts 5, 1, 4 and 2 (tests/bounds/
/// sliding-mapped.json, the generator's seed 88): its seven elements have
/// a single interior node between them, and a corner of 44.4 degrees
/// stays whatever it does. Easing slides boundary nodes along their
/// straight edges (`bound(boundary_slide, 0.2)`) and brings every corner
/// into the window; the nodes stay on the edges and the four input
/// vertices where they are. With the bound at 0 none moves, and the mesh
/// falls short.
#[test]
fn boundary_nodes_slide_along_their_edges_where_elements_have_no_other_room() {
    let text = std::fs::read_to_string("tests/bounds/sliding-mapped.json").expect("the file");
    let json: serde_json::Value = serde_json::from_str(&text).expect("JSON");
    let domain = Domain::from_json(&json).expect("valid");
    let opts = Options::default();
    let mut kb = KnowledgeBase::builtin().expect("the built-in KB loads");
    let slid = mesh_free_then_blocks(&domain, None, &mut kb, &opts, &mut |_| {}).expect("meshed");
    assert!(within_bounds(&slid.quality, 45.0), "{:?}", slid.quality);
    let corners: Vec<[f64; 2]> =
        serde_json::from_value(json["outer"]["points"].clone()).expect("the points");
    for c in &corners {
        assert!(
            slid.mesh.nodes().iter().any(|n| n.x == c[0] && n.y == c[1]),
            "input vertex {c:?} moved"
        );
    }
    // every boundary node on a side: its distance to the side's line
    for e in slid.mesh.boundary() {
        let p = slid.mesh.nodes()[e.a as usize];
        let on_a_side = (0..corners.len()).any(|i| {
            let (a, b) = (corners[i], corners[(i + 1) % corners.len()]);
            let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
            let cross = (p.x - a[0]) * dy - (p.y - a[1]) * dx;
            cross.abs() <= 1e-9 * (dx * dx + dy * dy)
        });
        assert!(on_a_side, "boundary node {p} off the sides");
    }
    let mut fixed = KnowledgeBase::builtin().expect("the built-in KB loads");
    fixed
        .consult_file("tests/kb/no-boundary-slide.pl")
        .expect("consulted");
    let unslid =
        mesh_free_then_blocks(&domain, None, &mut fixed, &opts, &mut |_| {}).expect("meshed");
    assert!(
        !within_bounds(&unslid.quality, 45.0),
        "{:?}",
        unslid.quality
    );
}

/// A uniform mesh with many more elements than the domain's area over
/// the size squared asks for (tests/bounds/coarser-fine-features.json,
/// the generator's seed 214: 122 elements where that is 57, two of them
/// out of bounds, when every edge reads the size) is made coarser: the
/// transitions see its small features' fine edges from the first run
/// (`bound(uniform_size_band, 1.5)`), and where that run still has over
/// 1.2 times the area's elements the coarser pass tries the
/// `coarser_with` variants, `coarser_fine_features` left out as its
/// bounds are those in place; the one within the bounds with fewest
/// elements kept, and the trace's first step says all. With
/// `bound(uniform_size_band, 0)` and `bound(coarser_when_over, 0)`
/// (tests/kb/no-fine-features.pl) the first mesh stays.
#[test]
fn a_mesh_with_many_more_elements_than_its_area_asks_is_meshed_coarser() {
    let text =
        std::fs::read_to_string("tests/bounds/coarser-fine-features.json").expect("the file");
    let domain = Domain::from_json(&serde_json::from_str(&text).expect("JSON")).expect("valid");
    let opts = Options::default().with_trace(true);
    let mut kb = KnowledgeBase::builtin().expect("the built-in KB loads");
    let coarser =
        mesh_free_then_blocks(&domain, None, &mut kb, &opts, &mut |_| {}).expect("meshed");
    let mut off = KnowledgeBase::builtin().expect("the built-in KB loads");
    off.consult_file("tests/kb/no-fine-features.pl")
        .expect("consulted");
    let first = mesh_free_then_blocks(&domain, None, &mut off, &opts, &mut |_| {}).expect("meshed");
    // its sharpest input corner is 30.9 degrees
    assert!(
        within_bounds(&coarser.quality, 30.9),
        "{:?}",
        coarser.quality
    );
    let (n, m) = (coarser.mesh.quads().len(), first.mesh.quads().len());
    assert!(n * 10 < m * 9, "{n} coarser against {m}");
    let told = &coarser.trace[0];
    assert!(
        told.action.starts_with("coarser(coarser_"),
        "{}",
        told.action
    );
    assert!(
        told.redesign[0].contains(
            " elements, over bound(coarser_when_over, 1.2) times the domain's area over the size squared"
        ),
        "{:?}",
        told.redesign
    );
    assert!(
        told.redesign[1].starts_with("the first run: "),
        "{:?}",
        told.redesign
    );
    assert_eq!(
        told.redesign[2],
        "coarser_fine_features (bound(uniform_size_band, 1.5)): not run, its bounds are those in place"
    );
    assert!(!first.trace[0]
        .redesign
        .iter()
        .any(|t| t.contains("coarser_when_over")));
    assert_sound(&coarser.mesh, &domain, "seed 214");
}

/// An inner line whose end comes a fifth of the size from a small hole
/// (seed 5313, a slot of the fresh draw): in one segment, the fronts
/// bridged the gap with a sliver (corners of 20.7 and 159.2 degrees, 186
/// quads where the area asks for 39); in segments of the gap
/// (`bound(line_gap, 1)`, input/line_gaps.rs) the mesh is within every
/// bound. With the bound 0 (tests/kb/no-line-gap.pl) the line is one
/// segment again, and the mesh is not.
#[test]
fn an_inner_line_near_a_small_hole_is_divided_in_segments_of_the_gap() {
    let near = free_then_blocks(5313);
    assert_eq!(near.stats.near_line_edges, 1);
    assert!(within_bounds(&near.quality, 45.0), "{:?}", near.quality);
    let off = free_then_blocks_with(5313, &["tests/kb/no-line-gap.pl"]);
    assert_eq!(off.stats.near_line_edges, 0);
    assert!(!within_bounds(&off.quality, 45.0), "{:?}", off.quality);
    let domain = Domain::from_json(&generate(5313)).expect("a valid domain");
    assert_sound(&near.mesh, &domain, "seed 5313");
}

/// A slot (random seed 437) with a small hole and an inner line near its
/// middle, where the rules leave a loop open: its triangles paired into
/// quads leave the rows along the slot whole, where splitting every
/// triangle in three halved every loop edge and split the rows along
/// the slot's whole length (533 quads where the area asks for 153).
#[test]
fn a_loop_left_open_in_a_slot_is_closed_without_splitting_the_slot() {
    let text = std::fs::read_to_string("tests/stuck/slot-with-a-hole.json").expect("the file");
    let domain = Domain::from_json(&serde_json::from_str(&text).expect("JSON")).expect("valid");
    let opts = Options::default().with_trace(true);
    // (the band off in both, as when the seed was chosen: with it, the
    // split leaves fewer elements to compare; and the line in one
    // segment: in segments of its gap to the hole, bound(line_gap, 1),
    // the rules leave no loop open)
    let mut kb = KnowledgeBase::builtin().expect("the built-in KB loads");
    kb.consult_file("tests/kb/band-off.pl").expect("consulted");
    kb.consult_file("tests/kb/no-line-gap.pl")
        .expect("consulted");
    let paired = mesh_free_then_blocks(&domain, None, &mut kb, &opts, &mut |_| {}).expect("meshed");
    let mut off = KnowledgeBase::builtin().expect("the built-in KB loads");
    off.consult_file("tests/kb/band-off.pl").expect("consulted");
    off.consult_file("tests/kb/no-line-gap.pl")
        .expect("consulted");
    off.consult_file("tests/kb/no-triangle-pairs.pl")
        .expect("consulted");
    let split = mesh_free_then_blocks(&domain, None, &mut off, &opts, &mut |_| {}).expect("meshed");
    let closing = |r: &freemesh::MeshResult| {
        r.trace
            .iter()
            .rev()
            .find(|t| t.feature == "stuck")
            .map(|t| t.action.clone())
            .unwrap_or_default()
    };
    assert!(
        closing(&paired).starts_with("loop_triangle_pairs("),
        "{}",
        closing(&paired)
    );
    assert!(
        closing(&split).starts_with("loop_triangle_split("),
        "{}",
        closing(&split)
    );
    let (n, m) = (paired.mesh.quads().len(), split.mesh.quads().len());
    assert!(n * 4 < m * 3, "{n} paired against {m} split");
    assert!(
        paired.stats.chord_split_elements * 2 < split.stats.chord_split_elements,
        "{} split along their rows against {}",
        paired.stats.chord_split_elements,
        split.stats.chord_split_elements
    );
    assert!(within_bounds(&paired.quality, 45.0), "{:?}", paired.quality);
    assert_sound(&paired.mesh, &domain, "seed 437");
}

/// What is meshed once is not meshed again: a retry whose free mesh is
/// the first run's (its bounds changed nothing there) is not tried in
/// blocks, and the coarser run leaves the retries to the first run,
/// which made them (a retry's engine has the user's files and its own
/// bounds alone, the same in both runs). A 9-degree spike: its free
/// mesh falls short, is retried, and has more elements than its area asks
/// (a 9.5-degree one, [6, 1] at the top, was, until the polish slid
/// boundary nodes: it now comes within the bounds at the first run).
#[test]
fn what_is_meshed_once_is_not_meshed_again() {
    let spike = r#"{"name": "spike", "size": 1, "outer": {"points": [[0,0],[6,0],[6,0.95]]}}"#;
    let domain = Domain::from_json_str(spike).expect("valid");
    let opts = Options::default().with_trace(true);
    let mut kb = KnowledgeBase::builtin().expect("the built-in KB loads");
    let r = mesh_free_then_blocks(&domain, None, &mut kb, &opts, &mut |_| {}).expect("meshed");
    let told = &r.trace[0].redesign;
    let retries: Vec<&String> = told.iter().filter(|t| t.starts_with("retry ")).collect();
    assert!(!retries.is_empty(), "{told:?}");
    // each retry's free mesh, then either its blocks or why none
    let again = retries
        .iter()
        .filter(|t| t.ends_with("the first run's free mesh again, not tried in blocks"))
        .count();
    assert!(again > 0, "{told:?}");
    for t in &retries {
        let variant = t.split(" (").next().expect("named");
        let lines: Vec<&&String> = retries.iter().filter(|u| u.starts_with(variant)).collect();
        let skipped = lines.iter().any(|u| u.ends_with("not tried in blocks"));
        let blocks = lines.iter().any(|u| u.contains("element sizes"));
        assert!(!(skipped && blocks), "{lines:?}");
    }
    // (coarser_fine_features is not run, its bounds being bound/2's: the
    // next variant is the first the pass makes)
    assert!(
        told.iter().any(|t| t.starts_with("coarser coarser_")
            && t.ends_with("no retries of its own (a retry's engine has the user's files and its own bounds alone: they are the first run's, mesh for mesh)")),
        "{told:?}"
    );
    assert_sound(&r.mesh, &domain, "spike");
}

/// The same domains graded: an interior limit of six times the boundary
/// size (the graded benchmark's), so the size field, the coarsening
/// rules (t3) and the taller rows all run (FREEMESH_RANDOM_MAX_SIZE=K
/// sets another multiple in the plain run instead).
#[test]
fn random_domains_graded_to_six_times_the_size_give_valid_meshes() {
    random_run(Some(6.0), 20, false);
}

/// The same domains in structured blocks (`--blocks`): the layout, the
/// interval assignment, the mapping elements and the free blocks all run
/// on shapes never tuned for.
#[test]
fn random_domains_in_blocks_give_valid_meshes() {
    random_run(None, 20, true);
}

/// Meshes the run's seeds (`ratio`: an interior limit of that many times
/// each domain's size; `blocks`: in structured blocks) and checks every
/// mesh.
fn random_run(ratio: Option<f64>, default_count: u64, blocks: bool) {
    let ratio = ratio.or_else(|| {
        std::env::var("FREEMESH_RANDOM_MAX_SIZE")
            .ok()
            .and_then(|s| s.parse().ok())
    });
    let count: u64 = std::env::var("FREEMESH_RANDOM_DOMAINS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(default_count);
    let from: u64 = std::env::var("FREEMESH_RANDOM_FROM")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(0);
    let seeds: Vec<u64> = match std::env::var("FREEMESH_RANDOM_SEED") {
        Ok(s) => vec![s.parse().expect("FREEMESH_RANDOM_SEED is a number")],
        Err(_) => (from..from + count).collect(),
    };
    let mut kb = KnowledgeBase::builtin().expect("the built-in KB loads");
    let (mut meshed, mut refused, mut fallbacks, mut last_resorts) = (0, 0, 0, 0);
    let (mut loops_closed, mut in_blocks) = (0, 0);
    let mut refusals: std::collections::BTreeMap<String, usize> = Default::default();
    let mut failures = Vec::new();
    for &seed in &seeds {
        let v = generate(seed);
        if seeds.len() == 1 {
            let path = std::env::temp_dir().join(format!("random-{seed}.json"));
            std::fs::write(&path, serde_json::to_string_pretty(&v).unwrap()).unwrap();
            eprintln!("domain written to {}", path.display());
        }
        let domain = match Domain::from_json(&v) {
            Ok(d) => {
                // for the outside judge: ../shared/bench/judge --set DIR
                if let Ok(dir) = std::env::var("FREEMESH_RANDOM_DUMP") {
                    let path = std::path::Path::new(&dir).join(format!("random-{seed}.json"));
                    std::fs::create_dir_all(&dir).expect("the dump folder can be made");
                    std::fs::write(&path, serde_json::to_string_pretty(&v).unwrap())
                        .expect("the domain is written");
                    if std::env::var_os("FREEMESH_RANDOM_DUMP_ONLY").is_some() {
                        continue;
                    }
                }
                d
            }
            Err(e) => {
                refused += 1;
                // the message without its numbers: what kind of refusal
                let kind: String = e
                    .to_string()
                    .chars()
                    .filter(|c| !c.is_ascii_digit() && *c != '.' && *c != '-')
                    .collect();
                *refusals.entry(kind).or_insert(0) += 1;
                continue;
            }
        };
        let t0 = std::time::Instant::now();
        let opts = Options::default().with_max_size(ratio.map(|k| k * domain.size()));
        let result = if blocks {
            freemesh::mesh_in_blocks(&domain, &mut kb, &opts, &mut |_| {})
        } else {
            mesh_domain(&domain, &mut kb, &opts, &mut |_| {})
        };
        if t0.elapsed().as_secs_f64() > 5.0 {
            eprintln!("seed {seed} took {:.1} s", t0.elapsed().as_secs_f64());
        }
        match result {
            Ok(r) => {
                let loops = 1 + domain.hole_count() as u32;
                let area = boundary_area(&r.mesh, loops);
                let fault = mesh_fault(r.mesh.nodes(), r.mesh.quads(), area).or_else(|| {
                    boundary_not_followed(&r.mesh, loops)
                        .map(|e| format!("boundary edge {e:?} is no element's edge"))
                });
                match fault {
                    None => meshed += 1,
                    Some(f) => failures.push(format!("seed {seed}: {f}")),
                }
                fallbacks += r.stats.fallback_splits;
                last_resorts += r.stats.triangle_fallbacks;
                if r.stats.triangle_fallbacks > 0 {
                    // which domains, and why: each kind is the next rule to write
                    let why = r.stopped_short.as_ref().map_or("", |s| s.reason.as_str());
                    eprintln!("seed {seed} meshed whole by the triangle fallback: {why}");
                }
                loops_closed += (r.stats.open_loops_closed > 0) as usize;
                in_blocks += (r.stats.blocks > 0) as usize;
            }
            Err(e) => failures.push(format!("seed {seed}: {e}")),
        }
    }
    eprintln!(
        "{} seeds: {meshed} meshed and valid, {refused} refused by the validator, {} failed; \
         {fallbacks} fallback splits, {loops_closed} with open loops closed by triangles, \
         {last_resorts} meshed whole by the triangle fallback{}",
        seeds.len(),
        failures.len(),
        if blocks {
            format!("; {in_blocks} in blocks")
        } else {
            String::new()
        }
    );
    for (kind, n) in &refusals {
        eprintln!("  refused {n}: {kind}");
    }
    if std::env::var_os("FREEMESH_RANDOM_DUMP_ONLY").is_some() {
        return; // the domains written, none meshed
    }
    assert!(
        failures.is_empty(),
        "{} of {} valid domains failed (FREEMESH_RANDOM_SEED=N reruns one):\n{}",
        failures.len(),
        seeds.len() - refused,
        failures.join("\n")
    );
    // where the rules stop, the fallback closes the loops they left open;
    // the whole domain goes to the last resort only where that fails
    assert!(
        last_resorts * 20 <= meshed,
        "{last_resorts} of {meshed} meshed whole by the triangle fallback"
    );
    assert!(
        meshed * 2 >= seeds.len(),
        "the generator should make mostly valid domains: {refused} of {} refused",
        seeds.len()
    );
}

/// The corners (deg, inside the loop) at the vertices of a loop of
/// points and bulges, as the curves' tangents make them, for the
/// vertices where an arc meets: (vertex, corner).
fn arc_corners(points: &[P], bulges: &[f64]) -> Vec<(P, f64)> {
    let n = points.len();
    let sub = |a: P, b: P| [b[0] - a[0], b[1] - a[1]];
    let turn = |d: P, t: f64| {
        [
            d[0] * t.cos() - d[1] * t.sin(),
            d[0] * t.sin() + d[1] * t.cos(),
        ]
    };
    // a positive bulge is an arc counter-clockwise from a to b: its
    // tangent leaves a half its sweep clockwise of the chord
    let sweep = |i: usize| 4.0 * bulges.get(i).copied().unwrap_or(0.0).atan();
    let twice_area: f64 = (0..n)
        .map(|i| {
            let (a, b) = (points[i], points[(i + 1) % n]);
            a[0] * b[1] - a[1] * b[0]
        })
        .sum();
    (0..n)
        .filter(|&i| sweep(i) != 0.0 || sweep((i + n - 1) % n) != 0.0)
        .map(|i| {
            let (prev, v, next) = (points[(i + n - 1) % n], points[i], points[(i + 1) % n]);
            let t_in = turn(sub(prev, v), sweep((i + n - 1) % n) / 2.0);
            let t_out = turn(sub(v, next), -sweep(i) / 2.0);
            // from the way out round to the way back, counter-clockwise
            let back = [-t_in[0], -t_in[1]];
            let cross = t_out[0] * back[1] - t_out[1] * back[0];
            let dot = t_out[0] * back[0] + t_out[1] * back[1];
            let ccw = cross.atan2(dot).to_degrees().rem_euclid(360.0);
            (v, if twice_area > 0.0 { ccw } else { 360.0 - ccw })
        })
        .collect()
}

/// Where an arc bulging out of a random domain meets a tip (15 to 50
/// deg between the curves' tangents), the arc's first chord takes half
/// its segment's sweep off the tip; shorter first segments
/// (`bound(arc_corner_chord, _)`, src/input/arc_corners.rs) bring the
/// element at the tip nearer the tip's corner. Checked on the first four
/// tips of the outer loops of seeds from 0 that equal segments
/// (tests/kb/no-arc-corner-chord.pl) take more than the judge's half
/// degree off, each meshed by the rules both ways.
#[test]
fn an_element_at_a_tip_beside_an_arc_keeps_the_tips_corner() {
    let corner_at = |r: &freemesh::MeshResult, v: glam::DVec2| -> Option<f64> {
        let nodes = r.mesh.nodes();
        let tol = 1e-9 * v.length().max(1.0);
        let tip = nodes.iter().position(|&p| (p - v).length() <= tol)? as u32;
        let at: Vec<&[u32; 4]> = r.mesh.quads().iter().filter(|q| q.contains(&tip)).collect();
        let [q] = at[..] else { return None };
        let k = q.iter().position(|&n| n == tip)?;
        let (a, b) = (
            nodes[q[(k + 1) % 4] as usize] - v,
            nodes[q[(k + 3) % 4] as usize] - v,
        );
        Some(a.angle_to(b).abs().to_degrees())
    };
    let mesh = |domain: &Domain, files: &[&str]| {
        let mut kb = KnowledgeBase::builtin().unwrap();
        for f in files {
            kb.consult_file(f).unwrap();
        }
        mesh_domain(domain, &mut kb, &Options::default(), &mut |_| {}).unwrap()
    };
    // (seed, tip, its element with equal segments, as built in)
    let mut spoiled: Vec<(u64, f64, f64, Option<f64>)> = Vec::new();
    for seed in 0..3000u64 {
        let value = generate(seed);
        let outer = &value["outer"];
        let points: Vec<P> = serde_json::from_value(outer["points"].clone()).unwrap();
        let bulges: Vec<f64> = outer
            .get("bulges")
            .map_or(vec![], |b| serde_json::from_value(b.clone()).unwrap());
        let tips: Vec<(P, f64)> = arc_corners(&points, &bulges)
            .into_iter()
            .filter(|&(_, c)| (15.0..50.0).contains(&c))
            .collect();
        let Ok(domain) = Domain::from_json(&value) else {
            continue;
        };
        if tips.is_empty() {
            continue;
        }
        let equal = mesh(&domain, &["tests/kb/no-arc-corner-chord.pl"]);
        let built_in = mesh(&domain, &[]);
        for (v, corner) in tips {
            let v = glam::DVec2::new(v[0], v[1]);
            match corner_at(&equal, v) {
                Some(a) if a < corner.min(45.0) - 0.5 => {
                    spoiled.push((seed, corner, a, corner_at(&built_in, v)))
                }
                _ => {}
            }
        }
        if spoiled.len() >= 4 {
            break;
        }
    }
    assert_eq!(
        spoiled.len(),
        4,
        "four tips spoilt by equal segments among the seeds"
    );
    // none sharper, most nearer the tip; within the half degree only
    // where the arc has segments enough to grow from a first one short
    // enough (`SHORTEST_SHARE`, 0.3 of the others; two segments cannot):
    // here 565's tip of 44.49 deg is 43.91, 1934's arc has two
    let nearer = spoiled
        .iter()
        .filter(|&&(_, _, e, a)| a.is_some_and(|a| a > e + 0.3))
        .count();
    assert!(
        spoiled
            .iter()
            .all(|&(_, _, e, a)| a.is_some_and(|a| a >= e))
            && nearer >= 3,
        "(seed, tip, equal segments, built in): {spoiled:?}"
    );
}

/// Smoothing moves one node at a time: a size jump or a corner that two
/// inner nodes hold between them stays just past its bound. Polishing
/// (`bound(polish_rings, 2)`, src/smoothing/polish.rs) moves the free
/// nodes round such an element together: two small four-sided domains
/// of the fresh draw with unequal fixed counts (seeds 5100 and 5483, a
/// size jump of 2.007 and 2.004 left by smoothing) come within every
/// bound with it and not without it (tests/kb/no-polish.pl).
#[test]
fn a_size_jump_two_inner_nodes_hold_is_polished_within_the_bound() {
    for seed in [5100u64, 5483] {
        let domain = Domain::from_json(&generate(seed)).unwrap();
        let mesh = |files: &[&str]| {
            let mut kb = KnowledgeBase::builtin().unwrap();
            for f in files {
                kb.consult_file(f).unwrap();
            }
            mesh_domain(&domain, &mut kb, &Options::default(), &mut |_| {}).unwrap()
        };
        let unpolished = mesh(&["tests/kb/no-polish.pl"]);
        let polished = mesh(&[]);
        assert!(
            !within_bounds(&unpolished.quality, 45.0),
            "seed {seed} within the bounds unpolished: {:?}",
            unpolished.quality
        );
        assert!(
            within_bounds(&polished.quality, 45.0),
            "seed {seed} polished: {:?}",
            polished.quality
        );
    }
}
