//! Tests of the smoothing stage and its sweeps.

use glam::DVec2;

use crate::element_quality::badness;
use crate::geometry::quad_angles;
use crate::mesh::{Mesh, NodeKind};
use crate::settings::ElementBounds;
use crate::smoothing::laplace::*;
use crate::smoothing::sizes::*;
use crate::smoothing::stage::*;
use crate::smoothing::strips::*;
use crate::smoothing::untangle::*;

/// `passes` sweeps of guarded Laplace smoothing; returns how many moves
/// were kept in the last sweep.
fn laplace(mesh: &mut Mesh, passes: usize) -> usize {
    sweep_in_strips(mesh, node_elements(mesh), |mesh, nodes, dirty| {
        laplace_sweeps(mesh, passes, nodes, dirty, &ElementBounds::default(), None)
    })
}

/// Moves each free node next to an element with a corner outside
/// [45, 135] to the place, found by a compass search, where the worst
/// corner round it is best; `passes` sweeps. Never makes an element worse
/// than it was, never inverts one. Returns the moves kept.
fn untangle_angles(mesh: &mut Mesh, passes: usize) -> usize {
    sweep_in_strips(mesh, node_elements(mesh), |mesh, nodes, dirty| {
        untangle_sweeps(mesh, passes, nodes, dirty, &ElementBounds::default())
    })
}

/// Evens out sizes and shapes where they break the paper's bounds: each
/// free node round an element past them moves, by a compass search, to
/// where the worst excess round it is least, without a corner round it
/// leaving [45, 135] further or getting much sharper than it was. Where
/// that leaves an element past a bound, the node moves together with a
/// neighbour (a corner at the window's edge can hold one node, not the
/// edge between two). `passes` sweeps; returns the moves kept.
fn even_out_sizes(mesh: &mut Mesh, passes: usize) -> usize {
    let around = node_elements(mesh);
    let neighbours = element_neighbours(mesh, &around);
    sweep_in_strips(mesh, around, |mesh, nodes, dirty| {
        even_out_sweeps(
            mesh,
            passes,
            nodes,
            &neighbours,
            dirty,
            &ElementBounds::default(),
        )
    })
}

/// Four unit squares round one free centre node (id 4).
fn two_by_two_block() -> Mesh {
    let mut m = Mesh::default();
    for y in 0..3 {
        for x in 0..3 {
            let kind = if x == 1 && y == 1 {
                NodeKind::Interior
            } else {
                NodeKind::Boundary
            };
            m.add_node(DVec2::new(x as f64, y as f64), kind);
        }
    }
    m.quads = vec![[0, 1, 4, 3], [1, 2, 5, 4], [3, 4, 7, 6], [4, 5, 8, 7]];
    m
}

/// The centre node pushed towards a corner until the element there has a
/// corner of 169 degrees: easing brings it back into the window.
#[test]
fn a_corner_past_the_window_is_eased_back_into_it() {
    let mut m = two_by_two_block();
    m.nodes[4] = DVec2::new(1.45, 1.45);
    let bounds = ElementBounds::default();
    let worst = |m: &Mesh| {
        (0..m.quads.len())
            .map(|q| crate::element_quality::badness_of(m, q, &bounds))
            .fold(0.0, f64::max)
    };
    assert!(worst(&m) > 0.0);
    assert!(crate::smoothing::ease_bad_corners(&mut m, &bounds).0 > 0);
    assert_eq!(worst(&m), 0.0);
}

/// Two elements in a strip of height 0.5, every node on the input
/// boundary; the bottom's middle node (1) pushed to x = 0.3 leaves a
/// corner of 35.5 degrees. `vertices` are the nodes that are input
/// vertices.
fn strip_with_a_pushed_bottom_node(vertices: &[u32]) -> Mesh {
    let mut m = Mesh::default();
    for p in [
        (0.0, 0.0),
        (0.3, 0.0),
        (2.0, 0.0),
        (0.0, 0.5),
        (1.0, 0.5),
        (2.0, 0.5),
    ] {
        m.add_node(DVec2::new(p.0, p.1), NodeKind::Boundary);
    }
    m.quads = vec![[0, 1, 4, 3], [1, 2, 5, 4]];
    for (a, b) in [(0, 1), (1, 2), (2, 5), (5, 4), (4, 3), (3, 0)] {
        m.boundary.push(crate::mesh::BoundaryEdge {
            a,
            b,
            group: 0,
            tag: None,
        });
    }
    let mut at: Vec<[u64; 2]> = vertices
        .iter()
        .map(|&n| {
            let p = m.nodes[n as usize];
            [p.x.to_bits(), p.y.to_bits()]
        })
        .collect();
    at.sort_unstable();
    m.input_vertices = Some(at);
    m
}

