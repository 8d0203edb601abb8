//! Polishing what is left just past the bounds. Smoothing, the clean-up's
//! local smoothing and the easing each move one node at a time, so a
//! corner or a size jump that two nodes hold between them stays where
//! it is. Here the free nodes within `bound(polish_rings, R)` rings of
//! each element still past the paper's bounds move together: a descent
//! on a soft maximum of every measure of the elements they touch
//! (corners against the window, size jumps against neighbours, aspect
//! ratio and taper, each as a share of its bound), kept only where the
//! worst of those measures gets better and no element turns over. A
//! boundary node inside an input edge is free too, along that edge (as
//! easing slides it, `bound(boundary_slide, _)`): at a spike's tip or in
//! a small domain of few segments the nodes are nearly all on the
//! boundary, and where they sit along it decides the corners.

use glam::DVec2;

use super::ease::{rail_through, slide_rails, Rail};
use super::strips::{element_neighbours, node_elements};
use crate::mesh::{Mesh, NodeKind};
use crate::settings::ElementBounds;

/// The soft maximum's sharpness, raised in turn: a broad one first (the
/// region as a whole moves), then sharper ones (the worst measure alone).
const SHARPNESS: [f64; 3] = [30.0, 100.0, 300.0];

/// Descent steps at each sharpness, at most.
const STEPS: usize = 60;

/// A region with more free nodes than this is left as it is (the
/// descent's cost grows with their square).
const MOST_FREE_NODES: usize = 120;

/// Moves the free nodes round the elements past `bounds` (see the
/// module's comment); returns how many regions got better.
pub fn polish_past_bounds(mesh: &mut Mesh, bounds: &ElementBounds) -> usize {
    let rings = bounds.polish_rings as usize;
    if rings == 0 || mesh.quads.is_empty() {
        return 0;
    }
    let around = node_elements(mesh);
    let neighbours = element_neighbours(mesh, &around);
    let rails = slide_rails(mesh, bounds);
    let fixed_corner = fixed_corners(mesh, &rails);
    let windows = corner_windows(mesh, &around, bounds);
    let how = Measuring {
        neighbours: &neighbours,
        fixed_corner: &fixed_corner,
        windows: &windows,
        bounds,
    };
    let past: Vec<u32> = (0..mesh.quads.len() as u32)
        .filter(|&q| Measures::of(mesh, &[q], &how).worst() > 0.0)
        .collect();
    let mut done = vec![false; mesh.quads.len()];
    let mut better = 0;
    for &q in &past {
        if done[q as usize] {
            continue;
        }
        let free = free_nodes_near(mesh, &around, &rails, q, rings);
        if free.is_empty() || free.len() > MOST_FREE_NODES {
            continue;
        }
        let touched = elements_of(&around, &free);
        for &t in &touched {
            done[t as usize] = true;
        }
        let freedom: Vec<Freedom> = free
            .iter()
            .map(|&n| Freedom::of(mesh, n, rails[n as usize], bounds.boundary_slide))
            .collect();
        if polish_region(mesh, &free, &freedom, &touched, &how) {
            better += 1;
        }
    }
    better
}

