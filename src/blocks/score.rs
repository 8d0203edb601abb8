//! How near a mesh is to the bounds, to choose among the meshes tried
//! (blocks, free, retries): the elements out of bounds, weighed by how
//! far, then the irregular interior nodes; and whether blocks within the
//! bounds have so many elements that the free mesh is made too.

use crate::input::domain::Domain;
use crate::pipeline::MeshResult;

/// The sharpest corner (deg) of the domain at a vertex of its input, as
/// the elements round that vertex in `mesh` add up (360 inside).
pub(super) fn sharpest_input_corner(mesh: &crate::mesh::Mesh, domain: &Domain) -> f64 {
    input_corner_angles(mesh, domain)
        .iter()
        .map(|a| a.1)
        .fold(360.0, f64::min)
}

/// The mesh's nodes at a vertex of the input, in order, each with the
/// domain's corner there (deg) as the elements round it add up.
fn input_corner_angles(mesh: &crate::mesh::Mesh, domain: &Domain) -> Vec<(u32, f64)> {
    let at_vertex = input_vertices(domain);
    let mut at: Vec<(u32, f64)> = Vec::new();
    for (q, quad) in mesh.quads.iter().enumerate() {
        let p = mesh.quad_points(q);
        let angles = crate::geometry::quad_angles(p);
        for k in 0..4 {
            if mesh.kinds[quad[k] as usize] == crate::mesh::NodeKind::Boundary && at_vertex(p[k]) {
                at.push((quad[k], angles[k]));
            }
        }
    }
    at.sort_by_key(|a| a.0);
    at.chunk_by(|a, b| a.0 == b.0)
        .map(|c| (c[0].0, c.iter().map(|a| a.1).sum::<f64>()))
        .collect()
}

/// The corners at the loops' vertices as the curves' tangents make
/// them, not the chords (an arc bulging out of the domain makes the
/// chords' corner sharper): the judge's measure. Elsewhere (a line's
/// vertex) as the elements add up.
fn as_the_curves_make_them(
    mut at: Vec<(u32, f64)>,
    mesh: &crate::mesh::Mesh,
    domain: &Domain,
) -> Vec<(u32, f64)> {
    let corner_at = by_position(
        crate::input::arc_corners::loop_corners(domain),
        1e-9 * domain.scale(),
    );
    for (node, angle) in &mut at {
        if let Some(c) = corner_at(mesh.nodes[*node as usize]) {
            *angle = c;
        }
    }
    at
}

/// Whether a point is at a vertex of the input (within a billionth of
/// the domain's scale).
fn input_vertices(domain: &Domain) -> impl Fn(glam::DVec2) -> bool {
    let vertices = domain
        .chains()
        .flat_map(crate::input::curves::chain_vertices)
        .map(|v| (v, ()))
        .collect();
    let at = by_position(vertices, 1e-9 * domain.scale());
    move |p: glam::DVec2| at(p).is_some()
}

/// What is told of the point within `tol` of a point, if one is: the
/// points sorted by x, so a point looks at those of about its x only.
fn by_position<T: Copy>(
    mut items: Vec<(glam::DVec2, T)>,
    tol: f64,
) -> impl Fn(glam::DVec2) -> Option<T> {
    items.sort_by(|a, b| a.0.x.total_cmp(&b.0.x));
    move |p: glam::DVec2| {
        let from = items.partition_point(|(v, _)| v.x < p.x - tol);
        items[from..]
            .iter()
            .take_while(|(v, _)| v.x <= p.x + tol)
            .find(|(v, _)| (*v - p).length() <= tol)
            .map(|&(_, t)| t)
    }
}

/// How far a mesh is from the bounds, then its irregular interior nodes:
/// less is better. `weight` orders first: each element with a corner
/// outside the window counts once, and once more for every
/// `bound(out_of_bounds_step, D)` degrees its worst corner lies outside
/// (one element at 2 degrees is worse than four at 42); one more for each
/// of aspect, taper and size jump above its bound. `outside` is the
/// plain count the trace reports. A corner within
/// `bound(corner_slack, D)` degrees outside the window counts as within
/// it; the elements with one are `slacked`, the last tie-break.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub(super) struct Score {
    pub(super) weight: usize,
    pub(super) outside: usize,
    pub(super) irregular: usize,
    pub(super) slacked: usize,
}