/// A boundary node inside a straight input edge slides along it until
/// the corners round it are in the window; it stays on the edge.
#[test]
fn a_boundary_node_slides_along_its_edge_to_ease_a_corner() {
    let mut m = strip_with_a_pushed_bottom_node(&[0, 2, 3, 5]);
    let bounds = ElementBounds::default();
    assert!(crate::element_quality::badness_of(&m, 1, &bounds) > 0.0);
    let (moved, slid) = crate::smoothing::ease_bad_corners(&mut m, &bounds);
    assert!(slid > 0 && moved >= slid, "{moved} moves, {slid} slides");
    assert_eq!(m.nodes[1].y, 0.0, "the node left its edge");
    assert!(m.nodes[1].x > 0.4 && m.nodes[1].x < 1.6, "{}", m.nodes[1]);
    for q in 0..2 {
        assert_eq!(crate::element_quality::badness_of(&m, q, &bounds), 0.0);
    }
}

/// A boundary node inside an input arc slides along the arc's circle:
/// the strip's bottom is an arc through (0, 0) and (2, 0) centred at
/// (1, 5), its middle node pushed to x = 0.3 on it.
#[test]
fn a_boundary_node_slides_along_its_arc_to_ease_a_corner() {
    let mut m = strip_with_a_pushed_bottom_node(&[0, 2, 3, 5]);
    let (centre, r) = (DVec2::new(1.0, 5.0), 26f64.sqrt());
    m.nodes[1] = DVec2::new(0.3, 5.0 - (r * r - 0.49).sqrt());
    let bounds = ElementBounds::default();
    assert!(crate::element_quality::badness_of(&m, 1, &bounds) > 0.0);
    let (moved, slid) = crate::smoothing::ease_bad_corners(&mut m, &bounds);
    assert!(slid > 0 && moved >= slid, "{moved} moves, {slid} slides");
    let off = ((m.nodes[1] - centre).length() - r).abs();
    assert!(off < 1e-12, "the node left its arc by {off}");
    assert!(m.nodes[1].x > 0.4 && m.nodes[1].x < 1.6, "{}", m.nodes[1]);
    for q in 0..2 {
        assert_eq!(crate::element_quality::badness_of(&m, q, &bounds), 0.0);
    }
}

/// A size jump two boundary nodes hold between them (the strip's middle
/// nodes, bottom and top, both pushed to x = 0.3: elements 0.3 and 1.7
/// wide, a jump of 2.38; one moved alone turns the corners past the
/// window): the polish slides both along their edges together, each stays
/// on its edge between its neighbours; with `bound(boundary_slide, 0)`
/// they stay where they are.
#[test]
fn the_polish_slides_boundary_nodes_along_their_edges_together() {
    let pushed = || {
        let mut m = strip_with_a_pushed_bottom_node(&[0, 2, 3, 5]);
        m.nodes[4] = DVec2::new(0.3, 0.5);
        m
    };
    let jump = |m: &Mesh| {
        let (a, b) = (
            crate::element_quality::quad_area(m, 0),
            crate::element_quality::quad_area(m, 1),
        );
        (a / b).max(b / a).sqrt()
    };
    let bounds = ElementBounds::default();
    let mut m = pushed();
    assert!(jump(&m) > 2.3, "{}", jump(&m));
    assert_eq!(crate::smoothing::polish_past_bounds(&mut m, &bounds), 1);
    assert!(jump(&m) <= 2.0, "a jump of {}", jump(&m));
    assert_eq!((m.nodes[1].y, m.nodes[4].y), (0.0, 0.5), "left their edges");
    for n in [1, 4] {
        assert!(m.nodes[n].x > 0.3 && m.nodes[n].x < 1.6, "{}", m.nodes[n]);
    }
    for q in 0..2 {
        assert_eq!(crate::element_quality::badness_of(&m, q, &bounds), 0.0);
    }
    let mut stays = pushed();
    let no_slide = bounds.with_boundary_slide(0.0).unwrap();
    crate::smoothing::polish_past_bounds(&mut stays, &no_slide);
    assert_eq!(stays.nodes, pushed().nodes);
}