/// One region: its free nodes moved together by a descent on the soft
/// maximum of its elements' measures; kept if the worst got better.
fn polish_region(
    mesh: &mut Mesh,
    free: &[u32],
    freedom: &[Freedom],
    touched: &[u32],
    how: &Measuring,
) -> bool {
    let start: Vec<DVec2> = free.iter().map(|&n| mesh.nodes[n as usize]).collect();
    let before = Measures::of(mesh, touched, how).past();
    let h = shortest_edge(mesh, touched);
    if h.is_nan() || h <= 0.0 {
        return false;
    }
    let counts: Vec<usize> = touched
        .iter()
        .map(|&q| {
            let mut v = Vec::new();
            push_measures(mesh, q, how, &mut v);
            v.len()
        })
        .collect();
    let layout = Layout::new(mesh, free, touched, how.neighbours, &counts);
    let mut x = start.clone();
    for beta in SHARPNESS {
        let value = |mesh: &mut Mesh, x: &[DVec2]| {
            place(mesh, free, x);
            if turned_over(mesh, touched) || !on_their_rails(mesh, freedom, x) {
                return f64::INFINITY;
            }
            Measures::of(mesh, touched, how).soft_max(beta)
        };
        let mut f = value(mesh, &x);
        let mut step = 0.05 * h;
        let delta = 1e-5 * h;
        for _ in 0..STEPS {
            // the gradient by central differences, node by node (from a
            // place turned over nowhere, each move measures only what it
            // changes)
            let base = f.is_finite().then(|| {
                place(mesh, free, &x);
                let m = Measures::of(mesh, touched, how);
                Base::of(m.values, beta)
            });
            let moved = |mesh: &mut Mesh, y: &[DVec2], i: usize| match &base {
                Some(b) => {
                    mesh.nodes[free[i] as usize] = y[i];
                    if !freedom[i].keeps_to(mesh, y[i]) {
                        mesh.nodes[free[i] as usize] = x[i];
                        return f64::INFINITY;
                    }
                    let v = b.moved(mesh, i, &layout, touched, how);
                    mesh.nodes[free[i] as usize] = x[i];
                    v
                }
                None => value(mesh, y),
            };
            let mut g = vec![DVec2::ZERO; x.len()];
            let mut y = x.clone();
            let slope = |up: f64, down: f64| {
                if up.is_finite() && down.is_finite() {
                    (up - down) / (2.0 * delta)
                } else {
                    0.0
                }
            };
            for i in 0..x.len() {
                if let Freedom::Plane = freedom[i] {
                    for axis in 0..2 {
                        y[i][axis] += delta;
                        let up = moved(mesh, &y, i);
                        y[i][axis] -= 2.0 * delta;
                        let down = moved(mesh, &y, i);
                        y[i][axis] = x[i][axis];
                        g[i][axis] = slope(up, down);
                    }
                } else {
                    // along the rail: one way, the length along it in x
                    y[i] = freedom[i].moved(x[i], DVec2::X * delta);
                    let up = moved(mesh, &y, i);
                    y[i] = freedom[i].moved(x[i], DVec2::X * -delta);
                    let down = moved(mesh, &y, i);
                    y[i] = x[i];
                    // at the share it keeps, one way only (from a place
                    // measured: turned over nowhere)
                    let along = match (up.is_finite(), down.is_finite(), f.is_finite()) {
                        (true, false, true) => (up - f) / delta,
                        (false, true, true) => (f - down) / delta,
                        _ => slope(up, down),
                    };
                    g[i] = DVec2::new(along, 0.0);
                }
            }
            let norm = g.iter().map(|v| v.length_squared()).sum::<f64>().sqrt();
            if norm.is_nan() || norm <= 0.0 {
                break;
            }
            // a step of `step` along the steepest descent, longer after
            // a success, shorter after a failure
            let mut moved = false;
            while step > 1e-6 * h {
                let y: Vec<DVec2> = x
                    .iter()
                    .zip(&g)
                    .zip(freedom)
                    .map(|((p, d), f)| f.moved(*p, -*d * (step / norm)))
                    .collect();
                let fy = value(mesh, &y);
                if fy < f {
                    (x, f, moved) = (y, fy, true);
                    step *= 1.5;
                    break;
                }
                step *= 0.5;
            }
            if !moved {
                break;
            }
        }
    }
    place(mesh, free, &x);
    // kept where no more measures are past their bounds and the worst
    // is better, or fewer are and the worst no worse
    let after = if turned_over(mesh, touched) {
        (usize::MAX, f64::INFINITY)
    } else {
        Measures::of(mesh, touched, how).past()
    };
    let better = (after.0 <= before.0 && after.1 < before.1 - 1e-9)
        || (after.0 < before.0 && after.1 <= before.1);
    if better {
        true
    } else {
        place(mesh, free, &start);
        false
    }
}

