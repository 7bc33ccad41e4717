//! Mesh advice for softening interfaces: how long the cohesive (process)
//! zone is, how many interface elements span it, and what strength would
//! make a coarse mesh adequate.
//!
//! # Lengths
//!
//! For a law with strength `tau_0` and toughness `G_c` (mode I: `N`,
//! `G_Ic`; mode II: `S`, `G_IIc`), between solids of Young's modulus `E_n`
//! across the interface (the transverse modulus `E_22` of a laminate):
//!
//! ```text
//! bulk         l_cz = M E_n G_c / tau_0^2        M = 1 (Hillerborg), 0.88 (Rice / Falk), 0.21 (Hui)
//! slender arm  l_cz = (E_x G_c / tau_0^2)^(1/4) h^(3/4)               (Yang & Cox 2005; Harper & Hallett 2008)
//! ```
//!
//! where `E_x` is the modulus along the crack direction (the fibres of a
//! laminate arm) and `h` the thickness of the thinner body on either side.
//! The bulk form is the limit of a thick body, the slender form that of a
//! thin arm; the zone is about the shorter of the two, with Rice's constant
//! (BENCHMARKS.md section 4). The advice takes the shorter over modes I
//! and II.
//!
//! # Elements in the zone
//!
//! `N_e = l_cz / l_e` with `l_e` the length of the interface elements. The
//! crack direction is not known beforehand: `l_e` is each element's shorter
//! in-plane side (for the long thin elements of a beam model meshed with
//! one element across its width, the side along the beam; for a triangle
//! (INTER6 / INTER12) its shortest edge, which for the two triangles of a
//! cut rectangle is the rectangle's shorter side, as for the quadrilateral
//! it replaces), and the verdict
//! uses the coarsest element *where the crack will run* ([`CrackRegion`]).
//! Fewer than 3 elements: too coarse (peak loads overshoot and the
//! load-displacement curve saw-tooths); 3 to 5: adequate; 5 or more: fine.
//!
//! # Where the crack will run
//!
//! A crack starts at the initial front: the boundary edges of the interface
//! block beyond which a solid element sharing the edge's nodes goes on
//! (the precrack of a DCB, ENF or MMB, free or in contact, or the end of
//! an overlap), not the edges where the solids end too (the specimen's
//! sides and far end). The mesh is judged on the interface elements with a
//! corner within [`REGION_ZONES`] cohesive-zone lengths of such an edge:
//! the bond the crack runs into first, where a coarse far field that no
//! crack reaches does not matter. An interface with no such edge (bonded
//! all round) is judged on all its elements, as before.
//!
//! # Turon's strength reduction
//!
//! For a mesh that is too coarse, Turon, Davila, Camanho & Costa (2007)
//! lower the strength until the zone spans `N_e` elements of length `l_e`:
//!
//! ```text
//! tau_0' = sqrt( 9 pi E_n G_c / (32 N_e l_e) )       (here with N_e = 3)
//! ```
//!
//! which keeps the toughness (so the propagation load) and widens the zone.
//!
//! # Geometry read from the model
//!
//! `E_n`: the directional modulus of the solid touching the interface
//! along the element normal; `E_x`: along the shorter in-plane side; `h`:
//! the extent along the normal of the solid elements reachable from each
//! side without crossing the interface (for a body that is connected to the
//! other side elsewhere this is the whole model's thickness, and the
//! slender length is then an overestimate).

use junta_core::{CoreError, FractureProperties, Model};
use std::collections::VecDeque;

/// Verdict on the mesh of a softening interface.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MeshVerdict {
    /// Fewer than 3 elements in the cohesive zone.
    TooCoarse,
    /// 3 to 5 elements.
    Adequate,
    /// 5 or more.
    Fine,
}

impl MeshVerdict {
    /// Name for summaries.
    pub fn name(self) -> &'static str {
        match self {
            MeshVerdict::TooCoarse => "too coarse",
            MeshVerdict::Adequate => "adequate",
            MeshVerdict::Fine => "fine",
        }
    }
}

