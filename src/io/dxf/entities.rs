//! The entities of a drawing's model space as edges and circles.

use std::f64::consts::PI;

use glam::DVec2;

use super::{layer_tag, DrawnCircle, DrawnEdge, DxfError};

/// A drawing's edges, circles and warnings.
pub(super) type DrawnGeometry = (Vec<DrawnEdge>, Vec<DrawnCircle>, Vec<String>);

/// The edges and circles of a drawing's model space, and a warning for
/// each kind of entity skipped.
pub(super) fn drawn_geometry(
    drawing: &::dxf::Drawing,
    path: &str,
) -> Result<DrawnGeometry, DxfError> {
    use ::dxf::entities::EntityType;
    let mut edges = Vec::new();
    let mut circles = Vec::new();
    let mut skipped: std::collections::BTreeMap<String, usize> = Default::default();
    for (k, entity) in drawing.entities().enumerate() {
        let layer = layer_tag(&entity.common.layer);
        if entity.common.is_in_paper_space {
            *skipped.entry("in paper space".into()).or_default() += 1;
            continue;
        }
        // Entities drawn seen from below (extrusion 0,0,-1, as mirrored
        // parts often are) have their x axis reversed; any other plane is
        // not a plane outline.
        let plane = |normal: &::dxf::Vector, what: &str| -> Result<f64, DxfError> {
            if normal.x.abs() > 1e-9 || normal.y.abs() > 1e-9 || normal.z == 0.0 {
                return Err(DxfError::Entity {
                    path: path.to_string(),
                    message: format!(
                        "entity {k} ({what} on layer {:?}) is not in the XY plane (extrusion {}, {}, {})",
                        entity.common.layer, normal.x, normal.y, normal.z
                    ),
                });
            }
            Ok(normal.z.signum())
        };
        match &entity.specific {
            EntityType::Line(l) => {
                // a LINE's points are in world coordinates
                edges.push(DrawnEdge {
                    a: DVec2::new(l.p1.x, l.p1.y),
                    b: DVec2::new(l.p2.x, l.p2.y),
                    bulge: 0.0,
                    layer,
                    typed: true,
                });
            }
            EntityType::Arc(a) => {
                let s = plane(&a.normal, "ARC")?;
                let (t0, t1) = (a.start_angle.to_radians(), a.end_angle.to_radians());
                let mut sweep = (t1 - t0).rem_euclid(2.0 * PI);
                if sweep == 0.0 {
                    sweep = 2.0 * PI;
                }
                let c = DVec2::new(a.center.x, a.center.y);
                let at =
                    |t: f64| DVec2::new(s * (c.x + a.radius * t.cos()), c.y + a.radius * t.sin());
                if sweep >= 2.0 * PI - 1e-12 {
                    circles.push(DrawnCircle {
                        center: DVec2::new(s * c.x, c.y),
                        radius: a.radius,
                        layer,
                    });
                    continue;
                }
                edges.push(DrawnEdge {
                    a: at(t0),
                    b: at(t1),
                    bulge: s * (sweep / 4.0).tan(),
                    layer,
                    typed: false,
                });
            }
            EntityType::Circle(c) => {
                let s = plane(&c.normal, "CIRCLE")?;
                circles.push(DrawnCircle {
                    center: DVec2::new(s * c.center.x, c.center.y),
                    radius: c.radius,
                    layer,
                });
            }
            EntityType::LwPolyline(pl) => {
                let s = plane(&pl.extrusion_direction, "LWPOLYLINE")?;
                let pts: Vec<(DVec2, f64)> = pl
                    .vertices
                    .iter()
                    .map(|v| (DVec2::new(s * v.x, v.y), s * v.bulge))
                    .collect();
                polyline_edges(&pts, pl.is_closed(), &layer, &mut edges);
            }
            EntityType::Polyline(pl) => {
                let s = plane(&pl.normal, "POLYLINE")?;
                if pl.is_polyface_mesh() || pl.is_3d_polygon_mesh() {
                    *skipped.entry("POLYLINE mesh".into()).or_default() += 1;
                    continue;
                }
                let pts: Vec<(DVec2, f64)> = pl
                    .vertices()
                    .map(|v| (DVec2::new(s * v.location.x, v.location.y), s * v.bulge))
                    .collect();
                polyline_edges(&pts, pl.is_closed(), &layer, &mut edges);
            }
            other => {
                let kind = format!("{other:?}");
                let kind = kind
                    .split(|c: char| !c.is_alphanumeric())
                    .next()
                    .unwrap_or("entity")
                    .to_uppercase();
                *skipped.entry(kind).or_default() += 1;
            }
        }
    }
    for (i, e) in edges.iter().enumerate() {
        if !(e.a.is_finite() && e.b.is_finite() && e.bulge.is_finite()) {
            return Err(DxfError::Entity {
                path: path.to_string(),
                message: format!("edge {i} has a coordinate or bulge that is not a finite number"),
            });
        }
    }
    for c in &circles {
        if !(c.center.is_finite() && c.radius.is_finite() && c.radius > 0.0) {
            return Err(DxfError::Entity {
                path: path.to_string(),
                message: format!(
                    "a CIRCLE at ({}, {}) has radius {}: not a positive number",
                    c.center.x, c.center.y, c.radius
                ),
            });
        }
    }
    let warnings = skipped
        .into_iter()
        .map(|(kind, n)| format!("{path}: skipped {n} {kind} (not an outline entity)"))
        .collect();
    Ok((edges, circles, warnings))
}

/// The edges of a polyline's vertices (each with the bulge of the edge
/// that leaves it).
fn polyline_edges(pts: &[(DVec2, f64)], closed: bool, layer: &str, out: &mut Vec<DrawnEdge>) {
    let n = pts.len();
    let m = if closed { n } else { n.saturating_sub(1) };
    for i in 0..m {
        let (a, bulge) = pts[i];
        let (b, _) = pts[(i + 1) % n];
        out.push(DrawnEdge {
            a,
            b,
            bulge,
            layer: layer.to_string(),
            typed: true,
        });
    }
}