/// How a free node moves: anywhere (an interior node), or along the
/// input edge it lies inside (a boundary node with a rail, ease.rs),
/// keeping at least a share of the way from either boundary neighbour.
#[derive(Debug, Clone, Copy)]
enum Freedom {
    Plane,
    Rail {
        ends: (u32, u32),
        along: Along,
        keep: f64,
    },
}

/// A rail's way: a straight edge's direction, or an arc's centre.
#[derive(Debug, Clone, Copy)]
enum Along {
    Line(DVec2),
    Arc(DVec2),
}

impl Freedom {
    /// Node n's freedom, with its rail (None: an interior node, or a
    /// boundary node that stays); the share it keeps from either end is
    /// `keep`, or less where it starts nearer.
    fn of(mesh: &Mesh, n: u32, rail: Option<(u32, u32)>, keep: f64) -> Freedom {
        let Some((a, b)) = rail else {
            return Freedom::Plane;
        };
        let (pa, p, pb) = (
            mesh.nodes[a as usize],
            mesh.nodes[n as usize],
            mesh.nodes[b as usize],
        );
        let along = match rail_through(pa, p, pb) {
            Some((Rail::Line(..), _)) => Along::Line((pb - pa).normalize()),
            Some((Rail::Arc(centre, ..), _)) => Along::Arc(centre),
            None => return Freedom::Plane,
        };
        Freedom::Rail {
            ends: (a, b),
            along,
            keep: keep.min(along.share(pa, p, pb)) * (1.0 - 1e-9),
        }
    }

    /// Where a node at `p` goes moved by `d` (along a rail, by `d.x`'s
    /// length along it; in the plane `p - d` is `p + (-d)` bit for bit, so
    /// a descent step is the same either way).
    fn moved(&self, p: DVec2, d: DVec2) -> DVec2 {
        match *self {
            Freedom::Plane => p + d,
            Freedom::Rail {
                along: Along::Line(u),
                ..
            } => p + u * d.x,
            Freedom::Rail {
                along: Along::Arc(c),
                ..
            } => {
                let r = p - c;
                c + DVec2::from_angle(d.x / r.length()).rotate(r)
            }
        }
    }

    /// Whether a node at `p` keeps its share of the way from its rail's
    /// ends where the mesh has them (a plane's always).
    fn keeps_to(&self, mesh: &Mesh, p: DVec2) -> bool {
        match *self {
            Freedom::Plane => true,
            Freedom::Rail {
                ends: (a, b),
                along,
                keep,
            } => {
                let share = along.share(mesh.nodes[a as usize], p, mesh.nodes[b as usize]);
                share > 0.0 && share >= keep
            }
        }
    }
}

impl Along {
    /// The lesser share of the way from `pa` and `pb` a point `p` on the
    /// rail is (0: not between them).
    fn share(self, pa: DVec2, p: DVec2, pb: DVec2) -> f64 {
        let (d1, d2) = match self {
            Along::Line(u) => ((p - pa).dot(u), (pb - p).dot(u)),
            Along::Arc(c) => {
                let turn = |x: DVec2, y: DVec2| x.perp_dot(y).atan2(x.dot(y));
                (turn(pa - c, p - c), turn(p - c, pb - c))
            }
        };
        if d1 * d2 <= 0.0 {
            return 0.0;
        }
        d1.abs().min(d2.abs()) / (d1.abs() + d2.abs())
    }
}

/// Whether every node on a rail keeps its share of the way, its ends
/// where the mesh has them.
fn on_their_rails(mesh: &Mesh, freedom: &[Freedom], x: &[DVec2]) -> bool {
    freedom.iter().zip(x).all(|(f, &p)| f.keeps_to(mesh, p))
}

fn place(mesh: &mut Mesh, free: &[u32], x: &[DVec2]) {
    for (&n, &p) in free.iter().zip(x) {
        mesh.nodes[n as usize] = p;
    }
}

