//! The drawn edges joined at their end points into loops and lines.

use std::collections::HashMap;
use std::f64::consts::PI;

use glam::DVec2;

use crate::geometry::point_in_polygon;
use crate::input::domain::Curve;

use super::{Circle, DrawnCircle, DrawnEdge, DxfError, Loop, Outline, Polyline, JOIN_TOLERANCE};

/// An edge of the joined drawing between two joined points.
#[derive(Debug, Clone)]
struct GraphEdge {
    ends: [usize; 2],
    /// From `ends[0]` to `ends[1]`.
    bulge: f64,
    layer: String,
}

/// An edge walked one way: (edge, forward).
type HalfEdge = (usize, bool);

/// The drawing's edges joined at their end points.
struct Graph {
    points: Vec<DVec2>,
    edges: Vec<GraphEdge>,
    /// The edges at each point.
    at: Vec<Vec<usize>>,
}

impl Graph {
    /// Joins end points within `tol`: typed points first, so that a
    /// computed end snaps onto a typed one.
    fn join(drawn: &[DrawnEdge], tol: f64) -> Graph {
        let mut ends: Vec<(DVec2, bool, usize, usize)> = Vec::new();
        for (i, e) in drawn.iter().enumerate() {
            ends.push((e.a, e.typed, i, 0));
            ends.push((e.b, e.typed, i, 1));
        }
        // typed first, then in file order: a stable sort keeps the order
        ends.sort_by_key(|e| !e.1);
        let cell = |p: DVec2| ((p.x / tol).floor() as i64, (p.y / tol).floor() as i64);
        let mut grid: HashMap<(i64, i64), Vec<usize>> = HashMap::new();
        let mut points: Vec<DVec2> = Vec::new();
        let mut end_point = vec![[usize::MAX; 2]; drawn.len()];
        for &(p, _, i, side) in &ends {
            let (cx, cy) = cell(p);
            let mut found = None;
            'search: for dx in -1..=1 {
                for dy in -1..=1 {
                    for &q in grid.get(&(cx + dx, cy + dy)).into_iter().flatten() {
                        if (points[q] - p).length() <= tol {
                            found = Some(q);
                            break 'search;
                        }
                    }
                }
            }
            let q = found.unwrap_or_else(|| {
                points.push(p);
                grid.entry((cx, cy)).or_default().push(points.len() - 1);
                points.len() - 1
            });
            end_point[i][side] = q;
        }
        let mut edges = Vec::new();
        // an edge drawn twice (CAD drawings often hold copies) counts once
        let mut seen = std::collections::HashSet::new();
        for (i, e) in drawn.iter().enumerate() {
            let ends = end_point[i];
            if ends[0] == ends[1] {
                continue; // shorter than the tolerance: a point
            }
            let key = if ends[0] < ends[1] {
                (ends[0], ends[1], (e.bulge + 0.0).to_bits())
            } else {
                (ends[1], ends[0], (0.0 - e.bulge).to_bits())
            };
            if !seen.insert(key) {
                continue;
            }
            edges.push(GraphEdge {
                ends,
                bulge: e.bulge,
                layer: e.layer.clone(),
            });
        }
        let mut at = vec![Vec::new(); points.len()];
        for (k, e) in edges.iter().enumerate() {
            at[e.ends[0]].push(k);
            at[e.ends[1]].push(k);
        }
        Graph { points, edges, at }
    }

    fn start(&self, h: HalfEdge) -> usize {
        self.edges[h.0].ends[if h.1 { 0 } else { 1 }]
    }

    fn end(&self, h: HalfEdge) -> usize {
        self.edges[h.0].ends[if h.1 { 1 } else { 0 }]
    }

    fn bulge(&self, h: HalfEdge) -> f64 {
        if h.1 {
            self.edges[h.0].bulge
        } else {
            // 0 - b, not -b: a straight edge stays 0, not -0
            0.0 - self.edges[h.0].bulge
        }
    }

    fn curve(&self, h: HalfEdge) -> Curve {
        let (a, b) = (self.points[self.start(h)], self.points[self.end(h)]);
        let bulge = self.bulge(h);
        if bulge == 0.0 {
            Curve::Line { a, b }
        } else {
            Curve::Arc { a, b, bulge }
        }
    }

    /// The direction in which a half-edge leaves its start (an arc's
    /// tangent: the chord turned by half the sweep, away from the bulge).
    fn leaving_angle(&self, h: HalfEdge) -> f64 {
        let d = self.points[self.end(h)] - self.points[self.start(h)];
        d.y.atan2(d.x) - 2.0 * self.bulge(h).atan()
    }

    /// Removes the chains that hang free (repeatedly, the edges at a
    /// point met by one active edge); returns them.
    fn prune_hanging(&self, active: &mut [bool]) -> Vec<usize> {
        let mut degree = vec![0usize; self.points.len()];
        for (k, e) in self.edges.iter().enumerate() {
            if active[k] {
                degree[e.ends[0]] += 1;
                degree[e.ends[1]] += 1;
            }
        }
        let mut queue: Vec<usize> = (0..self.points.len()).filter(|&p| degree[p] == 1).collect();
        let mut pruned = Vec::new();
        while let Some(p) = queue.pop() {
            if degree[p] != 1 {
                continue;
            }
            let Some(&k) = self.at[p].iter().find(|&&k| active[k]) else {
                continue;
            };
            active[k] = false;
            pruned.push(k);
            for &q in &self.edges[k].ends {
                degree[q] -= 1;
                if degree[q] == 1 {
                    queue.push(q);
                }
            }
        }
        pruned
    }

    /// The active edges in connected pieces, each in ascending order.
    fn components(&self, active: &[bool]) -> Vec<Vec<usize>> {
        let mut seen = vec![false; self.edges.len()];
        let mut out = Vec::new();
        for k0 in 0..self.edges.len() {
            if !active[k0] || seen[k0] {
                continue;
            }
            let mut comp = Vec::new();
            let mut stack = vec![k0];
            seen[k0] = true;
            while let Some(k) = stack.pop() {
                comp.push(k);
                for &p in &self.edges[k].ends {
                    for &j in &self.at[p] {
                        if active[j] && !seen[j] {
                            seen[j] = true;
                            stack.push(j);
                        }
                    }
                }
            }
            comp.sort_unstable();
            out.push(comp);
        }
        out
    }

    /// The walk round the outside of a connected piece (its unbounded
    /// face, clockwise): at each point the walk takes the sharpest left
    /// turn, which keeps the face on its left; of all the faces so
    /// walked, the outside is the one of negative area.
    fn outside_walk(&self, comp: &[usize], active: &[bool]) -> Vec<HalfEdge> {
        // the half-edges leaving each point, counter-clockwise by angle
        let mut leaving: HashMap<usize, Vec<(f64, HalfEdge)>> = HashMap::new();
        for &k in comp {
            for h in [(k, true), (k, false)] {
                leaving
                    .entry(self.start(h))
                    .or_default()
                    .push((self.leaving_angle(h), h));
            }
        }
        for v in leaving.values_mut() {
            v.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        }
        let next = |h: HalfEdge| -> HalfEdge {
            let around = &leaving[&self.end(h)];
            let back = (h.0, !h.1);
            let i = around
                .iter()
                .position(|x| x.1 == back)
                .expect("the reverse half-edge leaves the end point");
            // the first one clockwise from the way back
            around[(i + around.len() - 1) % around.len()].1
        };
        let mut walked: std::collections::HashSet<HalfEdge> = Default::default();
        let mut best: Option<(f64, Vec<HalfEdge>)> = None;
        for &k in comp {
            debug_assert!(active[k]);
            for h0 in [(k, true), (k, false)] {
                if walked.contains(&h0) {
                    continue;
                }
                let mut face = Vec::new();
                let mut h = h0;
                loop {
                    walked.insert(h);
                    face.push(h);
                    h = next(h);
                    if h == h0 || face.len() > 2 * comp.len() {
                        break;
                    }
                }
                let area: f64 = face.iter().map(|&h| self.curve(h).signed_area_term()).sum();
                if best.as_ref().is_none_or(|b| area < b.0) {
                    best = Some((area, face));
                }
            }
        }
        best.map(|b| b.1).unwrap_or_default()
    }
}