/// An input vertex stays where it is, even where its edges run on in one
/// line (a vertex that splits a side for its segment counts or tags).
#[test]
fn an_input_vertex_on_a_straight_side_never_slides() {
    let mut m = strip_with_a_pushed_bottom_node(&[0, 1, 2, 3, 5]);
    crate::smoothing::ease_bad_corners(&mut m, &ElementBounds::default());
    assert_eq!(m.nodes[1], DVec2::new(0.3, 0.0));
    // a mesh that does not know its input's vertices moves none either
    let mut m = strip_with_a_pushed_bottom_node(&[]);
    m.input_vertices = None;
    crate::smoothing::ease_bad_corners(&mut m, &ElementBounds::default());
    assert_eq!(m.nodes[1], DVec2::new(0.3, 0.0));
}

#[test]
fn centre_node_of_a_two_by_two_block_moves_to_the_middle() {
    let mut m = two_by_two_block();
    m.nodes[4] = DVec2::new(1.3, 0.8);
    laplace(&mut m, 20);
    assert!((m.nodes[4] - DVec2::new(1.0, 1.0)).length() < 1e-6);
}

#[test]
fn compass_search_repairs_a_pinched_corner() {
    let mut m = two_by_two_block();
    m.nodes[4] = DVec2::new(0.6, 0.6); // a corner of 157 deg at the centre
    assert!(untangle_angles(&mut m, 5) > 0);
    let worst = (0..4)
        .flat_map(|q| quad_angles(m.quad_points(q)))
        .fold(0.0, f64::max);
    assert!(worst <= 135.0 + 1e-6, "worst corner {worst}");
}

#[test]
fn a_size_jump_past_two_is_evened_out() {
    let mut m = two_by_two_block();
    m.nodes[4] = DVec2::new(0.2, 0.2); // areas 0.2 and 1.8: a jump of 3
    let jump = |m: &Mesh| {
        let a: Vec<f64> = (0..4)
            .map(|q| crate::geometry::polygon_area(&m.quad_points(q)).abs())
            .collect();
        (a[3] / a[0]).sqrt()
    };
    let worst_corner = |m: &Mesh| {
        (0..4)
            .map(|q| badness(m.quad_points(q), &ElementBounds::default()))
            .fold(0.0, f64::max)
    };
    let corner_before = worst_corner(&m);
    assert!(jump(&m) > 2.5);
    assert!(even_out_sizes(&mut m, 5) > 0);
    assert!(jump(&m) <= 2.0 * 0.95 + 1e-9, "jump {}", jump(&m));
    assert!(worst_corner(&m) <= corner_before + 1e-9);
}

/// A grid of n x n unit squares, its inner nodes pushed off the grid
/// by up to `push` (a fixed pseudo-random sequence).
pub(crate) fn pushed_grid(n: usize, push: f64) -> (Mesh, Vec<DVec2>) {
    let mut m = Mesh::default();
    let mut seed: u64 = 12345;
    let mut next = || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    };
    let mut grid = Vec::new();
    for y in 0..=n {
        for x in 0..=n {
            let p = DVec2::new(x as f64, y as f64);
            grid.push(p);
            let inner = x > 0 && y > 0 && x < n && y < n;
            let kind = if inner {
                NodeKind::Interior
            } else {
                NodeKind::Boundary
            };
            let off = if inner {
                DVec2::new(next(), next()) * push
            } else {
                DVec2::ZERO
            };
            m.add_node(p + off, kind);
        }
    }
    let id = |x: usize, y: usize| (y * (n + 1) + x) as u32;
    for y in 0..n {
        for x in 0..n {
            m.quads
                .push([id(x, y), id(x + 1, y), id(x + 1, y + 1), id(x, y + 1)]);
        }
    }
    (m, grid)
}