/// Whether an element of `qs` has a corner of no positive turn (turned
/// over or folded).
fn turned_over(mesh: &Mesh, qs: &[u32]) -> bool {
    qs.iter().any(|&q| {
        let p = mesh.quad_points(q as usize);
        (0..4).any(|i| (p[(i + 1) % 4] - p[i]).perp_dot(p[(i + 3) % 4] - p[i]) <= 0.0)
    })
}

fn shortest_edge(mesh: &Mesh, qs: &[u32]) -> f64 {
    qs.iter()
        .flat_map(|&q| {
            let p = mesh.quad_points(q as usize);
            (0..4).map(move |i| (p[(i + 1) % 4] - p[i]).length())
        })
        .fold(f64::INFINITY, f64::min)
}

/// The elements at any of `nodes`, sorted.
fn elements_of(around: &[Vec<(u32, u8)>], nodes: &[u32]) -> Vec<u32> {
    let mut qs: Vec<u32> = nodes
        .iter()
        .flat_map(|&n| around[n as usize].iter().map(|a| a.0))
        .collect();
    qs.sort_unstable();
    qs.dedup();
    qs
}

/// The interior nodes within `rings` rings of elements round element q,
/// and the boundary nodes there that may slide along a rail, sorted.
fn free_nodes_near(
    mesh: &Mesh,
    around: &[Vec<(u32, u8)>],
    rails: &[Option<(u32, u32)>],
    q: u32,
    rings: usize,
) -> Vec<u32> {
    let mut nodes: Vec<u32> = mesh.quads[q as usize].to_vec();
    for _ in 1..rings {
        nodes = elements_of(around, &nodes)
            .into_iter()
            .flat_map(|o| mesh.quads[o as usize])
            .collect();
    }
    nodes.sort_unstable();
    nodes.dedup();
    nodes.retain(|&n| mesh.kinds[n as usize] == NodeKind::Interior || rails[n as usize].is_some());
    nodes
}

/// Per corner (4 q + k), whether no move of a free node changes it: its
/// node and both neighbours in the element fixed (boundary nodes with no
/// rail: a lone element at an input corner). Such a corner is left out
/// of the measures: nothing here can change it.
fn fixed_corners(mesh: &Mesh, rails: &[Option<(u32, u32)>]) -> Vec<bool> {
    let fixed =
        |n: u32| mesh.kinds[n as usize] != NodeKind::Interior && rails[n as usize].is_none();
    mesh.quads
        .iter()
        .flat_map(|quad| {
            (0..4).map(move |k| {
                fixed(quad[k]) && fixed(quad[(k + 1) % 4]) && fixed(quad[(k + 3) % 4])
            })
        })
        .collect()
}

/// Per node, the window its elements' corners are measured against:
/// the bounds', but at a boundary node whose elements share a corner
/// too sharp (or too wide) for all to be within it, their even share of
/// that corner (as near as they can come).
fn corner_windows(
    mesh: &Mesh,
    around: &[Vec<(u32, u8)>],
    bounds: &ElementBounds,
) -> Vec<(f64, f64)> {
    (0..mesh.nodes.len())
        .map(|n| {
            let window = (bounds.lower_corner, bounds.upper_corner);
            if mesh.kinds[n] == NodeKind::Interior || around[n].is_empty() {
                return window;
            }
            let total: f64 = around[n]
                .iter()
                .map(|&(q, k)| {
                    crate::geometry::quad_angles(mesh.quad_points(q as usize))[k as usize]
                })
                .sum();
            let share = total / around[n].len() as f64;
            (window.0.min(share), window.1.max(share))
        })
        .collect()
}

/// Every measure of some elements as a share of its bound past it
/// (negative within): corners against the window, size jumps against
/// the neighbours, aspect ratio and taper.
struct Measures {
    values: Vec<f64>,
}

