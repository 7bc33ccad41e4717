//! Shear locking of fully integrated H8 blocks in bending: a warning from
//! `junta check` and in the run summaries.
//!
//! A fully integrated trilinear hexahedron (`h8`) cannot bend without
//! parasitic transverse shear (its side stays straight, so pure bending
//! leaves it a shear strain that grows with the element's length), and
//! with one element through the thickness it cannot vary the transverse
//! normal strain either (Poisson stiffening). A thin block of `h8` is
//! therefore too stiff in bending. `h8i` (incompatible modes) on the same
//! mesh, or the quadratic `h20` / `h27`, do not lock.
//!
//! # Detection
//!
//! A block is judged as part of its *body*: the solid elements connected
//! to its elements through shared nodes (interface elements do not connect:
//! the two arms of a DCB are two bodies), so that a beam cut into short
//! blocks is judged as the beam. Per `h8` block: the axis-aligned extents
//! of its body; the body's *axis* is its longest direction, and a direction
//! across it is *thin* when the axis is at least [`SLENDERNESS`] times the
//! body's extent along it.
//!
//! A thin direction is judged only if the body *bends through it*: the
//! model is loaded along it ([`loaded_directions`]: a nonzero applied force
//! or a nonzero prescribed displacement with a component along it). A
//! model with no such load (a thermal load alone) bends through the body's
//! thinnest direction, whose bending stiffness (`~ w t^3`) is the least.
//! So a DCB 25 mm wide with one element across, opened along z, is judged
//! through its 1.56 mm arms (z) only, never across its width (y), and a bar
//! pulled along its axis gets no warning. A body with at least
//! [`HELD_SHARE`] of its nodes fixed in all directions is held along a face
//! (the substrate of a peel test, fixed on its base) and does not bend.
//!
//! The number of element layers through the bending direction is the
//! body's extent along it over the median extent of the block's elements
//! along it (rounded); fewer than [`MIN_LAYERS`] get the warning, with the
//! element length the median extent of the block's elements along the
//! body's axis. The model gets one warning ([`bending_warnings`]): the
//! numbers of the block that locks worst, and the other blocks it applies
//! to. A thin body not aligned with the axes is not detected.
//!
//! # The measured stiffening
//!
//! The cantilever of `examples/cantilever.toml` (steel, E = 2.1e11 Pa,
//! nu = 0.3, 1 m x 0.1 m x 0.1 m, clamped at x = 0, P = 1000 N as a shear
//! traction on x = 1; one element across the width) with `h8`, `n` elements
//! through the thickness and elements `l` long, against Timoshenko's
//! `delta = P L^3 / (3 E I) + P L / (kappa G A) = 1.920e-4 m` (kappa = 5/6).
//! The entry is how much too stiff the mesh is, `delta_Timoshenko /
//! delta_h8 - 1` (junta 0.1, `junta run`, `probes.x1` of `summary.json`):
//!
//! ```text
//! l / t           1.0      0.5      0.25     0.125    (divisions along x: 10, 20, 40, 80)
//! n = 1          55.6 %   26.1 %   18.7 %   16.8 %    (160 along x: 16.3 %)
//! n = 2          47.1 %   17.2 %    9.6 %    7.6 %
//! n = 3          45.1 %   15.2 %    7.5 %    5.5 %
//! n = 4          44.4 %   14.4 %    6.7 %    4.7 %
//! h8i            1.5 % (n = 1, 10 along x), 2.5 % (n = 2, 10), 2.6 % (n = 4, 10),
//!                1.3 % (n = 2, 20), 0.8 % (n = 2, 40), 0.7 % (n = 4, 40)
//! h20, 80 x 4 x 4 0.8 %  (the clamped root: the converged 3D answer)
//! ```
//!
//! At a fixed element length more layers help little (the parasitic shear
//! grows with `l`, not with the element's height); refining along the beam
//! leaves a floor that falls with the layers (Poisson stiffening: 16.8 %
//! with one layer, 4.7 % with four). The warning quotes the entry of the
//! block's `n` and `l / t`, interpolated in `log2(l / t)` and clamped to
//! the table. The table is for an isotropic material with nu = 0.3; a
//! laminate with a low transverse shear modulus (E_1 / G_13 ~ 20) locks
//! less in shear.
//!
//! The H8 DCB (`examples/delamination/dcb_h8.toml`, AS4/PEEK arms 1.56 mm
//! thick with E_1 / G_13 = 22, two elements through each arm, 0.5 mm long
//! along the first 35 mm of the bond, l / t = 0.32: "about 12 %" by the
//! table) with `viscosity = 1e-4`, `h8` against `h8i` on the same mesh:
//! 34.46 N against 33.57 N at an opening of 1 mm before the peak (2.7 %
//! stiffer; corrected beam theory 32.87 N), peaks 142.6 N and 142.4 N, and
//! on the propagation branch the locking is lost in the saw-tooth of the
//! coarse cohesive mesh (121.0 N and 122.6 N at 6 mm, beam theory 116.0 N;
//! there the load goes as (EI)^(1/4)). The laminate's low transverse shear
//! modulus keeps its parasitic shear energy small: the table is an upper
//! estimate for such arms.

