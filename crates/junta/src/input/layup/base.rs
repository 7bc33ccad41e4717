//! The base regions a lay-up is stacked on, as segments: each a box in
//! parameter space `(u, v, w)` (`u` along the part, `v` across it, `w`
//! through the laminate from its inner or bottom surface) mapped into
//! space, with the frame `[e1 e2 e3]` of its plies (`e1` along `u`, `e2`
//! along `v`, `e3` the stacking direction, right-handed so that the map
//! keeps the elements' orientation).
//!
//! | `base.type` | segments | map |
//! |---|---|---|
//! | `rectangle` | one, straight | `x = origin + u e_x + v e_y + w e_z` |
//! | `l_section` | `arm_a`, `bend`, `arm_b` | arm a down `x = r_i + w`, `z` from `-L_a` to 0; the bend about the axis `y` through the origin, radius `r = r_i + w`, from angle 0 (`+x`) to 90 degrees (`+z`); arm b along `-x` at `z = r_i + w` |
//! | `ring` | `sweep` in halves (`half_1`, `half_2`) or one `sector` | about the `z` axis, radius `r_i + w`, angle `u` from `+x` towards `+y`, `z = v` |
//! | `gmsh` | one: a 2D mesh of quadrilaterals and triangles (holes included) | extruded along its nodal normals ([`super::normals`], [`super::extrude`]) |
//!
//! On a bend and a ring the plies stack radially: `e3` is the radius, `e2`
//! the axis and `e1` the tangent, so a 0-degree ply runs around the bend
//! (`junta_elements::material::Rotated::in_cylinder`).

use crate::error::{bail, Result};
use crate::input::gmsh::SurfaceMesh;
use nalgebra::Vector3;
use std::path::PathBuf;
use std::sync::Arc;

/// The laminate's own set names, which a Gmsh base's curves may not take.
const RESERVED: &[&str] = &[
    "bottom", "top", "inner", "outer", "side0", "side1", "end0", "end1",
];

/// `[laminate.base]` keys read by [`segments`].
pub struct BaseGeometry<'a> {
    /// `base.type`.
    pub kind: &'a str,
    /// Where messages point.
    pub at: String,
    /// A cross-section of plane elements ([`plane_segments`]).
    pub plane: bool,
    /// Rectangle: `[Lx, Ly]`.
    pub size: Option<[f64; 2]>,
    /// Line: its length.
    pub length: Option<f64>,
    /// Elements along each direction of the type.
    pub divisions: &'a [usize],
    /// Rectangle: the lower corner.
    pub origin: [f64; 3],
    /// L-section, ring: radius of the inner surface.
    pub inner_radius: Option<f64>,
    /// L-section: lengths of the two arms.
    pub arms: Option<[f64; 2]>,
    /// L-section: width; ring: axial length.
    pub width: Option<f64>,
    /// Ring: swept angle in degrees (default 360).
    pub sweep: Option<f64>,
    /// Gmsh: the 2D mesh file (already resolved next to the scene).
    pub file: Option<PathBuf>,
    /// Gmsh: the side of the surface the plies go.
    pub side: super::normals::StackSide,
}

/// A Gmsh base mesh: its cells oriented and its nodal normals
/// ([`super::normals`]); ply 1's bottom is the surface itself.
#[derive(Debug)]
pub struct Surface {
    /// The mesh as read.
    pub mesh: SurfaceMesh,
    /// Its cells, oriented, and the stacking direction at each node.
    pub base: super::extrude::OrientedBase,
}

/// How a segment maps `(u, v, w)` into space.
#[derive(Debug, Clone, Copy)]
pub enum SegmentMap {
    /// `x = p0 + u e1 + v e2 + w e3`.
    Straight {
        /// The point `(0, 0, 0)`.
        p0: Vector3<f64>,
        /// The frame.
        frame: [Vector3<f64>; 3],
    },
    /// `x = centre + v axis + (r_i + w) (cos u s + sin u (axis x s))`.
    Arc {
        /// A point of the axis (at `v = 0`).
        centre: Vector3<f64>,
        /// Unit axis, the frame's `e2`.
        axis: Vector3<f64>,
        /// Unit radius at `u = 0`.
        start: Vector3<f64>,
        /// Radius of the inner surface.
        inner_radius: f64,
    },
}

impl SegmentMap {
    /// The point of parameters `(u, v, w)`.
    pub fn point(&self, [u, v, w]: [f64; 3]) -> [f64; 3] {
        let x = match *self {
            SegmentMap::Straight { p0, frame } => p0 + u * frame[0] + v * frame[1] + w * frame[2],
            SegmentMap::Arc {
                centre,
                axis,
                start,
                inner_radius,
            } => {
                let radial = u.cos() * start + u.sin() * axis.cross(&start);
                centre + v * axis + (inner_radius + w) * radial
            }
        };
        x.into()
    }
}