/// What the measures of an element are taken against: its neighbours,
/// the corners no move changes, each node's window, the bounds.
struct Measuring<'a> {
    neighbours: &'a [[Option<u32>; 4]],
    fixed_corner: &'a [bool],
    windows: &'a [(f64, f64)],
    bounds: &'a ElementBounds,
}

impl Measures {
    fn of(mesh: &Mesh, qs: &[u32], how: &Measuring) -> Measures {
        let mut values = Vec::with_capacity(qs.len() * 10);
        for &q in qs {
            push_measures(mesh, q, how, &mut values);
        }
        Measures { values }
    }

    /// How many measures are past their bounds, and the worst.
    fn past(&self) -> (usize, f64) {
        (
            self.values.iter().filter(|&&v| v > 0.0).count(),
            self.worst(),
        )
    }

    fn worst(&self) -> f64 {
        self.values
            .iter()
            .copied()
            .fold(f64::NEG_INFINITY, f64::max)
    }

    /// log-sum-exp over `beta`, shifted by the worst (no overflow).
    fn soft_max(&self, beta: f64) -> f64 {
        let w = self.worst();
        if !w.is_finite() {
            return w;
        }
        let s: f64 = self.values.iter().map(|v| (beta * (v - w)).exp()).sum();
        w + s.ln() / beta
    }
}

/// The measures of element q (see `Measures`), pushed onto `out`: its
/// corners that can move, its aspect ratio and taper, its size jump to
/// each neighbour.
fn push_measures(mesh: &Mesh, q: u32, how: &Measuring, out: &mut Vec<f64>) {
    let Measuring {
        neighbours,
        fixed_corner,
        windows,
        bounds,
    } = *how;
    let area = |q: u32| crate::geometry::polygon_area(&mesh.quad_points(q as usize)).abs();
    let p = mesh.quad_points(q as usize);
    let angles = crate::geometry::quad_angles(p);
    let quad = mesh.quads[q as usize];
    for (k, a) in angles.iter().enumerate() {
        if fixed_corner[4 * q as usize + k] {
            continue;
        }
        let (lower, upper) = windows[quad[k] as usize];
        out.push((lower - a).max(a - upper) / 45.0);
    }
    let (aspect, taper) = crate::element_quality::aspect_taper(p);
    out.push((aspect - bounds.max_aspect) / bounds.max_aspect);
    out.push((taper - bounds.max_taper) / bounds.max_taper);
    let mine = area(q).max(1e-300);
    for o in neighbours[q as usize].iter().flatten() {
        let other = area(*o).max(1e-300);
        let jump = (mine / other).max(other / mine).sqrt();
        out.push((jump - bounds.max_size_jump) / bounds.max_size_jump);
    }
}

/// A region's measures at one place of its free nodes, for the
/// gradient's moves of one node at a time: a move measures again only
/// the elements whose measures it changes (those at the node and their
/// neighbours), and takes the soft maximum's other terms as they were;
/// the same numbers as `Measures::of` and `soft_max` afresh.
struct Base {
    values: Vec<f64>,
    worst: f64,
    /// Each value's term of the soft maximum's sum.
    terms: Vec<f64>,
    beta: f64,
}

/// Where each element's measures are in a region's, and which elements
/// a move of each free node changes.
struct Layout {
    /// Per element of the region: where its measures start (and, last,
    /// their count).
    starts: Vec<usize>,
    /// Per free node: the region's elements (their places in it) whose
    /// measures its place changes.
    changed: Vec<Vec<usize>>,
    /// Per free node: the elements with it as a corner.
    at: Vec<Vec<u32>>,
}