use junta_core::Model;

/// A direction is thin when the block's largest extent is at least this
/// multiple of its extent along it.
pub const SLENDERNESS: f64 = 5.0;

/// Fewer element layers than this through a thin direction get the warning.
pub const MIN_LAYERS: usize = 4;

/// Element length over block thickness `l / t` of [`STIFFENING`]'s columns.
pub const LENGTH_RATIOS: [f64; 4] = [1.0, 0.5, 0.25, 0.125];

/// Measured stiffening (percent) of an `h8` cantilever with 1, 2, 3
/// layers (rows) at the element lengths of [`LENGTH_RATIOS`] (columns);
/// see the module documentation.
pub const STIFFENING: [[f64; 4]; 3] = [
    [55.6, 26.1, 18.7, 16.8],
    [47.1, 17.2, 9.6, 7.6],
    [45.1, 15.2, 7.5, 5.5],
];

/// The measured stiffening (percent) for `layers` (1 to 3) elements through
/// the thickness and elements `ratio` = l / t long, interpolated in
/// `log2(ratio)` between the columns of [`STIFFENING`] and clamped to them.
pub fn expected_stiffening(layers: usize, ratio: f64) -> f64 {
    let row = &STIFFENING[layers.clamp(1, 3) - 1];
    let x = -ratio.max(1e-300).log2(); // 0, 1, 2, 3 at the columns
    if x <= 0.0 {
        return row[0];
    }
    if x >= 3.0 {
        return row[3];
    }
    let i = x.floor() as usize;
    let f = x - i as f64;
    row[i] + f * (row[(i + 1).min(3)] - row[i])
}

/// A thin `h8` block with too few layers (see the module documentation).
#[derive(Debug, Clone, PartialEq)]
pub struct ThinH8Block {
    /// Block name.
    pub block: String,
    /// The thin direction (0, 1, 2 for x, y, z).
    pub direction: usize,
    /// The block's extent along it.
    pub thickness: f64,
    /// Element layers through it.
    pub layers: usize,
    /// The block's longest direction.
    pub long_direction: usize,
    /// Median element length along the longest direction.
    pub element_length: f64,
    /// Expected stiffening in bending, percent ([`expected_stiffening`]).
    pub stiffening: f64,
}

