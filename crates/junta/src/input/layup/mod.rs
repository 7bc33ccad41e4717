//! The lay-up builder: a scene's `[laminate]` becomes plies, their
//! material axes, ply blocks, interface elements and named sets, before
//! anything else sees the model.
//!
//! ## What it builds
//!
//! * **Plies**, numbered 1 (bottom, lowest `z`, or the inner surface of a
//!   curved base) to `n` (top, outer): on each segment of the base
//!   ([`base`]: a rectangle, an L-section's two arms and bend, a ring) a
//!   box of the segment's plan with the ply's own thickness and elements
//!   through it, mapped into space and stacked along the stacking
//!   direction (`+z` on a rectangle, the radius on a bend or ring). The plies come from a compact code (`layup =
//!   "[0/90/±45]s"`, [`code`]) with one material and ply thickness, or from
//!   an explicit `[[laminate.plies]]` list.
//! * **Material axes**: ply `k` of angle `theta` gets its material turned
//!   into the segment's frame `[e1 e2 e3]` and by `theta` about the
//!   stacking direction `e3` ([`junta_elements::material::Rotated`]; on a
//!   rectangle `e1 = x`, `e3 = z`, so an orthotropic material without an
//!   orientation has its fibre along `(cos theta, sin theta, 0)`; on a
//!   bend or ring the frame turns with the point, `e1` the tangent). The
//!   material is named `MATERIAL@ANGLE` (`im7@-45`), on a curved base
//!   `MATERIAL@ANGLE.SEGMENT`, the name its blocks and messages show.
//! * **Ply blocks**: maximal runs of neighbouring plies of the same material
//!   and angle (angles equal modulo 180 degrees), unless `merge_plies =
//!   false` makes every ply its own block. A block behaves as one thick ply:
//!   `interfaces = "blocks"` puts interfaces between blocks only.
//! * **Interfaces** (`interfaces`): `"blocks"` (the default when an
//!   `interface_law` is given), `"all"` (between every pair of neighbouring
//!   plies), `"none"`, or a list of ply numbers `k`, each an interface
//!   between ply `k` and ply `k + 1`. Each takes the law of the first
//!   `[[laminate.interface_laws]]` rule that matches it (`angles = [a, b]`:
//!   the angles of its two plies in either order; `at = k`: the interface
//!   above ply `k`), else `interface_law`.
//! * **Sets**: element sets `ply_K` and `block_J`; node and face sets
//!   `bottom`, `top` (the laminate's faces at the lowest and highest `z`)
//!   and `x0`, `x1`, `y0`, `y1` (its edges, every ply) on a rectangle;
//!   `inner` (= `bottom`), `outer` (= `top`), `side0`, `side1` (the `v`
//!   sides) and `end0`, `end1` (the two ends, not on a full ring) on a
//!   curved base, whose plies' parts are `ply_K.SEGMENT`; the interfaces'
//!   blocks and element sets `interface_K_L` (between plies `K` and `L =
//!   K + 1`) with node sets `interface_K_L.bottom` and `.top`; and each
//!   ply's own box sets `ply_K.x0` .. `ply_K.z1`.
//!
//! * **Cross-sections**: with a plane `element` (`cpe*`, `cps*`, `cax*`)
//!   the base is a `line`, `l_section` or `ring` of the `x`-`y` plane
//!   ([`base::plane_segments`]): each ply is a plane box `(u, w)` mapped
//!   with `v = 0`, the interfaces are line interfaces, and the sets lose
//!   the width's (`y0`, `y1` of a rectangle, `side0`, `side1`).
//!
//! The edge and face sets hold both copies of the nodes an interface
//! duplicates (the rule of [`junta_core::mesh::interface`]), so a condition
//! on an edge holds every ply.

pub mod base;
pub mod code;
pub mod extrude;
pub mod normal_field;
pub mod normals;

use crate::error::{bail, err, Result};
use crate::input::scene::{generate_box, BoxGeometry, SceneFile};
use junta_core::mesh::{ElementRef, Mesh};
use junta_core::topology::CellShape;
use junta_core::Material;
use serde::Deserialize;
use std::collections::BTreeMap;
use std::sync::Arc;
use toml::Spanned;

/// `[laminate]`: the lay-up of a scene (module docs).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LaminateSpec {
    /// The region the plies are stacked on.
    pub base: BaseSpec,
    /// Solid element key of the plies (h8, h8i, h20, h27, h20r, h27r, wedge6, wedge15).
    pub element: Spanned<String>,
    /// Material of the plies of `layup` (and the default of `[[plies]]`).
    pub material: Option<Spanned<String>>,
    /// Thickness of the plies of `layup` (and the default of `[[plies]]`).
    pub ply_thickness: Option<f64>,
    /// Elements through each ply (default 1).
    pub elements_per_ply: Option<usize>,
    /// Compact lay-up code, bottom to top (`"[0/90/±45]s"`).
    pub layup: Option<Spanned<String>>,
    /// Explicit plies, bottom to top (instead of `layup`).
    #[serde(default)]
    pub plies: Vec<PlySpec>,
    /// Merge neighbouring plies of the same material and angle into one
    /// block (default true).
    pub merge_plies: Option<bool>,
    /// Where the interfaces go: `"blocks"`, `"all"`, `"none"` or a list of
    /// ply numbers (an interface above each).
    pub interfaces: Option<Spanned<Placement>>,
    /// The law of every interface no rule of `interface_laws` matches.
    pub interface_law: Option<Spanned<String>>,
    /// Laws by position: the first matching rule wins.
    #[serde(default)]
    pub interface_laws: Vec<InterfaceLawRule>,
    /// Integration rule of the interfaces: `"gauss"` (default) or `"lobatto"`.
    pub integration: Option<String>,
}

