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
//! Per solid block of `h8` elements: its axis-aligned extents; a direction
//! is *thin* when the largest extent is at least [`SLENDERNESS`] times its
//! extent. The number of element layers through a thin direction is its
//! extent over the median extent of the block's elements along it
//! (rounded). A block with fewer than [`MIN_LAYERS`] layers through a thin
//! direction gets the warning (the thin direction with the fewest layers;
//! the element length is the median element extent along the block's
//! longest direction). The block is not known to bend (a bar in tension
//! does not lock): the warning says "if it bends". A beam cut into short
//! blocks, or a thin body not aligned with the axes, is not detected.
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

/// The thin `h8` blocks of `model` with fewer than [`MIN_LAYERS`] element
/// layers through their thickness.
pub fn thin_h8_blocks(model: &Model) -> Vec<ThinH8Block> {
    let mesh = &model.mesh;
    let mut out = Vec::new();
    for (bi, b) in mesh.blocks.iter().enumerate() {
        if model.elements[bi].key() != "h8" || b.is_empty() {
            continue;
        }
        let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
        let mut elem_extent: [Vec<f64>; 3] = Default::default();
        for e in 0..b.len() {
            let (mut elo, mut ehi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
            for &n in b.element(e) {
                for d in 0..3 {
                    let x = mesh.nodes[n][d];
                    elo[d] = elo[d].min(x);
                    ehi[d] = ehi[d].max(x);
                }
            }
            for d in 0..3 {
                lo[d] = lo[d].min(elo[d]);
                hi[d] = hi[d].max(ehi[d]);
                elem_extent[d].push(ehi[d] - elo[d]);
            }
        }
        let ext: Vec<f64> = (0..3).map(|d| hi[d] - lo[d]).collect();
        let long = (0..3)
            .max_by(|&a, &c| ext[a].total_cmp(&ext[c]))
            .unwrap_or(0);
        let mut worst: Option<(usize, usize)> = None;
        for d in 0..3 {
            if ext[d].is_nan() || ext[d] <= 0.0 || ext[long] < SLENDERNESS * ext[d] {
                continue;
            }
            let h = median(elem_extent[d].clone());
            if h.is_nan() || h <= 0.0 {
                continue;
            }
            let layers = ((ext[d] / h).round() as usize).max(1);
            if layers < MIN_LAYERS && worst.is_none_or(|(_, l)| layers < l) {
                worst = Some((d, layers));
            }
        }
        let Some((d, layers)) = worst else {
            continue;
        };
        let element_length = median(elem_extent[long].clone());
        out.push(ThinH8Block {
            block: b.name.clone(),
            direction: d,
            thickness: ext[d],
            layers,
            long_direction: long,
            element_length,
            stiffening: expected_stiffening(layers, element_length / ext[d]),
        });
    }
    out
}

/// The warnings of [`thin_h8_blocks`].
pub fn bending_warnings(model: &Model) -> Vec<String> {
    thin_h8_blocks(model).iter().map(|t| t.message()).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

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
