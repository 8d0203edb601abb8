//! Tests of the DXF reader.

use super::entities::*;
use super::joining::*;
use super::*;
use glam::DVec2;
use std::f64::consts::PI;

fn line(a: [f64; 2], b: [f64; 2], layer: &str) -> DrawnEdge {
    DrawnEdge {
        a: DVec2::from(a),
        b: DVec2::from(b),
        bulge: 0.0,
        layer: layer.into(),
        typed: true,
    }
}

#[test]
fn four_lines_in_any_order_and_direction_and_a_copy_make_one_counter_clockwise_loop() {
    let edges = [
        line([10.0, 5.0], [10.0, 0.0], "right"),
        line([0.0, 0.0], [10.0, 0.0], "bottom"),
        line([0.0, 5.0], [0.0, 0.0], ""),
        line([0.0, 5.0], [10.0, 5.0], "top"),
    ];
    let mut edges = edges.to_vec();
    // the bottom drawn again, the other way
    edges.push(line([10.0, 0.0], [0.0, 0.0], "bottom"));
    let o = outline_of(&edges, &[], "t.dxf").unwrap();
    assert_eq!(
        o.outer,
        Loop::Polyline(Polyline {
            points: vec![[0.0, 0.0], [10.0, 0.0], [10.0, 5.0], [0.0, 5.0]],
            bulges: None,
            tags: Some(vec![
                "bottom".into(),
                "right".into(),
                "top".into(),
                "".into()
            ]),
        })
    );
    assert!(o.holes.is_empty() && o.lines.is_empty());
}

#[test]
fn end_points_within_the_tolerance_join_and_a_typed_point_wins() {
    let mut arc = line([10.0 + 1e-7, 0.0], [10.0, 5.0], "");
    arc.typed = false;
    arc.bulge = 0.1;
    let edges = [
        line([0.0, 0.0], [10.0, 0.0], ""),
        arc,
        line([10.0, 5.0], [0.0, 0.0], ""),
    ];
    let o = outline_of(&edges, &[], "t.dxf").unwrap();
    let Loop::Polyline(p) = &o.outer else {
        panic!()
    };
    assert_eq!(p.points, vec![[0.0, 0.0], [10.0, 0.0], [10.0, 5.0]]);
    assert_eq!(p.bulges, Some(vec![0.0, 0.1, 0.0]));
}

#[test]
fn an_outline_with_a_gap_names_the_gap() {
    let edges = [
        line([0.0, 0.0], [10.0, 0.0], ""),
        line([10.0, 0.0], [10.0, 5.0], ""),
        line([10.0, 5.0], [0.0, 5.0], ""),
        line([0.0, 5.0], [0.0, 0.01], ""),
    ];
    let e = outline_of(&edges, &[], "t.dxf").unwrap_err().to_string();
    assert!(
        e.starts_with("t.dxf: the outline does not close: a gap between (0, 0) and (0, 0.01), 1.000000e-2 apart"),
        "{e}"
    );
}

#[test]
fn a_circle_inside_is_a_hole_and_a_hanging_chain_a_line() {
    let edges = [
        line([0.0, 0.0], [10.0, 0.0], ""),
        line([10.0, 0.0], [10.0, 5.0], ""),
        line([10.0, 5.0], [0.0, 5.0], ""),
        line([0.0, 5.0], [0.0, 0.0], ""),
        // an edge crack from the bottom edge's corner inward, in two
        line([0.0, 0.0], [1.0, 1.0], "crack"),
        line([1.0, 1.0], [2.0, 1.0], "crack"),
    ];
    let circles = [DrawnCircle {
        center: DVec2::new(6.0, 2.5),
        radius: 1.0,
        layer: "bore".into(),
    }];
    let o = outline_of(&edges, &circles, "t.dxf").unwrap();
    assert_eq!(o.holes.len(), 1);
    assert!(
        matches!(&o.holes[0], Loop::Circle { circle } if circle.tag.as_deref() == Some("bore"))
    );
    assert_eq!(o.lines.len(), 1);
    assert_eq!(o.lines[0].points, vec![[0.0, 0.0], [1.0, 1.0], [2.0, 1.0]]);
}