/// Cohesive-zone lengths of one mode.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ZoneLengths {
    /// Strength of the mode.
    pub strength: f64,
    /// Toughness of the mode.
    pub toughness: f64,
    /// Bulk length with Hillerborg's M = 1.
    pub hillerborg: f64,
    /// Bulk length with Rice's M = 0.88.
    pub rice: f64,
    /// Bulk length with Hui's M = 0.21.
    pub hui: f64,
    /// Slender-arm length.
    pub slender: f64,
    /// The estimate used: min(Rice, slender).
    pub length: f64,
    /// Turon's strength that puts 3 coarsest elements in the zone.
    pub reduced_strength: f64,
}

/// The interface elements within this many cohesive-zone lengths of the
/// initial front are where the mesh is judged.
pub const REGION_ZONES: f64 = 3.0;

/// Where the crack will run: the interface elements near the initial front
/// (see the module documentation).
#[derive(Debug, Clone, PartialEq)]
pub struct CrackRegion {
    /// Boundary edges of the interface that are on the initial front.
    pub front_edges: usize,
    /// Distance from the front within which elements count:
    /// [`REGION_ZONES`] cohesive-zone lengths.
    pub radius: f64,
    /// Interface elements within it.
    pub elements: usize,
    /// Shorter in-plane side of the finest of them.
    pub element_length_min: f64,
    /// Shorter in-plane side of the coarsest of them.
    pub element_length_max: f64,
}

/// The advice for one interface block.
#[derive(Debug, Clone, PartialEq)]
pub struct CohesiveZoneAdvice {
    /// Block name.
    pub block: String,
    /// Modulus across the interface.
    pub modulus_normal: f64,
    /// Modulus along the (assumed) crack direction.
    pub modulus_along: f64,
    /// Thickness of the thinner body on either side.
    pub arm_thickness: f64,
    /// Shorter in-plane side of the finest element.
    pub element_length_min: f64,
    /// Shorter in-plane side of the coarsest element.
    pub element_length_max: f64,
    /// Mode I zone lengths (normal strength `N`, toughness `G_Ic`).
    pub mode_i: ZoneLengths,
    /// Mode II zone lengths (shear strength `S`, toughness `G_IIc`).
    pub mode_ii: ZoneLengths,
    /// The shorter zone of the two modes.
    pub length: f64,
    /// Where the crack will run, when the interface has an initial front
    /// (`None`: the whole interface is judged).
    pub crack_region: Option<CrackRegion>,
    /// Coarsest elements (of the crack region, else of the interface)
    /// spanning it.
    pub elements_in_zone: f64,
    /// Verdict.
    pub verdict: MeshVerdict,
}

impl CohesiveZoneAdvice {
    /// One-paragraph text for `junta check`.
    pub fn message(&self) -> String {
        let region = match &self.crack_region {
            Some(r) => format!(
                "; where the crack runs ({} elements within {:.3e} of the initial front): {:.3e} .. {:.3e} long",
                r.elements, r.radius, r.element_length_min, r.element_length_max
            ),
            None => String::new(),
        };
        let mut s = format!(
            "interface `{}`: cohesive zone about {:.3e} long (mode I {:.3e}, mode II {:.3e}; Rice bulk {:.3e} / slender arm {:.3e} for mode I, E_n = {:.4e}, E_along = {:.4e}, arm thickness {:.4e}); interface elements {:.3e} .. {:.3e} long{region}: {:.1} of the coarsest span it: {}",
            self.block,
            self.length,
            self.mode_i.length,
            self.mode_ii.length,
            self.mode_i.rice,
            self.mode_i.slender,
            self.modulus_normal,
            self.modulus_along,
            self.arm_thickness,
            self.element_length_min,
            self.element_length_max,
            self.elements_in_zone,
            self.verdict.name()
        );
        if self.verdict == MeshVerdict::TooCoarse {
            s += &format!(
                " (at least 3 needed: refine to elements of {:.3e} or shorter, or lower the strengths to Turon's N' = {:.4e}, S' = {:.4e})",
                self.length / 3.0,
                self.mode_i.reduced_strength,
                self.mode_ii.reduced_strength
            );
        }
        s
    }
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn norm(a: [f64; 3]) -> f64 {
    dot(a, a).sqrt()
}
fn unit(a: [f64; 3]) -> [f64; 3] {
    let n = norm(a);
    [a[0] / n, a[1] / n, a[2] / n]
}
fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// Lengths of one mode (see the module documentation).
pub fn zone_lengths(
    strength: f64,
    toughness: f64,
    e_n: f64,
    e_x: f64,
    h: f64,
    l_e: f64,
) -> ZoneLengths {
    let bulk = e_n * toughness / (strength * strength);
    let slender = (e_x * toughness / (strength * strength)).powf(0.25) * h.powf(0.75);
    let rice = 0.88 * bulk;
    ZoneLengths {
        strength,
        toughness,
        hillerborg: bulk,
        rice,
        hui: 0.21 * bulk,
        slender,
        length: rice.min(slender),
        reduced_strength: (9.0 * std::f64::consts::PI * e_n * toughness / (32.0 * 3.0 * l_e))
            .sqrt(),
    }
}

/// The solids beside an interface block, as the advisors read them from
/// the model (see "Geometry read from the model" in the module
/// documentation).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AdjacentSolids {
    /// Unit normal of the coarsest interface element.
    pub normal: [f64; 3],
    /// Unit direction of its shorter in-plane side.
    pub along: [f64; 3],
    /// Shorter in-plane side of the finest element.
    pub element_length_min: f64,
    /// Shorter in-plane side of the coarsest element.
    pub element_length_max: f64,
    /// Modulus across the interface `E_n` (the smaller of the two sides).
    pub modulus_normal: f64,
    /// Modulus along the (assumed) crack direction.
    pub modulus_along: f64,
    /// Thickness `h` of the thinner body on either side (infinite when
    /// neither side has an extent along the normal).
    pub arm_thickness: f64,
}