impl Score {
    pub(super) fn of(
        r: &MeshResult,
        settings: &crate::settings::Settings,
        domain: &Domain,
    ) -> Score {
        let (q, bounds) = (&r.quality, &settings.element);
        let over = |x: f64, bound: f64| usize::from(x > bound);
        let at_input =
            as_the_curves_make_them(input_corner_angles(&r.mesh, domain), &r.mesh, domain);
        // an element at a tip too sharp for any to meet the taper bound
        // is as near as one can be: only the others' shapes count
        let (aspect, taper) = if q.max_aspect > bounds.max_aspect || q.max_taper > bounds.max_taper
        {
            shapes_but_at_sharp_tips(&r.mesh, &at_input, settings.host.retry_sharpest_corner)
        } else {
            (q.max_aspect, q.max_taper)
        };
        let overs = over(aspect, bounds.max_aspect)
            + over(taper, bounds.max_taper)
            + over(q.max_size_jump, bounds.max_size_jump);
        let c = corners_outside(&r.mesh, bounds, &at_input, &settings.host);
        Score {
            weight: c.weight + overs,
            outside: c.outside + overs,
            irregular: irregular_nodes(&r.mesh),
            slacked: c.slacked,
        }
    }

    /// The trace's words: elements out of bounds, the weight where it
    /// differs, irregular nodes.
    pub(super) fn words(&self) -> String {
        let weighed = if self.weight > self.outside {
            format!(" (weighing {} by bound(out_of_bounds_step))", self.weight)
        } else {
            String::new()
        };
        let slacked = if self.slacked > 0 {
            format!(
                " ({} with a corner just outside the window, within bound(corner_slack))",
                self.slacked
            )
        } else {
            String::new()
        };
        format!(
            "{} elements out of bounds{weighed}{slacked}, {} irregular nodes",
            self.outside, self.irregular
        )
    }
}

/// Elements with a corner outside the bounds' window, but for a corner
/// at a vertex of the input sharper than the window that the element
/// takes whole, within the input's corner as the curves make it (it
/// cannot do better than that; an input
/// corner of 83 deg split into two of 41.5 is outside, as the judge has
/// it); and their weight, each one plus a step for every `step` degrees
/// its worst corner lies outside the window; and the elements with a
/// corner outside the window by no more than the slack (counted within).
fn corners_outside(
    mesh: &crate::mesh::Mesh,
    bounds: &crate::settings::ElementBounds,
    at_input: &[(u32, f64)],
    host: &crate::settings::HostBounds,
) -> Corners {
    let (step, slack) = (host.out_of_bounds_step, host.corner_slack);
    let mut c = Corners::default();
    for q in 0..mesh.quads.len() {
        let quad = mesh.quads[q];
        let angles = crate::geometry::quad_angles(mesh.quad_points(q));
        let (mut worst, mut slacked): (Option<f64>, bool) = (None, false);
        for k in 0..4 {
            // the lower of the window's corner and the input's there
            let tip = at_input
                .binary_search_by_key(&quad[k], |a| a.0)
                .map_or(bounds.lower_corner, |i| {
                    at_input[i].1.min(bounds.lower_corner)
                });
            let by = if angles[k] > bounds.upper_corner + 1e-9 {
                angles[k] - bounds.upper_corner
            } else if angles[k] < tip - 1e-6 {
                tip - angles[k]
            } else {
                continue;
            };
            if by <= slack + 1e-9 {
                slacked = true;
                continue;
            }
            worst = Some(worst.map_or(by, |w: f64| w.max(by)));
        }
        if let Some(by) = worst {
            c.outside += 1;
            c.weight += 1 + if step > 0.0 { (by / step) as usize } else { 0 };
        } else if slacked {
            c.slacked += 1;
        }
    }
    c
}