/// `[laminate.base]`: the region the plies are stacked on ([`base`]:
/// `rectangle`, `l_section`, `ring`).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BaseSpec {
    /// `"rectangle"`, `"l_section"`, `"ring"` or `"gmsh"`; with plane
    /// elements `"line"`, `"l_section"` or `"ring"` (a cross-section).
    #[serde(rename = "type")]
    pub kind: Spanned<String>,
    /// Rectangle: edge lengths along x and y.
    pub size: Option<[f64; 2]>,
    /// Line (plane elements): its length along x.
    pub length: Option<f64>,
    /// Elements: rectangle `[nx, ny]`; L-section `[arm a, bend, arm b,
    /// width]`; ring `[around, along the axis]`; none for a Gmsh base. In
    /// a cross-section: line `[n]`, L-section `[arm a, bend, arm b]`, ring
    /// `[around]`.
    #[serde(default)]
    pub divisions: Vec<usize>,
    /// Rectangle, line: the laminate's lower corner (bottom of ply 1),
    /// default the origin (`[x, y]` in a cross-section).
    #[serde(default, deserialize_with = "crate::input::scene::origin_xyz")]
    pub origin: [f64; 3],
    /// Rectangle: ratio of the last to the first element size along x and
    /// y (default 1); line: one ratio, along x.
    pub grading: Option<Vec<f64>>,
    /// L-section, ring: radius of the inner surface (ply 1's inner face).
    pub inner_radius: Option<f64>,
    /// L-section: lengths of arm a and arm b.
    pub arms: Option<[f64; 2]>,
    /// L-section: width (along y); ring: axial length (along z).
    pub width: Option<f64>,
    /// Ring: swept angle in degrees, default 360 (a full ring).
    pub sweep: Option<f64>,
    /// Gmsh: a 2D mesh of quadrilaterals and triangles (MSH 4.1, path
    /// relative to the scene), extruded along its nodal normals.
    pub file: Option<std::path::PathBuf>,
    /// Gmsh: the plies go on the side of the surface facing this point.
    pub normal_towards: Option<[f64; 3]>,
    /// Gmsh: the plies go on the side of the surface away from this point.
    pub normal_away_from: Option<[f64; 3]>,
    /// Gmsh: the plies go on the other side (default false).
    pub flip: Option<bool>,
    /// Gmsh: the 0-degree fibre is this direction projected on the
    /// surface at each point (default `[1, 0, 0]`).
    pub fibre_direction: Option<Spanned<[f64; 3]>>,
    /// Gmsh: instead, the in-plane transverse axis `e2` is this direction
    /// projected on the surface (a cylinder's axis: 0-degree fibres run
    /// around it).
    pub transverse_direction: Option<Spanned<[f64; 3]>>,
}

/// One ply of `[[laminate.plies]]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PlySpec {
    /// Fibre angle in degrees about z, from x towards y.
    pub angle: f64,
    /// Material (default `laminate.material`).
    pub material: Option<Spanned<String>>,
    /// Thickness (default `laminate.ply_thickness`).
    pub thickness: Option<f64>,
    /// Elements through the ply (default `laminate.elements_per_ply`, 1).
    pub elements: Option<usize>,
}

/// `interfaces = "blocks" | "all" | "none" | [k, ...]`.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(untagged)]
pub enum Placement {
    /// `"blocks"`, `"all"` or `"none"`.
    Named(String),
    /// Interfaces above the listed plies.
    Above(Vec<usize>),
}

/// `[[laminate.interface_laws]]`: the law of the interfaces it matches.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InterfaceLawRule {
    /// The angles of the two plies, in either order.
    pub angles: Option<[f64; 2]>,
    /// The interface above this ply.
    pub at: Option<usize>,
    /// Law name (a key of `[laws]`).
    pub law: Spanned<String>,
}

/// One ply, resolved.
#[derive(Debug, Clone, PartialEq)]
pub struct Ply {
    /// Fibre angle in degrees.
    pub angle: f64,
    /// Name of the material before the rotation.
    pub material: String,
    /// Thickness.
    pub thickness: f64,
    /// Elements through the thickness.
    pub elements: usize,
}

impl Ply {
    /// The name of this ply's rotated material, `MATERIAL@ANGLE`.
    pub fn material_name(&self) -> String {
        format!("{}@{}", self.material, self.angle)
    }
}

/// One interface of the lay-up, resolved.
#[derive(Debug, Clone, PartialEq)]
pub struct LayupInterface {
    /// Number of the ply below it (1-based): it lies between plies
    /// `below` and `below + 1`.
    pub below: usize,
    /// Its law.
    pub law: String,
}

impl LayupInterface {
    /// Its block and element set name, `interface_K_L`.
    pub fn name(&self) -> String {
        format!("interface_{}_{}", self.below, self.below + 1)
    }
}

/// A lay-up resolved from its scene table: plies bottom to top, blocks
/// (ranges of 0-based ply indices) and interfaces.
#[derive(Debug, Clone, PartialEq)]
pub struct Layup {
    /// The plies, bottom to top.
    pub plies: Vec<Ply>,
    /// The ply blocks: 0-based ply index ranges, bottom to top.
    pub blocks: Vec<std::ops::Range<usize>>,
    /// The interfaces, bottom to top.
    pub interfaces: Vec<LayupInterface>,
}