/// The solids beside interface block `block` of `model`, or `None` for an
/// empty block. An error when no solid element touches the interface.
pub fn adjacent_solids(model: &Model, block: usize) -> Result<Option<AdjacentSolids>, CoreError> {
    let mesh = &model.mesh;
    let b = mesh
        .blocks
        .get(block)
        .ok_or_else(|| CoreError::Invalid(format!("no block {block}")))?;
    if b.is_empty() {
        return Ok(None);
    }
    // element sizes and the normal / along directions of the coarsest one
    let (mut l_min, mut l_max) = (f64::INFINITY, 0.0f64);
    let mut normal = [0.0, 0.0, 1.0];
    let mut along = [1.0, 0.0, 0.0];
    for e in 0..b.len() {
        let nodes = b.element(e);
        let x = |a: usize| mesh.nodes[nodes[a]];
        if is_line(b) {
            // a line interface (2D): its bottom line, normal e_z x t
            let e01 = sub(x(1), x(0));
            let l = norm(e01);
            l_min = l_min.min(l);
            if l > l_max {
                l_max = l;
                along = unit(e01);
                normal = [-along[1], along[0], 0.0];
            }
            continue;
        }
        if b.shape.face_shape().is_some_and(|f| f.num_corners() == 3) {
            // triangle: corners 0..2 of the bottom face
            let (e01, e02, e12) = (sub(x(1), x(0)), sub(x(2), x(0)), sub(x(2), x(1)));
            let edge = *[e01, e02, e12]
                .iter()
                .min_by(|a, b| norm(**a).total_cmp(&norm(**b)))
                .expect("three edges");
            let short = norm(edge);
            l_min = l_min.min(short);
            if short > l_max {
                l_max = short;
                normal = unit(cross(e01, e02));
                along = unit(edge);
            }
            continue;
        }
        // corners 0..3 of the bottom face
        let e01 = sub(x(1), x(0));
        let e32 = sub(x(2), x(3));
        let e03 = sub(x(3), x(0));
        let e12 = sub(x(2), x(1));
        let l_xi = 0.5 * (norm(e01) + norm(e32));
        let l_eta = 0.5 * (norm(e03) + norm(e12));
        let short = l_xi.min(l_eta);
        l_min = l_min.min(short);
        if short > l_max {
            l_max = short;
            normal = unit(cross(e01, e03));
            along = unit(if l_xi <= l_eta { e01 } else { e03 });
        }
    }
    // solid elements on each side: flood from the interface nodes
    let nn = mesh.nodes.len();
    let mut node_elems: Vec<Vec<(usize, usize)>> = vec![Vec::new(); nn];
    for (bi, sb) in mesh.blocks.iter().enumerate() {
        if sb.shape.is_interface() {
            continue;
        }
        for e in 0..sb.len() {
            for &n in sb.element(e) {
                node_elems[n].push((bi, e));
            }
        }
    }
    let side_extent = |start: &mut dyn Iterator<Item = usize>| -> (f64, Option<f64>) {
        let mut seen_el = std::collections::HashSet::new();
        let mut seen_node = vec![false; nn];
        let mut queue: VecDeque<usize> = VecDeque::new();
        for n in start {
            if !seen_node[n] {
                seen_node[n] = true;
                queue.push_back(n);
            }
        }
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        let mut modulus = None;
        while let Some(n) = queue.pop_front() {
            let z = dot(mesh.nodes[n], normal);
            lo = lo.min(z);
            hi = hi.max(z);
            for &(bi, e) in &node_elems[n] {
                if seen_el.insert((bi, e)) {
                    if modulus.is_none() {
                        modulus = Some((bi, e));
                    }
                    for &k in mesh.blocks[bi].element(e) {
                        if !seen_node[k] {
                            seen_node[k] = true;
                            queue.push_back(k);
                        }
                    }
                }
            }
        }
        let e_n = modulus.and_then(|(bi, _)| model.elements[bi].directional_modulus(normal));
        ((hi - lo).max(0.0), e_n)
    };
    let m = b.nodes_per_element() / 2;
    let (h_bot, e_bot) =
        side_extent(&mut (0..b.len()).flat_map(|e| b.element(e)[..m].iter().copied()));
    let (h_top, e_top) =
        side_extent(&mut (0..b.len()).flat_map(|e| b.element(e)[m..].iter().copied()));
    let h = match (h_bot > 0.0, h_top > 0.0) {
        (true, true) => h_bot.min(h_top),
        (true, false) => h_bot,
        (false, true) => h_top,
        _ => f64::INFINITY,
    };
    let e_n = match (e_bot, e_top) {
        (Some(a), Some(b)) => a.min(b),
        (Some(a), None) | (None, Some(a)) => a,
        (None, None) => {
            return Err(CoreError::Invalid(format!(
                "interface `{}`: no solid element touches it, so the advisors have no modulus",
                b.name
            )))
        }
    };
    // modulus along the crack direction: from the same solids
    let e_x = mesh
        .blocks
        .iter()
        .enumerate()
        .filter(|(_, sb)| !sb.shape.is_interface())
        .filter_map(|(bi, _)| model.elements[bi].directional_modulus(along))
        .fold(0.0f64, f64::max);
    let e_x = if e_x > 0.0 { e_x } else { e_n };
    Ok(Some(AdjacentSolids {
        normal,
        along,
        element_length_min: l_min,
        element_length_max: l_max,
        modulus_normal: e_n,
        modulus_along: e_x,
        arm_thickness: h,
    }))
}