/// Loops and line edges of a set of edges: hanging chains and chains
/// inside a loop are line edges, the outsides of the rest loops, and
/// what lies inside a loop is sorted the same way in turn.
fn loops_and_lines(
    g: &Graph,
    mut active: Vec<bool>,
    loops: &mut Vec<Vec<HalfEdge>>,
    lines: &mut Vec<usize>,
) {
    lines.extend(g.prune_hanging(&mut active));
    for comp in g.components(&active) {
        let walk = g.outside_walk(&comp, &active);
        let mut count: HashMap<usize, usize> = HashMap::new();
        for h in &walk {
            *count.entry(h.0).or_default() += 1;
        }
        // an edge walked both ways joins two loops: a line; the runs of
        // the walk between such edges are loops
        let once = |h: &HalfEdge| count[&h.0] == 1;
        let mut runs: Vec<Vec<HalfEdge>> = Vec::new();
        match walk.iter().position(|h| !once(h)) {
            None => runs.push(walk.clone()),
            Some(s) => {
                let mut run = Vec::new();
                for i in 0..walk.len() {
                    let h = walk[(s + i) % walk.len()];
                    if once(&h) {
                        run.push(h);
                    } else if !run.is_empty() {
                        runs.push(std::mem::take(&mut run));
                    }
                }
                if !run.is_empty() {
                    runs.push(run);
                }
            }
        }
        let mut inner = vec![false; g.edges.len()];
        for &k in &comp {
            inner[k] = true;
        }
        for h in &walk {
            if once(h) {
                inner[h.0] = false;
            }
        }
        loops.extend(runs);
        if inner.iter().any(|&x| x) {
            loops_and_lines(g, inner, loops, lines);
        }
    }
}