/// An angle in (-90, 90]: two plies whose angles differ by 180 degrees
/// have the same fibre direction.
fn fibre_direction(angle: f64) -> f64 {
    let a = angle.rem_euclid(180.0);
    if a > 90.0 {
        a - 180.0
    } else {
        a
    }
}

fn same_direction(a: f64, b: f64) -> bool {
    let d = (fibre_direction(a) - fibre_direction(b)).abs();
    d < 1e-9 || (d - 180.0).abs() < 1e-9
}

impl Layup {
    /// Resolve the `[laminate]` of `sf` (checked: every error names the key).
    pub fn resolve(sf: &SceneFile, spec: &LaminateSpec) -> Result<Layup> {
        let plies = resolve_plies(sf, spec)?;
        let merge = spec.merge_plies.unwrap_or(true);
        let mut blocks: Vec<std::ops::Range<usize>> = Vec::new();
        for (i, p) in plies.iter().enumerate() {
            match blocks.last_mut() {
                Some(b)
                    if merge
                        && plies[i - 1].material == p.material
                        && same_direction(plies[i - 1].angle, p.angle) =>
                {
                    b.end = i + 1
                }
                _ => blocks.push(i..i + 1),
            }
        }
        let interfaces = resolve_interfaces(sf, spec, &plies, &blocks)?;
        Ok(Layup {
            plies,
            blocks,
            interfaces,
        })
    }

    /// `z` of the bottom of each ply and of the top of the last
    /// (`plies.len() + 1` values), from the laminate's bottom `z0`.
    pub fn ply_levels(&self, z0: f64) -> Vec<f64> {
        let mut z = vec![z0];
        for p in &self.plies {
            z.push(z.last().copied().unwrap_or(z0) + p.thickness);
        }
        z
    }
}

fn resolve_plies(sf: &SceneFile, spec: &LaminateSpec) -> Result<Vec<Ply>> {
    let file = sf.path.display();
    let default_elements = spec.elements_per_ply.unwrap_or(1);
    if default_elements == 0 {
        bail!("{file}: key `laminate.elements_per_ply`: must be at least 1");
    }
    let thickness = |t: Option<f64>, key: &str| -> Result<f64> {
        let t = t.or(spec.ply_thickness).ok_or_else(|| {
            err!("{file}: key `{key}` is required (or give `laminate.ply_thickness`)")
        })?;
        if !(t.is_finite() && t > 0.0) {
            bail!("{file}: key `{key}`: {t} is not a positive thickness");
        }
        Ok(t)
    };
    let material = |m: Option<&Spanned<String>>, key: &str| -> Result<String> {
        m.or(spec.material.as_ref())
            .map(|m| m.get_ref().clone())
            .ok_or_else(|| err!("{file}: key `{key}` is required (or give `laminate.material`)"))
    };
    let plies: Vec<Ply> = match (&spec.layup, spec.plies.is_empty()) {
        (Some(_), false) => bail!(
            "{file}: keys `laminate.layup` and `laminate.plies` both given; give the lay-up one way"
        ),
        (None, true) => bail!(
            "{file}: key `laminate.layup` (a code such as \"[0/90/±45]s\") or `[[laminate.plies]]` is required"
        ),
        (Some(code), true) => {
            let angles = code::parse_layup(code.get_ref()).map_err(|e| {
                err!("{}: key `laminate.layup`: {e}", sf.at(code.span()))
            })?;
            let material = material(None, "laminate.material")?;
            let thickness = thickness(None, "laminate.ply_thickness")?;
            angles
                .into_iter()
                .map(|angle| Ply {
                    angle,
                    material: material.clone(),
                    thickness,
                    elements: default_elements,
                })
                .collect()
        }
        (None, false) => spec
            .plies
            .iter()
            .enumerate()
            .map(|(i, p)| {
                let key = format!("laminate.plies[{i}]");
                if !p.angle.is_finite() {
                    bail!("{file}: key `{key}.angle`: {} is not a finite angle", p.angle);
                }
                let elements = p.elements.unwrap_or(default_elements);
                if elements == 0 {
                    bail!("{file}: key `{key}.elements`: must be at least 1");
                }
                Ok(Ply {
                    angle: p.angle,
                    material: material(p.material.as_ref(), &format!("{key}.material"))?,
                    thickness: thickness(p.thickness, &format!("{key}.thickness"))?,
                    elements,
                })
            })
            .collect::<Result<_>>()?,
    };
    for (name, known) in plies.iter().map(|p| (&p.material, &sf.scene.materials)) {
        if !known.contains_key(name) {
            bail!(
                "{file}: key `laminate`: unknown ply material `{name}`; materials defined in [materials]: {}",
                known.keys().cloned().collect::<Vec<_>>().join(", ")
            );
        }
    }
    Ok(plies)
}