/// The largest aspect ratio and taper among the elements with no corner
/// at an input corner sharper than `sharp` degrees (`at_input`: the
/// nodes at the input's vertices, sorted, with their corners): at such a
/// tip no element meets the taper bound (`bound(retry_sharpest_corner,
/// D)`), so the one there is as near as any would be.
fn shapes_but_at_sharp_tips(
    mesh: &crate::mesh::Mesh,
    at_input: &[(u32, f64)],
    sharp: f64,
) -> (f64, f64) {
    let at_sharp_tip = |node: u32| {
        at_input
            .binary_search_by_key(&node, |a| a.0)
            .is_ok_and(|i| at_input[i].1 < sharp)
    };
    (0..mesh.quads.len())
        .filter(|&q| !mesh.quads[q].iter().any(|&n| at_sharp_tip(n)))
        .map(|q| crate::element_quality::aspect_taper(mesh.quad_points(q)))
        .fold((1.0, 1.0), |(a, t), (qa, qt)| (a.max(qa), t.max(qt)))
}

/// What `corners_outside` counts.
#[derive(Debug, Default, PartialEq)]
struct Corners {
    outside: usize,
    weight: usize,
    slacked: usize,
}

/// Interior nodes (on no boundary edge) where other than four elements
/// meet.
pub fn irregular_nodes(mesh: &crate::mesh::Mesh) -> usize {
    let n = mesh.nodes.len();
    let mut on_boundary = vec![false; n];
    let mut edges: Vec<(u32, u32)> = Vec::with_capacity(4 * mesh.quads.len());
    for q in &mesh.quads {
        for k in 0..4 {
            let (a, b) = (q[k], q[(k + 1) % 4]);
            edges.push((a.min(b), a.max(b)));
        }
    }
    edges.sort_unstable();
    let mut valence = vec![0usize; n];
    let mut i = 0;
    while i < edges.len() {
        let mut j = i + 1;
        while j < edges.len() && edges[j] == edges[i] {
            j += 1;
        }
        let (a, b) = edges[i];
        valence[a as usize] += 1;
        valence[b as usize] += 1;
        if j - i == 1 {
            on_boundary[a as usize] = true;
            on_boundary[b as usize] = true;
        }
        i = j;
    }
    (0..n)
        .filter(|&v| valence[v] > 0 && !on_boundary[v] && valence[v] != 4)
        .count()
}