/// A fine polygon of a loop, for inside tests.
fn fine_polygon(curves: &[Curve]) -> Vec<DVec2> {
    let mut pts = Vec::new();
    for c in curves {
        let n = match *c {
            Curve::Line { .. } => 1,
            Curve::Arc { bulge, .. } => {
                ((4.0 * bulge.atan()).abs() / (PI / 64.0)).ceil().max(2.0) as usize
            }
            Curve::Circle { .. } => 128,
        };
        let p = c.divide(n);
        match c {
            Curve::Circle { .. } => pts.extend(p),
            _ => pts.extend(&p[..n]),
        }
    }
    pts
}

/// The outline of drawn edges and circles: `path` names the file in
/// messages.
pub fn outline_of(
    drawn: &[DrawnEdge],
    circles: &[DrawnCircle],
    path: &str,
) -> Result<Outline, DxfError> {
    let (mut lo, mut hi) = (DVec2::splat(f64::MAX), DVec2::splat(f64::MIN));
    for e in drawn {
        lo = lo.min(e.a).min(e.b);
        hi = hi.max(e.a).max(e.b);
    }
    for c in circles {
        lo = lo.min(c.center - c.radius);
        hi = hi.max(c.center + c.radius);
    }
    if drawn.is_empty() && circles.is_empty() {
        return Err(DxfError::Empty { path: path.into() });
    }
    let extent = (hi - lo)
        .max_element()
        .max(lo.abs().max_element() * 1e-9)
        .max(1e-300);
    let tol = JOIN_TOLERANCE * extent;
    let g = Graph::join(drawn, tol);
    let mut walks = Vec::new();
    let mut line_edges = Vec::new();
    loops_and_lines(&g, vec![true; g.edges.len()], &mut walks, &mut line_edges);

    // every loop, as curves, with its walk or circle
    enum Found {
        Walk(Vec<HalfEdge>),
        Circle(usize),
    }
    let mut found: Vec<(Vec<Curve>, Found)> = walks
        .into_iter()
        .map(|w| (w.iter().map(|&h| g.curve(h)).collect(), Found::Walk(w)))
        .collect();
    for (i, c) in circles.iter().enumerate() {
        found.push((
            vec![Curve::Circle {
                center: c.center,
                radius: c.radius,
            }],
            Found::Circle(i),
        ));
    }
    let lines = line_paths(
        &g,
        &line_edges,
        &found
            .iter()
            .filter_map(|f| match &f.1 {
                Found::Walk(w) => Some(w.as_slice()),
                Found::Circle(_) => None,
            })
            .collect::<Vec<_>>(),
    );

    let free_ends: Vec<usize> = (0..g.points.len())
        .filter(|&p| g.at[p].len() == 1)
        .collect();
    // the two nearest free ends, or (no two) a chain that is no loop
    let gap = |more: usize| -> DxfError {
        let mut best: Option<(f64, usize, usize)> = None;
        for (i, &p) in free_ends.iter().enumerate() {
            for &q in &free_ends[i + 1..] {
                let d = (g.points[p] - g.points[q]).length();
                if best.is_none_or(|b| d < b.0) {
                    best = Some((d, p, q));
                }
            }
        }
        match best {
            Some((distance, p, q)) => DxfError::Gap {
                path: path.into(),
                from: g.points[p],
                to: g.points[q],
                distance,
                tolerance: tol,
                more: if more > 1 {
                    format!(" ({more} open chains in all)")
                } else {
                    String::new()
                },
            },
            None => DxfError::Shape {
                path: path.into(),
                message: "no closed loop round the drawing".into(),
            },
        }
    };
    if found.is_empty() {
        return Err(gap(lines.len()));
    }
    let areas: Vec<f64> = found
        .iter()
        .map(|(c, _)| c.iter().map(Curve::signed_area_term).sum::<f64>())
        .collect();
    let outer = (0..found.len())
        .max_by(|&a, &b| areas[a].abs().total_cmp(&areas[b].abs()).then(b.cmp(&a)))
        .expect("a loop");
    let polygon = fine_polygon(&found[outer].0);
    for (i, (curves, _)) in found.iter().enumerate() {
        if i != outer && !point_in_polygon(curves[0].point_at(0.0), &polygon) {
            let p = curves[0].point_at(0.0);
            let q = found[outer].0[0].point_at(0.0);
            return Err(DxfError::Shape {
                path: path.into(),
                message: format!(
                    "two outlines side by side: the loop through ({}, {}) lies outside the loop through ({}, {})",
                    p.x, p.y, q.x, q.y
                ),
            });
        }
    }
    let outside = lines
        .iter()
        .filter(|l| {
            // a line lies inside when a point of it does: take the middle
            // of its first edge (its ends may lie on the loop)
            let a = DVec2::new(l.points[0][0], l.points[0][1]);
            let b = DVec2::new(l.points[1][0], l.points[1][1]);
            let bulge = l.bulges.as_ref().map_or(0.0, |b| b[0]);
            let first = if bulge == 0.0 {
                Curve::Line { a, b }
            } else {
                Curve::Arc { a, b, bulge }
            };
            !point_in_polygon(first.point_at(0.5), &polygon)
        })
        .count();
    if outside > 0 {
        return Err(gap(outside));
    }

    let to_loop = |i: usize, ccw: bool| -> Loop {
        match &found[i].1 {
            Found::Circle(c) => {
                let c = &circles[*c];
                Loop::Circle {
                    circle: Circle {
                        center: [c.center.x, c.center.y],
                        radius: c.radius,
                        tag: (!c.layer.is_empty()).then(|| c.layer.clone()),
                    },
                }
            }
            Found::Walk(w) => {
                let mut w = w.clone();
                if (areas[i] > 0.0) != ccw {
                    w = w.iter().rev().map(|&(k, f)| (k, !f)).collect();
                }
                // start at the lowest point (then leftmost)
                let s = (0..w.len())
                    .min_by(|&a, &b| {
                        let (p, q) = (g.points[g.start(w[a])], g.points[g.start(w[b])]);
                        p.y.total_cmp(&q.y).then(p.x.total_cmp(&q.x))
                    })
                    .unwrap_or(0);
                w.rotate_left(s);
                Loop::Polyline(polyline_of(&g, &w, false))
            }
        }
    };
    let holes = (0..found.len())
        .filter(|&i| i != outer)
        .map(|i| to_loop(i, false))
        .collect();
    Ok(Outline {
        outer: to_loop(outer, true),
        holes,
        lines,
        tolerance: tol,
        warnings: Vec::new(),
    })
}