/// The plies each interface sits above (0-based index of the ply below).
fn interface_positions(
    sf: &SceneFile,
    spec: &LaminateSpec,
    plies: &[Ply],
    blocks: &[std::ops::Range<usize>],
) -> Result<Vec<usize>> {
    let n = plies.len();
    let default = if spec.interface_law.is_some() || !spec.interface_laws.is_empty() {
        Placement::Named("blocks".into())
    } else {
        Placement::Named("none".into())
    };
    let placement = spec
        .interfaces
        .as_ref()
        .map(|p| p.get_ref())
        .unwrap_or(&default);
    let at = spec
        .interfaces
        .as_ref()
        .map_or(sf.path.display().to_string(), |p| sf.at(p.span()));
    Ok(match placement {
        Placement::Named(s) if s == "none" => Vec::new(),
        Placement::Named(s) if s == "all" => (0..n.saturating_sub(1)).collect(),
        Placement::Named(s) if s == "blocks" => {
            blocks.iter().skip(1).map(|b| b.start - 1).collect()
        }
        Placement::Named(s) => bail!(
            "{at}: key `laminate.interfaces`: `{s}` is not valid; use \"blocks\", \"all\", \"none\" or a list of ply numbers (an interface above each)"
        ),
        Placement::Above(list) => {
            let mut v = Vec::new();
            for &k in list {
                if k == 0 || k >= n {
                    bail!(
                        "{at}: key `laminate.interfaces`: ply {k} has no ply above it; an interface above ply k needs 1 <= k <= {}",
                        n.saturating_sub(1)
                    );
                }
                v.push(k - 1);
            }
            v.sort_unstable();
            v.dedup();
            v
        }
    })
}

fn resolve_interfaces(
    sf: &SceneFile,
    spec: &LaminateSpec,
    plies: &[Ply],
    blocks: &[std::ops::Range<usize>],
) -> Result<Vec<LayupInterface>> {
    let file = sf.path.display();
    for (r, rule) in spec.interface_laws.iter().enumerate() {
        if rule.angles.is_some() == rule.at.is_some() {
            bail!(
                "{}: key `laminate.interface_laws[{r}]`: give exactly one of `angles = [a, b]` and `at = k`",
                sf.at(rule.law.span())
            );
        }
        if !sf.scene.laws.contains_key(rule.law.get_ref()) {
            bail!(
                "{}: key `laminate.interface_laws[{r}].law`: unknown law `{}`; laws defined in [laws]: {}",
                sf.at(rule.law.span()),
                rule.law.get_ref(),
                sf.scene.laws.keys().cloned().collect::<Vec<_>>().join(", ")
            );
        }
    }
    let positions = interface_positions(sf, spec, plies, blocks)?;
    positions
        .into_iter()
        .map(|i| {
            let (a, b) = (plies[i].angle, plies[i + 1].angle);
            let rule = spec.interface_laws.iter().find(|r| match (r.angles, r.at) {
                (Some([x, y]), _) => {
                    (same_direction(x, a) && same_direction(y, b))
                        || (same_direction(x, b) && same_direction(y, a))
                }
                (_, Some(k)) => k == i + 1,
                _ => false,
            });
            let law = match (rule, &spec.interface_law) {
                (Some(r), _) => r.law.get_ref().clone(),
                (None, Some(l)) => l.get_ref().clone(),
                (None, None) => bail!(
                    "{file}: key `laminate.interface_law`: the interface between plies {} ({a}) and {} ({b}) has no law; give `interface_law` or a matching `[[laminate.interface_laws]]` rule",
                    i + 1,
                    i + 2
                ),
            };
            if !sf.scene.laws.contains_key(&law) {
                bail!(
                    "{file}: key `laminate.interface_law`: unknown law `{law}`; laws defined in [laws]: {}",
                    sf.scene.laws.keys().cloned().collect::<Vec<_>>().join(", ")
                );
            }
            Ok(LayupInterface { below: i + 1, law })
        })
        .collect()
}

/// Whether `laminate.element` is a plane element: the lay-up is then a
/// cross-section in the `x`-`y` plane ([`base::plane_segments`]).
fn is_cross_section(sf: &SceneFile, spec: &LaminateSpec) -> Result<bool> {
    let entry =
        junta_core::registry::find::<junta_core::registry::ElementEntry>(spec.element.get_ref())
            .map_err(|e| {
                err!(
                    "{}: key `laminate.element`: {e}",
                    sf.at(spec.element.span())
                )
            })?;
    Ok(entry.shape.is_plane())
}

/// `laminate.base.grading` as the ratios along `u` and `v`: two values on
/// a rectangle, one on a line, none elsewhere.
fn base_grading(sf: &SceneFile, b: &BaseSpec) -> Result<[f64; 2]> {
    let at = sf.at(b.kind.span());
    match (b.kind.get_ref().as_str(), b.grading.as_deref()) {
        (_, None) => Ok([1.0; 2]),
        ("rectangle", Some(&[gx, gy])) => Ok([gx, gy]),
        ("line", Some(&[g])) => Ok([g, 1.0]),
        ("rectangle", Some(_)) => bail!("{at}: key `laminate.base.grading`: give two ratios [along x, along y]"),
        ("line", Some(_)) => bail!("{at}: key `laminate.base.grading`: give one ratio [along the line]"),
        (kind, Some(_)) => bail!("{at}: key `laminate.base.grading` is not used with type = \"{kind}\"; only a rectangle or a line is graded"),
    }
}

fn base_geometry<'a>(sf: &SceneFile, spec: &'a LaminateSpec) -> Result<base::BaseGeometry<'a>> {
    let b = &spec.base;
    let plane = is_cross_section(sf, spec)?;
    refuse_unused_base_keys(sf, b, plane)?;
    Ok(base::BaseGeometry {
        kind: b.kind.get_ref(),
        at: sf.at(b.kind.span()),
        plane,
        length: b.length,
        size: b.size,
        divisions: &b.divisions,
        origin: b.origin,
        inner_radius: b.inner_radius,
        arms: b.arms,
        width: b.width,
        sweep: b.sweep,
        file: b.file.as_ref().map(|f| sf.relative(f)),
        side: normals::StackSide {
            towards: b.normal_towards,
            away_from: b.normal_away_from,
            flip: b.flip.unwrap_or(false),
        },
    })
}