#[test]
fn a_large_mesh_is_smoothed_in_strips_seams_included() {
    let (mut m, grid) = pushed_grid(150, 0.3);
    assert!(m.nodes.len() >= SPLIT_FROM_NODES);
    let off = |m: &Mesh, near_seam: bool| {
        let mid = 75.0;
        let (sum, count) = (0..m.nodes.len())
            .filter(|&i| m.kinds[i] == NodeKind::Interior)
            .filter(|&i| !near_seam || (grid[i].x - mid).abs() <= 2.0)
            .fold((0.0, 0), |(s, c), i| {
                (s + (m.nodes[i] - grid[i]).length(), c + 1)
            });
        sum / count as f64
    };
    let (before, before_seam) = (off(&m, false), off(&m, true));
    let mut again = m.clone();
    laplace(&mut m, 30);
    laplace(&mut again, 30);
    assert_eq!(m.nodes, again.nodes, "the same mesh every time");
    assert!(
        off(&m, false) < 0.3 * before,
        "{} of {before}",
        off(&m, false)
    );
    assert!(
        off(&m, true) < 0.3 * before_seam,
        "at the seam {} of {before_seam}",
        off(&m, true)
    );
    for (i, p) in m.nodes.iter().enumerate() {
        if m.kinds[i] == NodeKind::Boundary {
            assert_eq!(*p, grid[i]);
        }
    }
    assert!((0..m.quads.len())
        .all(|q| badness(m.quad_points(q), &ElementBounds::default()).is_finite()));
}

/// The largest size jump between neighbours (the square root of
/// their area ratio).
fn largest_jump(m: &Mesh) -> f64 {
    let around = node_elements(m);
    let area = |q: usize| crate::geometry::polygon_area(&m.quad_points(q)).abs();
    let mut jump: f64 = 1.0;
    for (q, nb) in element_neighbours(m, &around).iter().enumerate() {
        for &f in nb.iter().flatten() {
            jump = jump.max((area(q) / area(f as usize)).sqrt());
        }
    }
    jump
}

#[test]
fn a_size_jump_one_node_cannot_even_out_is_evened_out_by_two() {
    // a 4 x 4 grid graded hard in x and y, its inner nodes pushed: the
    // node between the two elements of the jump is held by a corner
    // at the window's edge (alone it gets the jump to 2.10 only)
    let (mut m, _) = pushed_grid(4, 0.0);
    for p in &mut m.nodes {
        *p = DVec2::new((p.x / 4.0).powi(3) * 4.0, (p.y / 4.0).powf(1.6) * 4.0);
    }
    let inner = [
        (6, 0.0333, 0.4637),
        (7, 0.3718, 0.2429),
        (8, 1.5747, 0.6143),
        (11, 0.2293, 1.0905),
        (12, 0.4863, 1.1262),
        (13, 1.8729, 1.2367),
        (16, 0.2734, 2.5611),
        (17, 0.5709, 2.5817),
        (18, 1.8180, 2.5270),
    ];
    for (i, x, y) in inner {
        assert_eq!(m.kinds[i], NodeKind::Interior);
        m.nodes[i] = DVec2::new(x, y);
    }
    let worst_corner = |m: &Mesh| {
        (0..m.quads.len())
            .map(|q| badness(m.quad_points(q), &ElementBounds::default()))
            .fold(0.0, f64::max)
    };
    let corner_before = worst_corner(&m);
    assert!(largest_jump(&m) > 2.4);
    assert!(even_out_sizes(&mut m, 10) > 0);
    assert!(largest_jump(&m) <= 2.0, "jump {}", largest_jump(&m));
    assert!(worst_corner(&m) <= corner_before + 1e-9);
}

#[test]
fn a_strip_comes_out_the_same_whichever_thread_sweeps_it() {
    // pushed hard, so that every sweep of the stage has work near the
    // seams; one thread sweeps the strips one after another, three
    // share them
    let (m, _) = pushed_grid(150, 0.45);
    let around = node_elements(&m);
    let neighbours = element_neighbours(&m, &around);
    let stage = |mesh: &mut Mesh, nodes: &Nodes, dirty: &mut [bool]| {
        all_sweeps(
            mesh,
            [5, 5],
            nodes,
            &neighbours,
            dirty,
            &ElementBounds::default(),
            None,
        )
    };
    let mut alone = m.clone();
    let mut shared = m.clone();
    let moved = sweep_in_strips_on(&mut alone, around.clone(), 1, stage);
    assert!(moved > 0);
    sweep_in_strips_on(&mut shared, around, 3, stage);
    assert_eq!(alone.nodes, shared.nodes);
}

