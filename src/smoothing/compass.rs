//! The compass search: the best place for a node (or nodes moved
//! together) among the eight directions round the best so far, the step
//! halving each round.

use glam::DVec2;

use crate::mesh::Mesh;

/// The eight directions of the compass search, a unit step each.
pub(crate) const COMPASS: [DVec2; 8] = {
    let d = std::f64::consts::FRAC_1_SQRT_2;
    [
        DVec2::new(1.0, 0.0),
        DVec2::new(d, d),
        DVec2::new(0.0, 1.0),
        DVec2::new(-d, d),
        DVec2::new(-1.0, 0.0),
        DVec2::new(-d, -d),
        DVec2::new(0.0, -1.0),
        DVec2::new(d, -d),
    ]
};

/// The best place for node `n` by a compass search: the eight directions
/// round the best place so far, six times over, the step halving from a
/// quarter of the shortest edge at the node. `score` judges the node where
/// it is put, given the best score so far (None: not allowed there, or
/// sure to be no better); a place is taken when `better` than the best so
/// far. The node is left where it was.
pub(crate) fn compass_search<S: Copy>(
    mesh: &mut Mesh,
    n: usize,
    around: &[(u32, u8)],
    start: S,
    score: impl FnMut(&Mesh, S) -> Option<S>,
    better: impl Fn(S, S) -> bool,
) -> DVec2 {
    compass_search_steps(mesh, n, around, start, score, better, 6)
}

/// `compass_search` with `steps` halvings of the step instead of six.
pub fn compass_search_steps<S: Copy>(
    mesh: &mut Mesh,
    n: usize,
    around: &[(u32, u8)],
    start: S,
    score: impl FnMut(&Mesh, S) -> Option<S>,
    better: impl Fn(S, S) -> bool,
    steps: usize,
) -> DVec2 {
    compass_search_together(mesh, &[n], around, start, score, better, steps)
}

/// `compass_search_steps` moving the nodes `ns` together, each by the
/// same displacement; `around` holds their elements. Returns the best
/// place of the first; the others keep their offsets from it.
pub(crate) fn compass_search_together<S: Copy>(
    mesh: &mut Mesh,
    ns: &[usize],
    around: &[(u32, u8)],
    start: S,
    score: impl FnMut(&Mesh, S) -> Option<S>,
    better: impl Fn(S, S) -> bool,
    steps: usize,
) -> DVec2 {
    let h = around
        .iter()
        .map(|&(q, c)| {
            let quad = mesh.quads[q as usize];
            let at = mesh.nodes[quad[c as usize] as usize];
            (mesh.nodes[quad[(c as usize + 1) % 4] as usize] - at).length()
        })
        .fold(f64::INFINITY, f64::min);
    compass_search_from(mesh, ns, 0.25 * h, start, score, better, steps)
}

/// `compass_search_together` from a first step of `first_step` (where
/// the shortest edge at the nodes is no measure of how far they must
/// go: an edge closing as a fold unfolds).
pub(crate) fn compass_search_from<S: Copy>(
    mesh: &mut Mesh,
    ns: &[usize],
    first_step: f64,
    start: S,
    mut score: impl FnMut(&Mesh, S) -> Option<S>,
    better: impl Fn(S, S) -> bool,
    steps: usize,
) -> DVec2 {
    let olds: Vec<DVec2> = ns.iter().map(|&n| mesh.nodes[n]).collect();
    let (first, old) = (ns[0], olds[0]);
    let mut best = (start, old);
    let mut step = first_step;
    for _ in 0..steps {
        let centre = best.1;
        for dir in COMPASS {
            mesh.nodes[first] = centre + dir * step;
            let shift = mesh.nodes[first] - old;
            for (&n, &o) in ns.iter().zip(&olds).skip(1) {
                mesh.nodes[n] = o + shift;
            }
            if let Some(w) = score(mesh, best.0) {
                if better(w, best.0) {
                    best = (w, mesh.nodes[first]);
                }
            }
        }
        step *= 0.5;
    }
    for (&n, &o) in ns.iter().zip(&olds) {
        mesh.nodes[n] = o;
    }
    best.1
}