/// Where blocks within the bounds have more than `bound(blocks_over_free,
/// K)` times the elements the boundary's segment lengths ask for, the
/// trace's words for it (the free mesh is then made too); None: the
/// blocks are kept as they are.
pub(super) fn blocks_over_free_words(
    blocks: &MeshResult,
    prepared: &crate::pipeline::PreparedRun,
    settings: &crate::settings::Settings,
) -> Option<String> {
    let over = settings.host.blocks_over_free;
    let asks = prepared.elements_the_boundary_asks();
    let count = blocks.mesh.quads.len();
    (over > 0.0 && count as f64 > over * asks).then(|| {
        format!(
            "blocks: {count} elements, over bound(blocks_over_free, {over}) times the {asks:.0} the boundary's segment lengths ask for: meshed free too"
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{Mesh, NodeKind};
    use glam::DVec2;

    /// `corners_outside` with the built-in element bounds and the given
    /// step and slack, on a domain away from the elements (no corner of
    /// theirs at a vertex of it).
    fn counted(m: &Mesh, step: f64, slack: f64) -> Corners {
        let domain = Domain::from_json_str(
            r#"{"size": 1, "outer": {"points": [[-9, -9], [-8, -9], [-8, -8]]}}"#,
        )
        .unwrap();
        let host = crate::settings::HostBounds {
            out_of_bounds_step: step,
            corner_slack: slack,
            ..Default::default()
        };
        let at_input = as_the_curves_make_them(input_corner_angles(m, &domain), m, &domain);
        corners_outside(
            m,
            &crate::settings::ElementBounds::default(),
            &at_input,
            &host,
        )
    }

    /// `n` unit rhombi side by side, each with corners of `deg` and
    /// 180 - `deg`.
    fn rhombi(n: usize, deg: f64) -> Mesh {
        let mut m = Mesh::default();
        let (c, s) = (deg.to_radians().cos(), deg.to_radians().sin());
        for k in 0..n {
            let x = 3.0 * k as f64;
            let base = m.nodes.len() as u32;
            for p in [[x, 0.0], [x + 1.0, 0.0], [x + 1.0 + c, s], [x + c, s]] {
                m.add_node(DVec2::new(p[0], p[1]), NodeKind::Interior);
            }
            m.quads.push([base, base + 1, base + 2, base + 3]);
        }
        m
    }

    /// Each element out of the window counts once, and once more a step
    /// of degrees past it: one element at 2 deg weighs more than four at
    /// 44, so the mesh kept where all fall short is the nearer one.
    #[test]
    fn an_element_far_outside_the_window_weighs_more_than_several_just_outside() {
        let out = |m: &Mesh, step: f64| {
            let c = counted(m, step, 0.0);
            (c.outside, c.weight)
        };
        assert_eq!(out(&rhombi(1, 60.0), 5.0), (0, 0));
        assert_eq!(out(&rhombi(4, 44.0), 5.0), (4, 4));
        // 28 deg past: 5 steps more
        assert_eq!(out(&rhombi(1, 17.0), 5.0), (1, 6));
        // 43 deg past
        assert_eq!(out(&rhombi(1, 2.0), 5.0), (1, 9));
        // a step of 0 counts each element once
        assert_eq!(out(&rhombi(1, 2.0), 0.0), (1, 1));
    }

    /// An element at an input tip sharper than
    /// `bound(retry_sharpest_corner, D)` cannot meet the taper bound: its
    /// shape is left out of the mesh's, so a mesh whose only element past
    /// the bounds is that one counts as within them (no further mesh is
    /// tried for it); at a blunter tip it counts.
    #[test]
    fn the_element_at_a_tip_too_sharp_for_the_taper_bound_is_left_out() {
        let mut m = rhombi(1, 80.0);
        // a kite at node 4 with a 5 deg corner there: sides 1 and 0.09
        let (half, long) = (2.5f64.to_radians(), 1.0);
        let tip = DVec2::new(10.0, 0.0);
        let a = tip + long * DVec2::new(half.cos(), -half.sin());
        let b = tip + long * DVec2::new(half.cos(), half.sin());
        let c = tip + DVec2::new(long * half.cos() + 0.06, 0.0);
        let base = m.nodes.len() as u32;
        for p in [tip, a, c, b] {
            m.add_node(p, NodeKind::Boundary);
        }
        m.quads.push([base, base + 1, base + 2, base + 3]);
        let kite = crate::element_quality::aspect_taper(m.quad_points(1));
        assert!(kite.1 > 10.0, "{kite:?}");
        let rhombus = crate::element_quality::aspect_taper(m.quad_points(0));
        assert_eq!(shapes_but_at_sharp_tips(&m, &[(base, 5.0)], 8.1), rhombus);
        let blunt = shapes_but_at_sharp_tips(&m, &[(base, 12.0)], 8.1);
        assert_eq!(blunt.1, kite.1.max(rhombus.1));
    }

    /// A corner within `bound(corner_slack, D)` degrees outside the
    /// window counts as within it (the judge's tolerance); one further
    /// out is counted, its weight from the window itself.
    #[test]
    fn a_corner_within_the_slack_counts_as_within_the_window() {
        let out = |m: &Mesh, slack: f64| {
            let c = counted(m, 5.0, slack);
            (c.outside, c.weight, c.slacked)
        };
        assert_eq!(out(&rhombi(2, 44.7), 0.0), (2, 2, 0));
        assert_eq!(out(&rhombi(2, 44.7), 0.5), (0, 0, 2));
        assert_eq!(out(&rhombi(2, 44.0), 0.5), (2, 2, 0));
        // 29 deg past the window: 5 steps more, the slack not taken off
        assert_eq!(out(&rhombi(1, 16.0), 0.5), (1, 6, 0));
    }
}