/// One segment of a base region.
#[derive(Debug, Clone)]
pub struct Segment {
    /// Name suffix of its parts (`""` for a single flat segment).
    pub name: &'static str,
    /// Extent along `u` (a length, or an angle in radians on an arc).
    pub length: f64,
    /// Extent along `v`.
    pub width: f64,
    /// Elements along `u` and `v`.
    pub divisions: [usize; 2],
    /// The map into space (a Gmsh base: the identity, for the ply frame).
    pub map: SegmentMap,
    /// A Gmsh base's mesh, extruded instead of a box.
    pub surface: Option<Arc<Surface>>,
}

fn positive(at: &str, key: &str, v: Option<f64>) -> Result<f64> {
    match v {
        Some(x) if x.is_finite() && x > 0.0 => Ok(x),
        Some(x) => bail!("{at}: key `laminate.base.{key}`: {x} must be positive and finite"),
        None => bail!("{at}: key `laminate.base.{key}` is required"),
    }
}

fn divisions<const N: usize>(at: &str, d: &[usize], what: &str) -> Result<[usize; N]> {
    let arr: [usize; N] = d.try_into().map_err(|_| {
        crate::error::err!(
            "{at}: key `laminate.base.divisions`: give {N} number{}, {what}",
            if N == 1 { "" } else { "s" }
        )
    })?;
    if arr.contains(&0) {
        bail!("{at}: key `laminate.base.divisions`: every count must be at least 1 ({what})");
    }
    Ok(arr)
}

/// The segments of a base region (module docs).
pub fn segments(g: &BaseGeometry) -> Result<Vec<Segment>> {
    if g.plane {
        return plane_segments(g);
    }
    let at = &g.at;
    let x = Vector3::x();
    let y = Vector3::y();
    let z = Vector3::z();
    match g.kind {
        "rectangle" => {
            let [nx, ny] = divisions::<2>(at, g.divisions, "elements along x and y")?;
            let Some([lx, ly]) = g.size else {
                bail!("{at}: key `laminate.base.size` ([Lx, Ly]) is required with type = \"rectangle\"")
            };
            positive(at, "size", Some(lx.min(ly)))?;
            Ok(vec![Segment {
                name: "",
                length: lx,
                width: ly,
                divisions: [nx, ny],
                map: SegmentMap::Straight {
                    p0: Vector3::from(g.origin),
                    frame: [x, y, z],
                },
                surface: None,
            }])
        }
        "l_section" => {
            let [na, nb, nc, nw] = divisions::<4>(
                at,
                g.divisions,
                "elements along arm a, around the bend, along arm b and across the width",
            )?;
            let r = positive(at, "inner_radius", g.inner_radius)?;
            let w = positive(at, "width", g.width)?;
            let Some([la, lb]) = g.arms else {
                bail!("{at}: key `laminate.base.arms` ([L_a, L_b]) is required with type = \"l_section\"")
            };
            positive(at, "arms", Some(la.min(lb)))?;
            // e2 = -y throughout, so that every map keeps the orientation
            let e2 = -y;
            Ok(vec![
                Segment {
                    name: "arm_a",
                    length: la,
                    width: w,
                    divisions: [na, nw],
                    map: SegmentMap::Straight {
                        p0: Vector3::new(r, w, -la),
                        frame: [z, e2, x],
                    },
                    surface: None,
                },
                Segment {
                    name: "bend",
                    length: std::f64::consts::FRAC_PI_2,
                    width: w,
                    divisions: [nb, nw],
                    map: SegmentMap::Arc {
                        centre: Vector3::new(0.0, w, 0.0),
                        axis: e2,
                        start: x,
                        inner_radius: r,
                    },
                    surface: None,
                },
                Segment {
                    name: "arm_b",
                    length: lb,
                    width: w,
                    divisions: [nc, nw],
                    map: SegmentMap::Straight {
                        p0: Vector3::new(0.0, w, r),
                        frame: [-x, e2, z],
                    },
                    surface: None,
                },
            ])
        }
        "ring" => {
            let [nu, nv] = divisions::<2>(at, g.divisions, "elements around and along the axis")?;
            let r = positive(at, "inner_radius", g.inner_radius)?;
            let length = positive(at, "width", g.width)?;
            let sweep = g.sweep.unwrap_or(360.0);
            if !(sweep > 0.0 && sweep <= 360.0) {
                bail!("{at}: key `laminate.base.sweep`: {sweep} must lie in (0, 360] degrees");
            }
            let arc = |name, from: f64, angle: f64, n| Segment {
                name,
                length: angle.to_radians(),
                width: length,
                divisions: [n, nv],
                map: SegmentMap::Arc {
                    centre: Vector3::zeros(),
                    axis: z,
                    start: Vector3::new(from.to_radians().cos(), from.to_radians().sin(), 0.0),
                    inner_radius: r,
                },
                surface: None,
            };
            if sweep < 360.0 {
                return Ok(vec![arc("sector", 0.0, sweep, nu)]);
            }
            if nu < 2 || nu % 2 != 0 {
                bail!("{at}: key `laminate.base.divisions`: a full ring needs an even number of elements around it (its two halves are merged), got {nu}");
            }
            Ok(vec![
                arc("half_1", 0.0, 180.0, nu / 2),
                arc("half_2", 180.0, 180.0, nu / 2),
            ])
        }
        "gmsh" => {
            let Some(file) = &g.file else {
                bail!("{at}: key `laminate.base.file` (a 2D Gmsh mesh) is required with type = \"gmsh\"")
            };
            let mesh = crate::input::gmsh::read_surface(file)
                .map_err(|e| crate::error::err!("{at}: key `laminate.base.file`: {e}"))?;
            let base = super::normals::orient(&mesh, g.side)
                .map_err(|e| crate::error::err!("{at}: key `laminate.base.file`: {}: {e}", file.display()))?;
            for name in mesh.curves.keys() {
                if RESERVED.contains(&name.as_str()) || name.starts_with("ply_") || name.starts_with("interface_") || name.starts_with("block_") {
                    bail!("{at}: key `laminate.base.file`: the physical curve `{name}` of {} has the name of one of the laminate's own sets; rename it", file.display());
                }
            }
            Ok(vec![Segment {
                name: "",
                length: 0.0,
                width: 0.0,
                divisions: [0, 0],
                map: SegmentMap::Straight {
                    p0: Vector3::zeros(),
                    frame: [x, y, z],
                },
                surface: Some(Arc::new(Surface { mesh, base })),
            }])
        }
        "line" => bail!(
            "{at}: key `laminate.base.type`: `line` is the base of a cross-section of plane elements (cpe*, cps*, cax*); with solid plies use \"rectangle\", \"l_section\", \"ring\" or \"gmsh\""
        ),
        other => bail!(
            "{at}: key `laminate.base.type`: `{other}` is not valid; use \"rectangle\", \"l_section\", \"ring\" or \"gmsh\" (or, with plane elements, \"line\")"
        ),
    }
}