#[test]
fn bands_far_enough_apart_come_out_as_swept_together() {
    // pushed hard, so that every sweep of the stage has work; columns
    // of a 60 x 60 grid marked, nine steps apart (apart) or eight (one)
    let (m, _) = pushed_grid(60, 0.45);
    let around = node_elements(&m);
    let neighbours = element_neighbours(&m, &around);
    let stage = |mesh: &mut Mesh, nodes: &Nodes, dirty: &mut [bool]| {
        all_sweeps(
            mesh,
            [5, 5],
            nodes,
            &neighbours,
            dirty,
            &ElementBounds::default(),
            None,
        )
    };
    let columns = |a: usize, b: usize| -> Vec<bool> {
        (0..m.nodes.len())
            .map(|i| (a..a + 5).contains(&(i % 61)) || (b..b + 5).contains(&(i % 61)))
            .collect()
    };
    assert_eq!(
        apart_groups(&m, &around, &columns(8, 20), BANDS_APART).len(),
        1
    );
    let marked = columns(8, 21);
    let groups = apart_groups(&m, &around, &marked, BANDS_APART);
    assert_eq!(groups.len(), 2);
    let all_dirty = vec![true; m.nodes.len()];
    let mut apart = m.clone();
    sweep_groups(&mut apart, &around, &groups, &all_dirty, 2, &stage);
    let mut together = m.clone();
    let visit: Vec<u32> = (0..m.nodes.len() as u32)
        .filter(|&i| marked[i as usize])
        .collect();
    let moved = stage(
        &mut together,
        &Nodes {
            around: &around,
            visit: &visit,
        },
        &mut all_dirty.clone(),
    );
    assert!(moved > 0);
    assert_eq!(apart.nodes, together.nodes);
}

#[test]
fn boundary_nodes_never_move() {
    let mut m = Mesh::default();
    m.add_node(DVec2::ZERO, NodeKind::Boundary);
    m.add_node(DVec2::X, NodeKind::Boundary);
    m.add_node(DVec2::new(1.0, 1.0), NodeKind::Boundary);
    m.add_node(DVec2::new(0.2, 0.9), NodeKind::Boundary);
    m.quads = vec![[0, 1, 2, 3]];
    let before = m.nodes.clone();
    laplace(&mut m, 5);
    assert_eq!(m.nodes, before);
}

/// Columns of elements growing 1.3 times a column, as a graded run's
/// field (1 at the left edge, growing 0.3 a unit of distance) aims for:
/// plain Laplace pulls each inner node toward the coarse side, evening
/// the columns out; weighted by the field (`bound(weighted_laplace, 1)`)
/// the nodes stay near where the grading put them.
#[test]
fn laplace_weighted_by_the_size_field_keeps_the_grading() {
    let (cols, rows) = (7, 4);
    let mut xs = vec![0.0];
    for i in 0..cols {
        let x: f64 = xs[i];
        xs.push(x + 1.0 + 0.3 * x);
    }
    let graded = || {
        let mut m = Mesh::default();
        for y in 0..=rows {
            for (i, &x) in xs.iter().enumerate() {
                let inner = i > 0 && i < cols && y > 0 && y < rows;
                let kind = if inner {
                    NodeKind::Interior
                } else {
                    NodeKind::Boundary
                };
                m.add_node(DVec2::new(x, y as f64 * 2.0), kind);
            }
        }
        let id = |x: usize, y: usize| (y * (cols + 1) + x) as u32;
        for y in 0..rows {
            for x in 0..cols {
                m.quads
                    .push([id(x, y), id(x + 1, y), id(x + 1, y + 1), id(x, y + 1)]);
            }
        }
        m
    };
    // segments of length 1 up the left edge: h = 1 + 0.3 x
    let left: Vec<(DVec2, DVec2)> = (0..2 * rows)
        .map(|k| (DVec2::new(0.0, k as f64), DVec2::new(0.0, k as f64 + 1.0)))
        .collect();
    let field = crate::size_field::SizeField::new(left, 0.3, 100.0).unwrap();
    let moved = |weights: Option<&crate::size_field::SizeField>| {
        let mut m = graded();
        let start = m.nodes.clone();
        let around = node_elements(&m);
        sweep_in_strips(&mut m, around, |mesh, nodes, dirty| {
            laplace_sweeps(mesh, 20, nodes, dirty, &ElementBounds::default(), weights)
        });
        m.nodes
            .iter()
            .zip(&start)
            .map(|(a, b)| (*a - *b).length())
            .fold(0.0, f64::max)
    };
    let (plain, weighted) = (moved(None), moved(Some(&field)));
    assert!(plain > 0.3, "plain Laplace moved nodes by {plain}");
    assert!(
        weighted < plain / 100.0,
        "weighted {weighted} against plain {plain}"
    );
}