/// Advice for interface block `block` of `model`, or `None` if its law
/// does not soften (no fracture properties).
pub fn cohesive_zone_advice(
    model: &Model,
    block: usize,
) -> Result<Option<CohesiveZoneAdvice>, CoreError> {
    let b = model
        .mesh
        .blocks
        .get(block)
        .ok_or_else(|| CoreError::Invalid(format!("no block {block}")))?;
    let Some(FractureProperties {
        strength_normal,
        strength_shear,
        toughness_mode_i,
        toughness_mode_ii,
        ..
    }) = model.elements[block].fracture_properties()
    else {
        return Ok(None);
    };
    let Some(AdjacentSolids {
        element_length_min: l_min,
        element_length_max: l_max,
        modulus_normal: e_n,
        modulus_along: e_x,
        arm_thickness: h,
        ..
    }) = adjacent_solids(model, block)?
    else {
        return Ok(None);
    };
    // the zone's length does not depend on the element length
    let length = zone_lengths(strength_normal, toughness_mode_i, e_n, e_x, h, l_max)
        .length
        .min(zone_lengths(strength_shear, toughness_mode_ii, e_n, e_x, h, l_max).length);
    let crack_region = crack_region(model, block, REGION_ZONES * length);
    let l_judged = crack_region
        .as_ref()
        .map_or(l_max, |r| r.element_length_max);
    let mode_i = zone_lengths(strength_normal, toughness_mode_i, e_n, e_x, h, l_judged);
    let mode_ii = zone_lengths(strength_shear, toughness_mode_ii, e_n, e_x, h, l_judged);
    let elements_in_zone = length / l_judged;
    let verdict = if elements_in_zone < 3.0 {
        MeshVerdict::TooCoarse
    } else if elements_in_zone < 5.0 {
        MeshVerdict::Adequate
    } else {
        MeshVerdict::Fine
    };
    Ok(Some(CohesiveZoneAdvice {
        block: b.name.clone(),
        modulus_normal: e_n,
        modulus_along: e_x,
        arm_thickness: h,
        element_length_min: l_min,
        element_length_max: l_max,
        mode_i,
        mode_ii,
        length,
        crack_region,
        elements_in_zone,
        verdict,
    }))
}