/// The polyline of a walk; `open` adds the last end point.
fn polyline_of(g: &Graph, walk: &[HalfEdge], open: bool) -> Polyline {
    let mut points: Vec<[f64; 2]> = walk
        .iter()
        .map(|&h| g.points[g.start(h)].to_array())
        .collect();
    if open {
        if let Some(&h) = walk.last() {
            points.push(g.points[g.end(h)].to_array());
        }
    }
    let bulges: Vec<f64> = walk.iter().map(|&h| g.bulge(h)).collect();
    let tags: Vec<String> = walk.iter().map(|&h| g.edges[h.0].layer.clone()).collect();
    Polyline {
        points,
        bulges: bulges.iter().any(|&b| b != 0.0).then_some(bulges),
        tags: tags.iter().any(|t| !t.is_empty()).then_some(tags),
    }
}

/// The line edges as paths: a path runs on through a point met by two
/// line edges and by no loop, and stops anywhere else.
fn line_paths(g: &Graph, line_edges: &[usize], loops: &[&[HalfEdge]]) -> Vec<Polyline> {
    let mut is_line = vec![false; g.edges.len()];
    for &k in line_edges {
        is_line[k] = true;
    }
    let mut on_loop = vec![false; g.points.len()];
    for w in loops {
        for &h in *w {
            on_loop[g.start(h)] = true;
        }
    }
    let line_degree = |p: usize| g.at[p].iter().filter(|&&k| is_line[k]).count();
    let through = |p: usize| !on_loop[p] && line_degree(p) == 2;
    let mut used = vec![false; g.edges.len()];
    let mut paths = Vec::new();
    let walk_from = |p0: usize, k0: usize, used: &mut Vec<bool>| -> Vec<HalfEdge> {
        let mut path = Vec::new();
        let (mut p, mut k) = (p0, k0);
        loop {
            used[k] = true;
            let h = (k, g.edges[k].ends[0] == p);
            path.push(h);
            p = g.end(h);
            if !through(p) {
                break;
            }
            match g.at[p].iter().find(|&&j| is_line[j] && !used[j]) {
                Some(&j) => k = j,
                None => break,
            }
        }
        path
    };
    // from the ends first (in point order), then what is left: rings of
    // line edges alone
    for p in 0..g.points.len() {
        if through(p) {
            continue;
        }
        for &k in &g.at[p] {
            if is_line[k] && !used[k] {
                paths.push(walk_from(p, k, &mut used));
            }
        }
    }
    for &k in line_edges {
        if !used[k] {
            paths.push(walk_from(g.edges[k].ends[0], k, &mut used));
        }
    }
    paths
        .into_iter()
        .map(|mut path| {
            // start at the lower (then left) end
            let (a, b) = (
                g.points[g.start(path[0])],
                g.points[g.end(path[path.len() - 1])],
            );
            if b.y.total_cmp(&a.y).then(b.x.total_cmp(&a.x)).is_lt() {
                path = path.iter().rev().map(|&(k, f)| (k, !f)).collect();
            }
            polyline_of(g, &path, true)
        })
        .collect()
}