/// The `[laminate.base]` keys each base type reads (`type` and
/// `grading`, checked by [`base_grading`], aside), in a solid laminate and
/// in a cross-section of plane elements; `None` for a type that does not
/// exist there (its own message comes from [`base::segments`]).
fn base_keys(kind: &str, plane: bool) -> Option<&'static [&'static str]> {
    Some(match (kind, plane) {
        ("rectangle", false) => &["size", "divisions", "origin"],
        ("line", true) => &["length", "divisions", "origin"],
        ("l_section", false) => &["inner_radius", "arms", "width", "divisions"],
        ("l_section", true) => &["inner_radius", "arms", "divisions"],
        ("ring", false) => &["inner_radius", "width", "sweep", "divisions"],
        ("ring", true) => &["inner_radius", "sweep", "divisions"],
        ("gmsh", false) => &[
            "file",
            "normal_towards",
            "normal_away_from",
            "flip",
            "fibre_direction",
            "transverse_direction",
        ],
        _ => return None,
    })
}

/// A `[laminate.base]` key that its type does not read is an error naming
/// it and the keys that type reads (it would otherwise be ignored). An
/// `origin` of `[0, 0, 0]` cannot be told from none and passes.
fn refuse_unused_base_keys(sf: &SceneFile, b: &BaseSpec, plane: bool) -> Result<()> {
    let kind = b.kind.get_ref().as_str();
    let Some(reads) = base_keys(kind, plane) else {
        return Ok(());
    };
    let given = [
        ("size", b.size.is_some()),
        ("length", b.length.is_some()),
        ("divisions", !b.divisions.is_empty()),
        ("origin", b.origin != [0.0; 3]),
        ("inner_radius", b.inner_radius.is_some()),
        ("arms", b.arms.is_some()),
        ("width", b.width.is_some()),
        ("sweep", b.sweep.is_some()),
        ("file", b.file.is_some()),
        ("normal_towards", b.normal_towards.is_some()),
        ("normal_away_from", b.normal_away_from.is_some()),
        ("flip", b.flip.is_some()),
        ("fibre_direction", b.fibre_direction.is_some()),
        ("transverse_direction", b.transverse_direction.is_some()),
    ];
    if let Some((key, _)) = given.iter().find(|(k, g)| *g && !reads.contains(k)) {
        let section = if plane { " in a cross-section" } else { "" };
        let hint = match (*key, plane) {
            ("width", true) => " (a cross-section's width is `[model] thickness`)",
            _ => "",
        };
        bail!(
            "{}: key `laminate.base.{key}` is not read with type = \"{kind}\"{section}{hint}; that type reads {}",
            sf.at(b.kind.span()),
            reads.iter().map(|k| format!("`{k}`")).collect::<Vec<_>>().join(", ")
        );
    }
    Ok(())
}

/// The part (block and element set) of ply `k` on segment `s`: `ply_K`
/// on a one-segment base, `ply_K.SEGMENT` on a curved one.
fn part_name(k: usize, s: &base::Segment) -> String {
    if s.name.is_empty() {
        ply_set(k)
    } else {
        format!("{}.{}", ply_set(k), s.name)
    }
}

/// The material of ply `p` on segment `s`: `MATERIAL@ANGLE[.SEGMENT]`.
fn part_material(p: &Ply, s: &base::Segment) -> String {
    if s.name.is_empty() {
        p.material_name()
    } else {
        format!("{}.{}", p.material_name(), s.name)
    }
}

/// The mesh of a `[laminate]`: plies stacked on each segment of the base,
/// merged, the laminate's sets, then its interfaces inserted bottom to top
/// (module docs).
pub fn build_mesh(sf: &SceneFile, spec: &LaminateSpec) -> Result<Mesh> {
    let layup = Layup::resolve(sf, spec)?;
    let at = sf.at(spec.base.kind.span());
    let segments = base::segments(&base_geometry(sf, spec)?)?;
    let levels = layup.ply_levels(0.0);
    let grading = base_grading(sf, &spec.base)?;
    let plane = is_cross_section(sf, spec)?;
    let mut parts = Vec::with_capacity(layup.plies.len() * segments.len());
    for (k, ply) in layup.plies.iter().enumerate() {
        for s in &segments {
            if let Some(surf) = &s.surface {
                let elements = extruded_elements(sf, spec, &surf.mesh)?;
                let part = extrude::extrude_ply(
                    &surf.mesh,
                    &surf.base,
                    levels[k],
                    ply.thickness,
                    ply.elements,
                    elements,
                    &part_material(ply, s),
                );
                parts.push((part_name(k, s), part));
                continue;
            }
            // a cross-section's ply is the plane box (u, w)
            let geometry = if plane {
                BoxGeometry {
                    size: [s.length, ply.thickness, 1.0],
                    divisions: [s.divisions[0], ply.elements, 1],
                    origin: [0.0, levels[k], 0.0],
                    grading: [grading[0], 1.0, 1.0],
                }
            } else {
                BoxGeometry {
                    size: [s.length, s.width, ply.thickness],
                    divisions: [s.divisions[0], s.divisions[1], ply.elements],
                    origin: [0.0, 0.0, levels[k]],
                    grading: [grading[0], grading[1], 1.0],
                }
            };
            let mut part = generate_box(
                sf,
                "laminate",
                geometry,
                &spec.element,
                &part_material(ply, s),
            )?;
            for p in part.nodes.iter_mut() {
                *p = if plane {
                    s.map.point([p[0], 0.0, p[1]])
                } else {
                    s.map.point(*p)
                };
            }
            parts.push((part_name(k, s), part));
        }
    }
    let mut mesh = junta_core::mesh::merge::merge(parts, 1e-9)
        .map_err(|e| err!("{at}: key `laminate`: {e}"))?;
    add_laminate_sets(&mut mesh, &layup, &segments, plane);
    for f in &layup.interfaces {
        let (below, above) = (ply_set(f.below - 1), ply_set(f.below));
        junta_core::mesh::interface::insert_interface(&mut mesh, &below, &above, &f.name(), &f.law)
            .map_err(|e| err!("{at}: key `laminate.interfaces`: {}: {e}", f.name()))?;
    }
    Ok(mesh)
}