impl ThinH8Block {
    /// The warning.
    pub fn message(&self) -> String {
        let axis = ["x", "y", "z"];
        let ratio = self.element_length / self.thickness;
        let about = if ratio > LENGTH_RATIOS[0] {
            "at least"
        } else {
            "about"
        };
        format!(
            "block `{}`: fully integrated h8, {} element{} through its {:.4e} thickness ({}), \
             elements {:.4e} long ({}), l/t = {:.2}: if it bends, it locks (parasitic shear, \
             Poisson stiffening): {about} {:.0}% too stiff (measured on an isotropic h8 \
             cantilever with {} layer{} and this l/t against Timoshenko's beam; a laminate with a low \
             G_13 locks less: the H8 DCB of examples/delamination/dcb_h8.toml is 2.7% stiffer \
             than h8i before the peak); use element = \"h8i\" on this mesh (within 2.6% on that cantilever) or \"h20\"",
            self.block,
            self.layers,
            if self.layers == 1 { "" } else { "s" },
            self.thickness,
            axis[self.direction],
            self.element_length,
            axis[self.long_direction],
            ratio,
            self.stiffening,
            self.layers,
            if self.layers == 1 { "" } else { "s" },
        )
    }
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// The global directions (x, y, z) along which `model` is loaded: a
/// component of the applied forces, or of the nonzero prescribed
/// displacements, at least 1e-3 of the largest such component; `None` when
/// neither is (a thermal load alone, or no load).
pub fn loaded_directions(model: &Model) -> Option<[bool; 3]> {
    let (mut force, mut disp) = ([0.0f64; 3], [0.0f64; 3]);
    for (d, f) in model.f_ext.iter().enumerate() {
        force[d % 3] += f.abs();
    }
    for (d, &eq) in model.dofs.eq.iter().enumerate() {
        if eq == junta_core::dof::CONSTRAINED {
            disp[d % 3] += model.dofs.prescribed[d].abs();
        }
    }
    let fmax = force.iter().copied().fold(0.0, f64::max);
    let umax = disp.iter().copied().fold(0.0, f64::max);
    if !(fmax > 0.0 || umax > 0.0) {
        return None;
    }
    Some(std::array::from_fn(|c| {
        (fmax > 0.0 && force[c] >= 1e-3 * fmax) || (umax > 0.0 && disp[c] >= 1e-3 * umax)
    }))
}

/// The connected solid bodies of `model`: the body of every node (solid
/// elements sharing a node are one body; interface elements do not join),
/// `usize::MAX` for a node of no solid element.
fn solid_bodies(model: &Model) -> Vec<usize> {
    let mesh = &model.mesh;
    let mut parent: Vec<usize> = (0..mesh.nodes.len()).collect();
    fn root(parent: &mut [usize], mut a: usize) -> usize {
        while parent[a] != a {
            parent[a] = parent[parent[a]];
            a = parent[a];
        }
        a
    }
    let mut solid = vec![false; mesh.nodes.len()];
    for b in mesh.blocks.iter().filter(|b| b.shape.is_solid()) {
        for e in 0..b.len() {
            let nodes = b.element(e);
            for &n in nodes {
                solid[n] = true;
            }
            let r0 = root(&mut parent, nodes[0]);
            for &n in &nodes[1..] {
                let r = root(&mut parent, n);
                if r != r0 {
                    parent[r] = r0;
                }
            }
        }
    }
    (0..mesh.nodes.len())
        .map(|n| {
            if solid[n] {
                root(&mut parent, n)
            } else {
                usize::MAX
            }
        })
        .collect()
}

/// Axis-aligned bounding box of every body (indexed by its root node).
fn body_boxes(
    model: &Model,
    body: &[usize],
) -> std::collections::HashMap<usize, ([f64; 3], [f64; 3])> {
    let mut boxes = std::collections::HashMap::new();
    for (n, &r) in body.iter().enumerate() {
        if r == usize::MAX {
            continue;
        }
        let x = model.mesh.nodes[n];
        let (lo, hi) = boxes
            .entry(r)
            .or_insert(([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]));
        for d in 0..3 {
            lo[d] = lo[d].min(x[d]);
            hi[d] = hi[d].max(x[d]);
        }
    }
    boxes
}

/// A body with at least this share of its nodes fixed in every direction
/// is held along a face (a substrate on its base), not a beam: it does
/// not bend.
pub const HELD_SHARE: f64 = 0.25;

/// The bodies (roots of [`solid_bodies`]) with at least [`HELD_SHARE`] of
/// their nodes constrained in all three directions.
fn held_bodies(model: &Model, body: &[usize]) -> std::collections::HashSet<usize> {
    let mut count: std::collections::HashMap<usize, (usize, usize)> =
        std::collections::HashMap::new();
    for (n, &r) in body.iter().enumerate() {
        if r == usize::MAX {
            continue;
        }
        let fixed =
            (0..3).all(|c| model.dofs.eq.get(3 * n + c) == Some(&junta_core::dof::CONSTRAINED));
        let e = count.entry(r).or_default();
        e.0 += 1;
        e.1 += usize::from(fixed);
    }
    count
        .into_iter()
        .filter(|(_, (all, fixed))| *fixed as f64 >= HELD_SHARE * *all as f64)
        .map(|(r, _)| r)
        .collect()
}

/// The thin `h8` blocks of `model` with fewer than [`MIN_LAYERS`] element
/// layers through the direction their body bends in (see the module
/// documentation).
pub fn thin_h8_blocks(model: &Model) -> Vec<ThinH8Block> {
    let mesh = &model.mesh;
    let loaded = loaded_directions(model);
    let body = solid_bodies(model);
    let boxes = body_boxes(model, &body);
    let held = held_bodies(model, &body);
    let mut out = Vec::new();
    for (bi, b) in mesh.blocks.iter().enumerate() {
        if model.elements[bi].key() != "h8" || b.is_empty() || held.contains(&body[b.element(0)[0]])
        {
            continue;
        }
        // the block's bodies (usually one) and its element extents
        let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
        let mut elem_extent: [Vec<f64>; 3] = Default::default();
        for e in 0..b.len() {
            let nodes = b.element(e);
            if let Some((blo, bhi)) = boxes.get(&body[nodes[0]]) {
                for d in 0..3 {
                    lo[d] = lo[d].min(blo[d]);
                    hi[d] = hi[d].max(bhi[d]);
                }
            }
            for (d, ext) in elem_extent.iter_mut().enumerate() {
                let xs = nodes.iter().map(|&n| mesh.nodes[n][d]);
                let (a, c) = xs.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, c), x| {
                    (a.min(x), c.max(x))
                });
                ext.push(c - a);
            }
        }
        if let Some(t) = thin_block(b.name.clone(), &lo, &hi, &elem_extent, loaded) {
            out.push(t);
        }
    }
    out
}