impl Layout {
    fn new(
        mesh: &Mesh,
        free: &[u32],
        touched: &[u32],
        neighbours: &[[Option<u32>; 4]],
        counts: &[usize],
    ) -> Layout {
        let mut starts = Vec::with_capacity(touched.len() + 1);
        let mut sum = 0;
        for c in counts {
            starts.push(sum);
            sum += c;
        }
        starts.push(sum);
        let mut changed = vec![Vec::new(); free.len()];
        let mut at = vec![Vec::new(); free.len()];
        for (j, &q) in touched.iter().enumerate() {
            let mut nodes: Vec<u32> = mesh.quads[q as usize].to_vec();
            for o in neighbours[q as usize].iter().flatten() {
                nodes.extend(mesh.quads[*o as usize]);
            }
            nodes.sort_unstable();
            nodes.dedup();
            for n in nodes {
                if let Ok(i) = free.binary_search(&n) {
                    changed[i].push(j);
                }
            }
            for n in mesh.quads[q as usize] {
                if let Ok(i) = free.binary_search(&n) {
                    if !at[i].contains(&q) {
                        at[i].push(q);
                    }
                }
            }
        }
        Layout {
            starts,
            changed,
            at,
        }
    }
}

impl Base {
    fn of(values: Vec<f64>, beta: f64) -> Base {
        let worst = values.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let terms = values.iter().map(|v| (beta * (v - worst)).exp()).collect();
        Base {
            values,
            worst,
            terms,
            beta,
        }
    }