/// The solid elements of a Gmsh base's plies: `laminate.element` on the
/// quadrilaterals (Hex8: h8, h8i on Quad4; Hex20: h20, h20r on Quad8),
/// the wedge of the same order on the triangles (wedge6 on Tri3, wedge15
/// on Tri6); on a base of triangles only, `element` may name the wedge.
fn extruded_elements<'a>(
    sf: &SceneFile,
    spec: &'a LaminateSpec,
    s: &crate::input::gmsh::SurfaceMesh,
) -> Result<extrude::PlyElements<'a>> {
    let at = sf.at(spec.element.span());
    let key = spec.element.get_ref().as_str();
    let entry = junta_core::registry::find::<junta_core::registry::ElementEntry>(key)
        .map_err(|e| err!("{at}: key `laminate.element`: {e}"))?;
    let (hex, wedge, wedge_key, fits) = if s.quadratic {
        (
            CellShape::Hex20,
            CellShape::Wedge15,
            "wedge15",
            "h20 or h20r",
        )
    } else {
        (CellShape::Hex8, CellShape::Wedge6, "wedge6", "h8 or h8i")
    };
    let cells = match (s.quads.is_empty(), s.tris.is_empty()) {
        (false, true) => "quadrilaterals",
        (true, false) => "triangles",
        _ => "quadrilaterals and triangles",
    };
    let n = s.quad_shape().num_nodes();
    if entry.shape == hex {
        Ok(extrude::PlyElements {
            hex: key,
            wedge: wedge_key,
        })
    } else if entry.shape == wedge && s.quads.is_empty() {
        Ok(extrude::PlyElements {
            hex: key,
            wedge: key,
        })
    } else {
        bail!(
            "{at}: key `laminate.element`: `{}` does not fit the base's {cells} (order {}); use {fits}{}",
            entry.key,
            if s.quadratic { 2 } else { 1 },
            if s.quads.is_empty() {
                format!(" (or {wedge_key}); the triangles get {wedge_key}")
            } else if s.tris.is_empty() {
                String::new()
            } else {
                format!(" on the {n}-node quadrilaterals; the triangles get {wedge_key}")
            }
        );
    }
}

/// The element set (and block) of ply `k` (0-based index): `ply_{k+1}`.
fn ply_set(k: usize) -> String {
    format!("ply_{}", k + 1)
}

/// `ply_K` (on a curved base: the union of its segments), `block_J`, and
/// the laminate's faces and edges (module docs), before the interfaces are
/// inserted, so that they keep both copies of every duplicated node.
fn add_laminate_sets(mesh: &mut Mesh, layup: &Layup, segments: &[base::Segment], plane: bool) {
    let n = layup.plies.len();
    let curved = !segments[0].name.is_empty();
    if curved {
        for k in 0..n {
            let mut set: Vec<ElementRef> = Vec::new();
            for s in segments {
                set.extend_from_slice(
                    mesh.element_sets
                        .get(&part_name(k, s))
                        .map_or(&[][..], |v| v),
                );
            }
            mesh.element_sets.insert(ply_set(k), set);
        }
    }
    for (j, b) in layup.blocks.iter().enumerate() {
        let mut set: Vec<ElementRef> = Vec::new();
        for k in b.clone() {
            set.extend_from_slice(mesh.element_sets.get(&ply_set(k)).map_or(&[][..], |s| s));
        }
        mesh.element_sets.insert(format!("block_{}", j + 1), set);
    }
    let all: Vec<usize> = (0..segments.len()).collect();
    let last = segments.len() - 1;
    // (set, plies, segments, the box side of each part)
    // the box sides of a ply's bottom, top and width
    let (bottom, top, across) = if plane {
        ("y0", "y1", None)
    } else {
        ("z0", "z1", Some(["y0", "y1"]))
    };
    let mut sides: Vec<(&str, Vec<usize>, Vec<usize>, &str)> = vec![
        ("bottom", vec![0], all.clone(), bottom),
        ("top", vec![n - 1], all.clone(), top),
    ];
    if let Some(surf) = &segments[0].surface {
        for name in surf.mesh.curves.keys() {
            sides.push((name.as_str(), (0..n).collect(), all.clone(), name.as_str()));
        }
    } else if !curved {
        for side in ["x0", "x1"].into_iter().chain(across.into_iter().flatten()) {
            sides.push((side, (0..n).collect(), all.clone(), side));
        }
    } else {
        sides.push(("inner", vec![0], all.clone(), bottom));
        sides.push(("outer", vec![n - 1], all.clone(), top));
        if let Some([y0, y1]) = across {
            sides.push(("side0", (0..n).collect(), all.clone(), y0));
            sides.push(("side1", (0..n).collect(), all.clone(), y1));
        }
        if segments[0].name != "half_1" {
            sides.push(("end0", (0..n).collect(), vec![0], "x0"));
            sides.push(("end1", (0..n).collect(), vec![last], "x1"));
        }
    }
    for (name, plies, segs, side) in sides {
        let (mut nodes, mut faces) = (Vec::new(), Vec::new());
        for &k in &plies {
            for &s in &segs {
                let key = format!("{}.{side}", part_name(k, &segments[s]));
                nodes.extend_from_slice(mesh.node_sets.get(&key).map_or(&[][..], |v| v));
                faces.extend_from_slice(mesh.face_sets.get(&key).map_or(&[][..], |v| v));
            }
        }
        nodes.sort_unstable();
        nodes.dedup();
        mesh.node_sets.insert(name.to_string(), nodes);
        mesh.face_sets.insert(name.to_string(), faces);
    }
}