/// The verdict on one `h8` block of a body spanning `lo..hi`, its elements'
/// extents along each direction, and the model's loaded directions.
fn thin_block(
    block: String,
    lo: &[f64; 3],
    hi: &[f64; 3],
    elem_extent: &[Vec<f64>; 3],
    loaded: Option<[bool; 3]>,
) -> Option<ThinH8Block> {
    let ext: [f64; 3] = std::array::from_fn(|d| hi[d] - lo[d]);
    if ext.iter().any(|e| !e.is_finite()) {
        return None;
    }
    let long = (0..3).max_by(|&a, &c| ext[a].total_cmp(&ext[c]))?;
    let thin = |d: usize| d != long && ext[d] > 0.0 && ext[long] >= SLENDERNESS * ext[d];
    // the direction it bends through: a loaded thin one, else the thinnest
    let bends = |d: usize| match loaded {
        Some(l) => l[d],
        None => {
            (0..3)
                .filter(|&c| c != long)
                .min_by(|&a, &c| ext[a].total_cmp(&ext[c]))
                == Some(d)
        }
    };
    let mut worst: Option<(usize, usize)> = None;
    for d in (0..3).filter(|&d| thin(d) && bends(d)) {
        let h = median(elem_extent[d].clone());
        if h.is_nan() || h <= 0.0 {
            continue;
        }
        let layers = ((ext[d] / h).round() as usize).max(1);
        if layers < MIN_LAYERS && worst.is_none_or(|(_, l)| layers < l) {
            worst = Some((d, layers));
        }
    }
    let (d, layers) = worst?;
    let element_length = median(elem_extent[long].clone());
    Some(ThinH8Block {
        block,
        direction: d,
        thickness: ext[d],
        layers,
        long_direction: long,
        element_length,
        stiffening: expected_stiffening(layers, element_length / ext[d]),
    })
}