#[test]
fn a_line_across_the_loop_is_a_line_and_a_loop_joined_by_a_line_a_hole() {
    let edges = [
        line([0.0, 0.0], [10.0, 0.0], ""),
        line([10.0, 0.0], [10.0, 5.0], ""),
        line([10.0, 5.0], [0.0, 5.0], ""),
        line([0.0, 5.0], [0.0, 0.0], ""),
        // a partition from the bottom to the top
        line([4.0, 0.0], [4.0, 5.0], "interface"),
        // a square hole joined to the right side by a line
        line([6.0, 2.0], [8.0, 2.0], ""),
        line([8.0, 2.0], [8.0, 3.0], ""),
        line([8.0, 3.0], [6.0, 3.0], ""),
        line([6.0, 3.0], [6.0, 2.0], ""),
        line([8.0, 2.0], [10.0, 2.0], "tie"),
    ];
    // the bottom and top edges are split where the partition meets them
    let mut edges = edges.to_vec();
    edges[0] = line([0.0, 0.0], [4.0, 0.0], "");
    edges.push(line([4.0, 0.0], [10.0, 0.0], ""));
    edges[2] = line([10.0, 5.0], [4.0, 5.0], "");
    edges.push(line([4.0, 5.0], [0.0, 5.0], ""));
    edges[1] = line([10.0, 0.0], [10.0, 2.0], "");
    edges.push(line([10.0, 2.0], [10.0, 5.0], ""));
    let o = outline_of(&edges, &[], "t.dxf").unwrap();
    let Loop::Polyline(outer) = &o.outer else {
        panic!()
    };
    assert_eq!(outer.points.len(), 7);
    assert_eq!(o.holes.len(), 1);
    let Loop::Polyline(hole) = &o.holes[0] else {
        panic!()
    };
    assert_eq!(
        hole.points,
        vec![[6.0, 2.0], [6.0, 3.0], [8.0, 3.0], [8.0, 2.0]]
    );
    let mut lines: Vec<_> = o.lines.iter().map(|l| l.points.clone()).collect();
    lines.sort_by(|a, b| a[0][0].total_cmp(&b[0][0]));
    assert_eq!(
        lines,
        vec![vec![[4.0, 0.0], [4.0, 5.0]], vec![[8.0, 2.0], [10.0, 2.0]]]
    );
}

#[test]
fn an_arc_seen_from_below_is_mirrored_and_turns_the_other_way() {
    use ::dxf::entities::{Arc, Entity, EntityType};
    let mut drawing = ::dxf::Drawing::new();
    let mut arc = Arc::new(::dxf::Point::new(0.0, 0.0, 0.0), 1.0, 0.0, 90.0);
    arc.normal = ::dxf::Vector::new(0.0, 0.0, -1.0);
    drawing.add_entity(Entity::new(EntityType::Arc(arc)));
    let (edges, _, _) = drawn_geometry(&drawing, "t.dxf").unwrap();
    // from (-1, 0) clockwise (seen from above) to (0, 1)
    assert!((edges[0].a - DVec2::new(-1.0, 0.0)).length() < 1e-15);
    assert!((edges[0].b - DVec2::new(0.0, 1.0)).length() < 1e-15);
    assert!((edges[0].bulge + (PI / 8.0).tan()).abs() < 1e-15);
    assert!(!edges[0].typed);
}

#[test]
fn flat_arrays_go_on_one_line_and_strings_are_left_alone() {
    let v = serde_json::json!({"a": [[0.0, 1.5], [2.0, 3.0]], "t": ["x, [y]", "\"q\""]});
    let text = serde_json::to_string_pretty(&v).unwrap();
    assert_eq!(
        one_line_flat_arrays(&text),
        "{\n  \"a\": [\n    [0.0, 1.5],\n    [2.0, 3.0]\n  ],\n  \"t\": [\"x, [y]\", \"\\\"q\\\"\"]\n}"
    );
}

#[test]
fn a_drawing_of_points_only_has_no_loop() {
    let edges = [line([1.0, 1.0], [1.0, 1.0], "")];
    let e = outline_of(&edges, &[], "t.dxf").unwrap_err().to_string();
    assert_eq!(e, "t.dxf: no closed loop round the drawing");
}

#[test]
fn two_loops_side_by_side_are_refused() {
    let sq = |x: f64| {
        vec![
            line([x, 0.0], [x + 1.0, 0.0], ""),
            line([x + 1.0, 0.0], [x + 1.0, 1.0], ""),
            line([x + 1.0, 1.0], [x, 1.0], ""),
            line([x, 1.0], [x, 0.0], ""),
        ]
    };
    let mut edges = sq(0.0);
    edges.extend(sq(3.0));
    let e = outline_of(&edges, &[], "t.dxf").unwrap_err().to_string();
    assert!(e.contains("two outlines side by side"), "{e}");
}