    /// The soft maximum with free node `i` where the mesh has it (every
    /// other node at the base's place; the base turned over nowhere).
    fn moved(
        &self,
        mesh: &Mesh,
        i: usize,
        layout: &Layout,
        touched: &[u32],
        how: &Measuring,
    ) -> f64 {
        if turned_over(mesh, &layout.at[i]) {
            return f64::INFINITY;
        }
        let mut values = self.values.clone();
        let mut fresh = Vec::new();
        for &j in &layout.changed[i] {
            fresh.clear();
            push_measures(mesh, touched[j], how, &mut fresh);
            values[layout.starts[j]..layout.starts[j + 1]].copy_from_slice(&fresh);
        }
        let w = values.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        if !w.is_finite() {
            return w;
        }
        let beta = self.beta;
        let s: f64 = if w.to_bits() == self.worst.to_bits() {
            let mut terms = self.terms.clone();
            for &j in &layout.changed[i] {
                for k in layout.starts[j]..layout.starts[j + 1] {
                    terms[k] = (beta * (values[k] - w)).exp();
                }
            }
            terms.iter().sum()
        } else {
            values.iter().map(|v| (beta * (v - w)).exp()).sum()
        };
        w + s.ln() / beta
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A grid of 3 x 3 unit squares, its four inner nodes moved by
    /// `shift` (nodes 5, 6, 9, 10: the grid's nodes are numbered by rows).
    fn grid(shift: [DVec2; 4]) -> Mesh {
        let mut m = crate::mesh::three_by_three();
        for (k, n) in [5usize, 6, 9, 10].into_iter().enumerate() {
            m.nodes[n] += shift[k];
        }
        m
    }

    fn worst_corner_past(m: &Mesh, b: &ElementBounds) -> f64 {
        (0..m.quads.len())
            .flat_map(|q| crate::geometry::quad_angles(m.quad_points(q)))
            .map(|a| (b.lower_corner - a).max(a - b.upper_corner))
            .fold(f64::NEG_INFINITY, f64::max)
    }

    /// Two inner nodes pushed together toward a corner leave corners
    /// past 135 deg; moved together they come within the window, and
    /// the boundary nodes stay where they are.
    #[test]
    fn corners_past_the_window_come_within_it_and_the_boundary_stays() {
        let d = DVec2::new(0.42, 0.42);
        let mut m = grid([d, d, DVec2::ZERO, DVec2::ZERO]);
        let before = m.clone();
        let b = ElementBounds::default();
        assert!(
            worst_corner_past(&m, &b) > 5.0,
            "{}",
            worst_corner_past(&m, &b)
        );
        assert_eq!(polish_past_bounds(&mut m, &b), 1);
        assert!(
            worst_corner_past(&m, &b) <= 0.0,
            "{}",
            worst_corner_past(&m, &b)
        );
        for n in 0..m.nodes.len() {
            if m.kinds[n] == NodeKind::Boundary {
                assert_eq!(m.nodes[n], before.nodes[n]);
            }
        }
    }

    /// A move of one free node measured from the base gives the soft
    /// maximum measured afresh, bit for bit: where it changes the worst
    /// measure and where it does not, and where it turns an element over.
    #[test]
    fn a_move_from_the_base_measures_as_the_region_afresh() {
        let d = DVec2::new(0.42, 0.42);
        let mut m = grid([d, d, DVec2::ZERO, DVec2::ZERO]);
        let b = ElementBounds::default();
        let around = node_elements(&m);
        let neighbours = element_neighbours(&m, &around);
        let rails = slide_rails(&m, &b);
        let fixed = fixed_corners(&m, &rails);
        let windows = corner_windows(&m, &around, &b);
        let how = Measuring {
            neighbours: &neighbours,
            fixed_corner: &fixed,
            windows: &windows,
            bounds: &b,
        };
        let free: Vec<u32> = vec![5, 6, 9, 10];
        let touched = elements_of(&around, &free);
        let counts: Vec<usize> = touched
            .iter()
            .map(|&q| {
                let mut v = Vec::new();
                push_measures(&m, q, &how, &mut v);
                v.len()
            })
            .collect();
        let layout = Layout::new(&m, &free, &touched, &neighbours, &counts);
        let afresh = |m: &Mesh, beta: f64| {
            if turned_over(m, &touched) {
                return f64::INFINITY;
            }
            Measures::of(m, &touched, &how).soft_max(beta)
        };
        let (mut same_worst, mut other_worst, mut turned) = (0, 0, 0);
        for beta in SHARPNESS {
            let base_values = Measures::of(&m, &touched, &how).values;
            let base = Base::of(base_values, beta);
            for (i, &n) in free.iter().enumerate() {
                let at = m.nodes[n as usize];
                for k in 0..24 {
                    let t = k as f64 * 0.7;
                    let r = 0.05 * (1 + k % 4) as f64 * if k % 7 == 6 { 12.0 } else { 1.0 };
                    m.nodes[n as usize] = at + r * DVec2::new(t.cos(), t.sin());
                    let want = afresh(&m, beta);
                    let got = base.moved(&m, i, &layout, &touched, &how);
                    assert_eq!(want.to_bits(), got.to_bits(), "node {n}, move {k}");
                    let worst = Measures::of(&m, &touched, &how).worst();
                    if !want.is_finite() {
                        turned += 1;
                    } else if worst.to_bits() == base.worst.to_bits() {
                        same_worst += 1;
                    } else {
                        other_worst += 1;
                    }
                }
                m.nodes[n as usize] = at;
            }
        }
        assert!(
            same_worst > 0 && other_worst > 0 && turned > 0,
            "{same_worst} {other_worst} {turned}"
        );
    }

    /// `bound(polish_rings, 0)` leaves the mesh as it is, and so does a
    /// mesh within the bounds.
    #[test]
    fn no_rings_or_nothing_past_the_bounds_leaves_the_mesh() {
        let d = DVec2::new(0.42, 0.42);
        let mut m = grid([d, d, DVec2::ZERO, DVec2::ZERO]);
        let before = m.nodes.clone();
        let off = ElementBounds::default().with_polish_rings(0.0).unwrap();
        assert_eq!(polish_past_bounds(&mut m, &off), 0);
        assert_eq!(m.nodes, before);
        let mut square = grid([DVec2::ZERO; 4]);
        let before = square.nodes.clone();
        assert_eq!(
            polish_past_bounds(&mut square, &ElementBounds::default()),
            0
        );
        assert_eq!(square.nodes, before);
    }

    /// A rings bound must be a whole number from 0 to 4.
    #[test]
    fn the_rings_bound_is_checked() {
        let b = ElementBounds::default();
        assert!(b.with_polish_rings(1.5).is_err());
        assert!(b.with_polish_rings(5.0).is_err());
        assert_eq!(b.with_polish_rings(3.0).unwrap().polish_rings, 3.0);
    }
}