/// The segments of a cross-section's base (plane elements; module docs):
/// the 3D maps with `v = 0` and `e2 = -z`.
pub fn plane_segments(g: &BaseGeometry) -> Result<Vec<Segment>> {
    let at = &g.at;
    let (x, y, z) = (Vector3::x(), Vector3::y(), Vector3::z());
    let straight =
        |name, length, n, p0: Vector3<f64>, e1: Vector3<f64>, e3: Vector3<f64>| Segment {
            name,
            length,
            width: 0.0,
            divisions: [n, 1],
            map: SegmentMap::Straight {
                p0,
                frame: [e1, -z, e3],
            },
            surface: None,
        };
    let arc = |name, from: Vector3<f64>, angle: f64, r: f64, n| Segment {
        name,
        length: angle,
        width: 0.0,
        divisions: [n, 1],
        map: SegmentMap::Arc {
            centre: Vector3::zeros(),
            axis: -z,
            start: from,
            inner_radius: r,
        },
        surface: None,
    };
    match g.kind {
        "line" => {
            let [n] = divisions::<1>(at, g.divisions, "elements along the line")?;
            let l = positive(at, "length", g.length)?;
            Ok(vec![straight("", l, n, Vector3::from(g.origin), x, y)])
        }
        "l_section" => {
            let [na, nb, nc] = divisions::<3>(
                at,
                g.divisions,
                "elements along arm a, around the bend and along arm b",
            )?;
            let r = positive(at, "inner_radius", g.inner_radius)?;
            let Some([la, lb]) = g.arms else {
                bail!("{at}: key `laminate.base.arms` ([L_a, L_b]) is required with type = \"l_section\"")
            };
            positive(at, "arms", Some(la.min(lb)))?;
            Ok(vec![
                straight("arm_a", la, na, Vector3::new(-r, -la, 0.0), y, -x),
                arc("bend", -x, std::f64::consts::FRAC_PI_2, r, nb),
                straight("arm_b", lb, nc, Vector3::new(0.0, r, 0.0), x, y),
            ])
        }
        "ring" => {
            let [nu] = divisions::<1>(at, g.divisions, "elements around the ring")?;
            let r = positive(at, "inner_radius", g.inner_radius)?;
            let sweep = g.sweep.unwrap_or(360.0);
            if !(sweep > 0.0 && sweep <= 360.0) {
                bail!("{at}: key `laminate.base.sweep`: {sweep} must lie in (0, 360] degrees");
            }
            if sweep < 360.0 {
                return Ok(vec![arc("sector", x, sweep.to_radians(), r, nu)]);
            }
            if nu < 2 || nu % 2 != 0 {
                bail!("{at}: key `laminate.base.divisions`: a full ring needs an even number of elements around it (its two halves are merged), got {nu}");
            }
            Ok(vec![
                arc("half_1", x, std::f64::consts::PI, r, nu / 2),
                arc("half_2", -x, std::f64::consts::PI, r, nu / 2),
            ])
        }
        "rectangle" | "gmsh" => bail!(
            "{at}: key `laminate.base.type`: `{}` is a base of solid (3D) plies; a cross-section of plane elements takes \"line\", \"l_section\" or \"ring\"",
            g.kind
        ),
        other => bail!(
            "{at}: key `laminate.base.type`: `{other}` is not valid; a cross-section of plane elements takes \"line\", \"l_section\" or \"ring\""
        ),
    }
}