/// Whether interface block `b` is a line interface (2D).
fn is_line(b: &junta_core::mesh::ElementBlock) -> bool {
    b.shape.face_shape().is_some_and(|f| f.num_corners() == 2)
}

/// Shorter in-plane side of element `e` of interface block `b` (the
/// rule of the module documentation; a line interface's length), and its
/// bottom-face corners.
fn short_side(
    mesh: &junta_core::mesh::Mesh,
    b: &junta_core::mesh::ElementBlock,
    e: usize,
) -> (f64, usize) {
    let nodes = b.element(e);
    let x = |a: usize| mesh.nodes[nodes[a]];
    if is_line(b) {
        return (norm(sub(x(1), x(0))), 2);
    }
    if b.shape.face_shape().is_some_and(|f| f.num_corners() == 3) {
        let l = [sub(x(1), x(0)), sub(x(2), x(0)), sub(x(2), x(1))]
            .iter()
            .map(|v| norm(*v))
            .fold(f64::INFINITY, f64::min);
        return (l, 3);
    }
    let l_xi = 0.5 * (norm(sub(x(1), x(0))) + norm(sub(x(2), x(3))));
    let l_eta = 0.5 * (norm(sub(x(3), x(0))) + norm(sub(x(2), x(1))));
    (l_xi.min(l_eta), 4)
}