/// The model's one locking warning ([`locking_warning`] of
/// [`thin_h8_blocks`]), or none.
pub fn bending_warnings(model: &Model) -> Vec<String> {
    locking_warning(&thin_h8_blocks(model))
        .into_iter()
        .collect()
}

/// One warning for all `blocks`: the numbers of the block that locks worst
/// (the largest expected stiffening), then the other blocks with theirs.
pub fn locking_warning(blocks: &[ThinH8Block]) -> Option<String> {
    // the first of equals (`max_by` keeps the last)
    let worst = blocks
        .iter()
        .rev()
        .max_by(|a, b| a.stiffening.total_cmp(&b.stiffening))?;
    let mut s = worst.message();
    let others: Vec<String> = blocks
        .iter()
        .filter(|b| b.block != worst.block)
        .map(|b| format!("`{}` ({:.0}%)", b.block, b.stiffening))
        .collect();
    if !others.is_empty() {
        s += &format!(
            "; also bent through too few layers: block{} {}",
            if others.len() == 1 { "" } else { "s" },
            others.join(", ")
        );
    }
    Some(s)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A DCB arm 150 x 25.4 x 1.56 with one element across its width and
    /// two through its thickness, elements 0.5 long: opened along z it is
    /// judged through z only (2 layers, l/t = 0.32); with no load known it
    /// bends through its thinnest direction (z); loaded along y (in its
    /// plane) it is thin across y (150 / 25.4 >= 5, one layer) and is judged
    /// there; pulled along its axis it gets nothing.
    #[test]
    fn the_bending_direction_is_the_loaded_one() {
        let (lo, hi) = ([0.0; 3], [150.0, 25.4, 1.56]);
        let ext = [vec![0.5; 3], vec![25.4; 3], vec![0.78; 3]];
        let z = thin_block("arm".into(), &lo, &hi, &ext, Some([false, false, true])).unwrap();
        assert_eq!((z.direction, z.layers, z.long_direction), (2, 2, 0));
        assert!((z.element_length - 0.5).abs() < 1e-15);
        let none = thin_block("arm".into(), &lo, &hi, &ext, None).unwrap();
        assert_eq!(none.direction, 2);
        let y = thin_block("arm".into(), &lo, &hi, &ext, Some([false, true, false])).unwrap();
        assert_eq!((y.direction, y.layers), (1, 1));
        assert!(thin_block("arm".into(), &lo, &hi, &ext, Some([true, false, false])).is_none());
    }

    /// One warning for several blocks: the worst one's numbers, the others
    /// named with theirs.
    #[test]
    fn one_warning_names_the_worst_block_and_the_others() {
        let block = |name: &str, stiffening: f64| ThinH8Block {
            block: name.into(),
            direction: 2,
            thickness: 1.0,
            layers: 2,
            long_direction: 0,
            element_length: 1.0,
            stiffening,
        };
        assert_eq!(locking_warning(&[]), None);
        let w = locking_warning(&[block("a", 12.0), block("b", 47.1), block("c", 47.1)]).unwrap();
        assert!(
            w.starts_with("block `b`:") && w.contains("47% too stiff"),
            "{w}"
        );
        assert!(w.ends_with("blocks `a` (12%), `c` (47%)"), "{w}");
    }

    #[test]
    fn stiffening_interpolates_the_table_and_clamps() {
        assert_eq!(expected_stiffening(2, 0.5), 17.2);
        assert_eq!(expected_stiffening(1, 4.0), 55.6);
        assert_eq!(expected_stiffening(3, 0.01), 5.5);
        // halfway in log2 between l/t = 0.5 and 0.25
        let r = 0.5 * 2f64.powf(-0.5);
        assert!((expected_stiffening(2, r) - 0.5 * (17.2 + 9.6)).abs() < 1e-12);
    }
}