/// Add the rotated material `MATERIAL@ANGLE` of every ply to `materials`
/// (which holds the scene's `[materials]`).
pub fn add_ply_materials(
    sf: &SceneFile,
    spec: &LaminateSpec,
    materials: &mut BTreeMap<String, Arc<dyn Material>>,
) -> Result<()> {
    use junta_elements::material::Rotated;
    let layup = Layup::resolve(sf, spec)?;
    let segments = base::segments(&base_geometry(sf, spec)?)?;
    let thickness = layup.plies.iter().map(|p| p.thickness).sum::<f64>();
    let frames: Vec<Option<SurfaceFrame>> = segments
        .iter()
        .map(|s| {
            s.surface
                .as_ref()
                .map(|surf| surface_frame(sf, &spec.base, surf, thickness))
                .transpose()
        })
        .collect::<Result<_>>()?;
    for p in &layup.plies {
        for (s, frame) in segments.iter().zip(&frames) {
            let name = part_material(p, s);
            if materials.contains_key(&name) {
                continue;
            }
            let inner = materials.get(&p.material).cloned().ok_or_else(|| {
                err!(
                    "{}: key `laminate`: unknown ply material `{}`",
                    sf.path.display(),
                    p.material
                )
            })?;
            let ply = match (frame, s.map) {
                (Some(f), _) => f.ply(inner, p.angle),
                (None, base::SegmentMap::Straight { frame, .. }) => {
                    let f = nalgebra::Matrix3::from_columns(&frame);
                    let turn = nalgebra::Rotation3::from_axis_angle(
                        &nalgebra::Vector3::z_axis(),
                        p.angle.to_radians(),
                    );
                    Rotated::new(inner, f * turn.into_inner())
                }
                (None, base::SegmentMap::Arc { centre, axis, .. }) => {
                    Rotated::in_cylinder(inner, centre.into(), axis.into(), p.angle)
                }
            };
            materials.insert(name, Arc::new(ply));
        }
    }
    Ok(())
}

/// The ply frame of a Gmsh base: one fixed frame on a plane, else the
/// normal field of the curved surface, with the in-plane reference.
struct SurfaceFrame {
    reference: junta_elements::material::InPlaneReference,
    /// On a plane: `[e1 e2 e3]`.
    plane: Option<nalgebra::Matrix3<f64>>,
    /// On a curved surface: its normal field.
    field: Option<Arc<normal_field::SurfaceNormals>>,
    /// A point of the base, where the ply's nominal `C` is evaluated.
    at: [f64; 3],
}

impl SurfaceFrame {
    fn ply(&self, inner: Arc<dyn Material>, angle: f64) -> junta_elements::material::Rotated {
        use junta_elements::material::Rotated;
        match (&self.field, self.plane) {
            (Some(field), _) => {
                Rotated::on_surface(inner, field.clone(), self.reference, angle, self.at)
            }
            (None, q) => {
                let q = q.unwrap_or_else(nalgebra::Matrix3::identity);
                let turn = nalgebra::Rotation3::from_axis_angle(
                    &nalgebra::Vector3::z_axis(),
                    angle.to_radians(),
                );
                Rotated::new(inner, q * turn.into_inner())
            }
        }
    }
}