/// Distance from point `p` to the segment `a`-`b`.
fn segment_distance(p: [f64; 3], a: [f64; 3], b: [f64; 3]) -> f64 {
    let ab = sub(b, a);
    let len2 = dot(ab, ab);
    let t = if len2 > 0.0 {
        (dot(sub(p, a), ab) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    norm(sub(
        p,
        [a[0] + t * ab[0], a[1] + t * ab[1], a[2] + t * ab[2]],
    ))
}

/// The initial front of interface block `block`: its boundary edges
/// (bottom-face corner pairs of one element only) beyond which a solid
/// element holding both edge nodes reaches (see the module documentation).
pub fn initial_front(model: &Model, block: usize) -> Vec<([f64; 3], [f64; 3])> {
    let mesh = &model.mesh;
    let Some(b) = mesh.blocks.get(block) else {
        return Vec::new();
    };
    // edges of the bottom faces, with the element they bound
    let mut edges: std::collections::HashMap<(usize, usize), (usize, usize)> =
        std::collections::HashMap::new();
    for e in 0..b.len() {
        let (_, corners) = short_side(mesh, b, e);
        let nodes = b.element(e);
        if is_line(b) {
            // a line's boundary is its end nodes: a front is a point (p, p)
            for &p in &nodes[..2] {
                edges.entry((p, p)).or_insert((e, 0)).1 += 1;
            }
            continue;
        }
        for a in 0..corners {
            let (p, q) = (nodes[a], nodes[(a + 1) % corners]);
            let key = (p.min(q), p.max(q));
            edges.entry(key).or_insert((e, 0)).1 += 1;
        }
    }
    let mut node_solids: std::collections::HashMap<usize, Vec<(usize, usize)>> =
        std::collections::HashMap::new();
    for (&(p, q), _) in edges.iter().filter(|(_, (_, n))| *n == 1) {
        node_solids.entry(p).or_default();
        node_solids.entry(q).or_default();
    }
    for (bi, sb) in mesh.blocks.iter().enumerate() {
        if !sb.shape.is_solid() {
            continue;
        }
        for e in 0..sb.len() {
            for &n in sb.element(e) {
                if let Some(v) = node_solids.get_mut(&n) {
                    v.push((bi, e));
                }
            }
        }
    }
    let mut front = Vec::new();
    for (&(p, q), &(e, _)) in edges.iter().filter(|(_, (_, n))| *n == 1) {
        let (xp, xq) = (mesh.nodes[p], mesh.nodes[q]);
        let mid = [
            0.5 * (xp[0] + xq[0]),
            0.5 * (xp[1] + xq[1]),
            0.5 * (xp[2] + xq[2]),
        ];
        let (side, corners) = short_side(mesh, b, e);
        let nodes = b.element(e);
        let mut c = [0.0; 3];
        for &n in &nodes[..corners] {
            for d in 0..3 {
                c[d] += mesh.nodes[n][d] / corners as f64;
            }
        }
        // outward in-plane direction: from the centroid, across the edge
        // (a line's end point: from the centroid to the point)
        let to_mid = sub(mid, c);
        let out = if p == q {
            to_mid
        } else {
            let t = unit(sub(xq, xp));
            let along = dot(to_mid, t);
            sub(to_mid, [along * t[0], along * t[1], along * t[2]])
        };
        if norm(out) == 0.0 {
            continue;
        }
        let out = unit(out);
        let tol = 1e-3 * side;
        let beyond = node_solids[&p]
            .iter()
            .filter(|s| node_solids[&q].contains(s))
            .any(|&(bi, se)| {
                mesh.blocks[bi]
                    .element(se)
                    .iter()
                    .any(|&n| dot(sub(mesh.nodes[n], mid), out) > tol)
            });
        if beyond {
            front.push((xp, xq));
        }
    }
    front
}

/// The interface elements of block `block` with a corner within `radius`
/// of its initial front ([`initial_front`]), or `None` when the interface
/// has no initial front.
pub fn crack_region(model: &Model, block: usize, radius: f64) -> Option<CrackRegion> {
    let front = initial_front(model, block);
    if front.is_empty() || !radius.is_finite() {
        return None;
    }
    let mesh = &model.mesh;
    let b = &mesh.blocks[block];
    let (mut n, mut l_min, mut l_max) = (0, f64::INFINITY, 0.0f64);
    for e in 0..b.len() {
        let (side, corners) = short_side(mesh, b, e);
        let near = b.element(e)[..corners].iter().any(|&k| {
            front
                .iter()
                .any(|&(a, c)| segment_distance(mesh.nodes[k], a, c) <= radius)
        });
        if near {
            n += 1;
            l_min = l_min.min(side);
            l_max = l_max.max(side);
        }
    }
    (n > 0).then_some(CrackRegion {
        front_edges: front.len(),
        radius,
        elements: n,
        element_length_min: l_min,
        element_length_max: l_max,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// AS4/PEEK mode I (BENCHMARKS.md section 4): E22 = 10.1 GPa,
    /// G_Ic = 0.969 N/mm, N = 80 MPa; arm h = 1.56 mm, E11 = 122.7 GPa.
    #[test]
    fn lengths_and_turon_strength_are_the_closed_forms() {
        let z = zone_lengths(80.0, 0.969, 10100.0, 122700.0, 1.56, 1.0);
        let bulk = 10100.0 * 0.969 / 6400.0;
        assert!((z.hillerborg - bulk).abs() < 1e-12);
        assert!((z.rice - 0.88 * bulk).abs() < 1e-12);
        assert!((z.hui - 0.21 * bulk).abs() < 1e-12);
        let slender = (122700.0 * 0.969 / 6400.0f64).powf(0.25) * 1.56f64.powf(0.75);
        assert!((z.slender - slender).abs() < 1e-12);
        assert_eq!(z.length, z.rice.min(z.slender));
        // Turon: the reduced strength puts exactly 3 elements of length 1
        // in Rice's zone (M = 9 pi / 32 ~ 0.88)
        let l_reduced =
            9.0 * std::f64::consts::PI / 32.0 * 10100.0 * 0.969 / z.reduced_strength.powi(2);
        assert!((l_reduced - 3.0).abs() < 1e-9, "{l_reduced}");
    }
}