/// The frame of a Gmsh base's plies (`fibre_direction` or
/// `transverse_direction`, [`junta_elements::material::Rotated::on_surface`]);
/// a reference that is (nearly) normal to the surface at a node is an
/// error naming it.
fn surface_frame(
    sf: &SceneFile,
    b: &BaseSpec,
    surf: &base::Surface,
    thickness: f64,
) -> Result<SurfaceFrame> {
    use junta_elements::material::InPlaneReference;
    let (reference, key, span) = match (&b.fibre_direction, &b.transverse_direction) {
        (Some(_), Some(t)) => bail!(
            "{}: key `laminate.base.transverse_direction`: give `fibre_direction` or `transverse_direction`, not both",
            sf.at(t.span())
        ),
        (Some(f), None) => (InPlaneReference::Fibre(*f.get_ref()), "fibre_direction", Some(f.span())),
        (None, Some(t)) => (InPlaneReference::Transverse(*t.get_ref()), "transverse_direction", Some(t.span())),
        (None, None) => (InPlaneReference::Fibre([1.0, 0.0, 0.0]), "fibre_direction", None),
    };
    let at = span.map_or_else(|| sf.at(b.kind.span()), |s| sf.at(s));
    let used: Vec<usize> = surf
        .base
        .quads
        .iter()
        .chain(&surf.base.tris)
        .copied()
        .collect();
    let first = nalgebra::Vector3::from(surf.base.normals[used[0]]);
    let mut plane = true;
    for &i in &used {
        let n = nalgebra::Vector3::from(surf.base.normals[i]);
        plane &= (n - first).norm() < 1e-12;
        // within about 6 degrees of the normal: no direction along the surface
        if reference.frame(n, 0.1).is_none() {
            bail!(
                "{at}: key `laminate.base.{key}`: {:?} is (nearly) normal to the base surface at its node {} (normal {:?}), so it gives no fibre direction there; give a direction along the surface{}",
                match reference { InPlaneReference::Fibre(r) | InPlaneReference::Transverse(r) => r },
                i + 1,
                surf.base.normals[i],
                if key == "fibre_direction" { ", or `transverse_direction` (a cylinder's axis)" } else { "" }
            );
        }
    }
    Ok(SurfaceFrame {
        reference,
        plane: reference.frame(first, 0.1),
        field: (!plane).then(|| {
            Arc::new(normal_field::SurfaceNormals::new(
                &surf.mesh, &surf.base, thickness,
            ))
        }),
        at: surf.mesh.nodes[used[0]],
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn layup(laminate: &str) -> Result<Layup> {
        let text = format!(
            "[materials.cf]\ntype = \"isotropic\"\nE = 1.0\nnu = 0.3\n[laws.cz]\ntype = \"linear_penalty\"\nd = 1.0\n[laws.cz2]\ntype = \"linear_penalty\"\nd = 2.0\n[laminate]\nbase = {{ type = \"rectangle\", size = [1.0, 1.0], divisions = [1, 1] }}\nelement = \"h8\"\nmaterial = \"cf\"\nply_thickness = 0.1\n{laminate}"
        );
        let sf = SceneFile::parse(std::path::Path::new("lam.toml"), text).unwrap();
        let spec = sf.scene.laminate.as_ref().unwrap();
        Layup::resolve(&sf, spec)
    }

    #[test]
    fn blocks_merge_same_angles_and_interfaces_follow_them() {
        let l = layup("layup = \"[0/90_2/45]s\"\ninterface_law = \"cz\"").unwrap();
        // 0 / 90 90 / 45 45 / 90 90 / 0
        assert_eq!(l.plies.len(), 8);
        assert_eq!(l.blocks, vec![0..1, 1..3, 3..5, 5..7, 7..8]);
        let below: Vec<usize> = l.interfaces.iter().map(|f| f.below).collect();
        assert_eq!(below, [1, 3, 5, 7]);
        assert_eq!(l.interfaces[0].name(), "interface_1_2");
        let all = layup("layup = \"[0/90_2/45]s\"\ninterface_law = \"cz\"\ninterfaces = \"all\"")
            .unwrap();
        assert_eq!(all.interfaces.len(), 7);
        let unmerged =
            layup("layup = \"[0/90_2/45]s\"\ninterface_law = \"cz\"\nmerge_plies = false").unwrap();
        assert_eq!(unmerged.blocks.len(), 8);
        assert_eq!(unmerged.interfaces.len(), 7);
        let none = layup("layup = \"[0/90]s\"").unwrap();
        assert!(none.interfaces.is_empty());
    }

    #[test]
    fn laws_by_position_and_by_angles() {
        let l = layup(
            "layup = \"[0/90/45/-45]\"\ninterface_law = \"cz\"\n[[laminate.interface_laws]]\nangles = [-45, 45]\nlaw = \"cz2\"\n[[laminate.interface_laws]]\nat = 1\nlaw = \"cz2\"",
        )
        .unwrap();
        let laws: Vec<&str> = l.interfaces.iter().map(|f| f.law.as_str()).collect();
        assert_eq!(laws, ["cz2", "cz", "cz2"]);
        let listed =
            layup("layup = \"[0/90/45/-45]\"\ninterface_law = \"cz\"\ninterfaces = [3, 1]")
                .unwrap();
        let below: Vec<usize> = listed.interfaces.iter().map(|f| f.below).collect();
        assert_eq!(below, [1, 3]);
        // 180 degrees apart is the same fibre direction: one block
        let same = layup("layup = \"[90/-90]\"\ninterface_law = \"cz\"").unwrap();
        assert_eq!(same.blocks.len(), 1);
    }

    #[test]
    fn mistakes_name_the_key() {
        for (lam, says) in [
            (
                "layup = \"[0/90]\"\ninterfaces = [2]\ninterface_law = \"cz\"",
                "ply 2 has no ply above",
            ),
            (
                "layup = \"[0/90]\"\ninterfaces = \"every\"",
                "`every` is not valid",
            ),
            ("layup = \"[0/90]\"\ninterfaces = \"all\"", "has no law"),
            (
                "layup = \"[0/90]\"\ninterface_law = \"glue\"",
                "unknown law `glue`",
            ),
            ("layup = \"[0/9O]\"", "laminate.layup"),
            ("", "is required"),
            (
                "layup = \"[0]\"\n[[laminate.plies]]\nangle = 0",
                "both given",
            ),
            (
                "[[laminate.plies]]\nangle = 0\nmaterial = \"steel\"",
                "unknown ply material `steel`",
            ),
            (
                "[[laminate.plies]]\nangle = 0\nthickness = -1",
                "not a positive thickness",
            ),
        ] {
            let e = layup(lam).unwrap_err().to_string();
            assert!(e.contains(says), "{lam}: {e}");
            assert!(e.contains("lam.toml"), "{e}");
        }
    }
}
