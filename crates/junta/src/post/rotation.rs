//! The largest rigid rotation of the solid elements of a converged state,
//! and the warning a small-strain run gives when it passes the rotation at
//! which its answer drifts ([`SMALL_STRAIN_ROTATION_LIMIT`]).
//!
//! Each solid element's rotation is the angle of the rotation factor of
//! the polar decomposition of its deformation gradient at its centre
//! ([`junta_elements::rotation::element_rotation`], which carries the
//! maths). Every run writes the largest one to `summary.json` as
//! `largest_rotation` (radians, degrees, block, element label, the
//! kinematics); a small-strain run adds the threshold and the ratio to it,
//! and past the threshold a warning that recommends `nlgeom`.
//!
//! `junta check` cannot know a rotation before the solve; it says what the
//! run will report ([`check_note`]).

use junta_core::{Kinematics, Model};
use junta_elements::rotation::element_rotation;
use serde::Serialize;
use serde_json::{json, Value};

/// The rotation (radians) past which a small-strain run is warned:
/// 0.147 rad (8.4 degrees), measured on a cantilever under a dead end
/// load, where the small-strain tip deflection is 1 % larger than the
/// large-deformation (`nlgeom`) one.
///
/// Measured with `junta` itself (test
/// `small_strain_drift_reaches_one_percent_at_the_rotation_limit` in
/// `crates/cli/tests/large_deformation.rs`, which keeps this figure
/// honest): a 100 x 2 x 2 H20 cantilever (20 x 1 x 1 elements, E = 1000,
/// nu = 0) under a dead end load, run with small strain and with
/// `nlgeom = true` at `P L^2 / EI` = 0.2, 0.3, 0.4. The small-strain
/// run's largest element rotation (by this measure: the centre of the tip
/// element) and the drift of its tip deflection above the `nlgeom` run's:
///
/// | `P L^2/EI` | largest rotation (small strain) | drift |
/// |---|---|---|
/// | 0.2 | 0.0996 rad (5.71 deg) | 0.456 % |
/// | 0.3 | 0.1488 rad (8.52 deg) | 1.021 % |
/// | 0.4 | 0.1972 rad (11.30 deg) | 1.804 % |
///
/// The drift grows with the square of the rotation (46 % per rad^2 at
/// all three loads), so 1 % is reached at 0.147 rad. The elastica gives
/// the same figure: the linear tip deflection `P L^3 / 3 EI` is 1 % above
/// the elastica's at `P L^2 / EI = 0.297`, a linear tip slope of 0.148.
/// It is a guide, not a bound: a DCB under an imposed opening drifts
/// about as fast (ASTM D5528's large-displacement factor `F` departs
/// from 1 by 1 % at an arm tip rotation of 0.137 rad), while a plate
/// whose deflection stretches its mid-plane (membrane stiffening) drifts
/// at smaller rotations.
pub const SMALL_STRAIN_ROTATION_LIMIT: f64 = 0.147;

/// What [`SMALL_STRAIN_ROTATION_LIMIT`] is the limit of, for messages.
pub const LIMIT_SOURCE: &str =
    "where a small-strain cantilever's tip deflection drifts by 1 % from the large-deformation answer";

/// The largest element rotation of a state.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LargestRotation {
    /// Angle in radians, in `[0, pi]`.
    pub radians: f64,
    /// The same in degrees.
    pub degrees: f64,
    /// The block of the element.
    pub block: String,
    /// The element's label (the input's own number, else the 1-based
    /// running number over the blocks).
    pub element: usize,
    /// The run's kinematics.
    pub kinematics: Kinematics,
    /// Small strain: [`SMALL_STRAIN_ROTATION_LIMIT`] (radians).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub threshold_radians: Option<f64>,
    /// Small strain: `radians / threshold_radians`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ratio: Option<f64>,
    /// Solid elements inverted (`det F <= 0` at the centre) and left out.
    pub inverted_elements: usize,
}

/// The model's kinematics: finite when any element is.
pub fn model_kinematics(model: &Model) -> Kinematics {
    if model
        .elements
        .iter()
        .any(|e| e.kinematics() == Kinematics::Finite)
    {
        Kinematics::Finite
    } else {
        Kinematics::Small
    }
}

/// The largest rotation over the solid elements of `model` at the nodal
/// displacements `u`; `None` without solid elements (or when every one is
/// inverted).
pub fn largest_rotation(model: &Model, u: &[f64]) -> Option<LargestRotation> {
    const MAX: usize = 27;
    let mesh = &model.mesh;
    let mut best: Option<(f64, usize, usize)> = None;
    let mut inverted = 0;
    let mut coords = [[0.0; 3]; MAX];
    let mut disp = [0.0; 3 * MAX];
    for (bi, b) in mesh.blocks.iter().enumerate() {
        let nn = b.nodes_per_element();
        if !b.shape.is_solid() || nn > MAX {
            continue;
        }
        for e in 0..b.len() {
            let mut ok = true;
            for (a, &n) in b.element(e).iter().enumerate() {
                coords[a] = mesh.nodes[n];
                match u.get(3 * n..3 * n + 3) {
                    Some(v) => disp[3 * a..3 * a + 3].copy_from_slice(v),
                    None => ok = false,
                }
            }
            if !ok {
                continue;
            }
            match element_rotation(b.shape, &coords[..nn], &disp[..3 * nn]) {
                Some(t) if best.map_or(true, |(m, _, _)| t > m) => best = Some((t, bi, e)),
                Some(_) => {}
                None => inverted += 1,
            }
        }
    }
    let (radians, bi, e) = best?;
    let kinematics = model_kinematics(model);
    let small = kinematics == Kinematics::Small;
    Some(LargestRotation {
        radians,
        degrees: radians.to_degrees(),
        block: mesh.blocks[bi].name.clone(),
        element: mesh.element_label(bi, e),
        kinematics,
        threshold_radians: small.then_some(SMALL_STRAIN_ROTATION_LIMIT),
        ratio: small.then_some(radians / SMALL_STRAIN_ROTATION_LIMIT),
        inverted_elements: inverted,
    })
}

/// The switch that turns on large deformation for the input kind.
fn nlgeom_switch(deck: bool) -> &'static str {
    if deck {
        "`*STEP, NLGEOM`"
    } else {
        "`[analysis] nlgeom = true`"
    }
}

impl LargestRotation {
    /// The warning of a small-strain run past the threshold (`deck`: the
    /// input is an Abaqus/CalculiX deck), else `None`.
    pub fn warning(&self, deck: bool) -> Option<String> {
        let ratio = self.ratio?;
        (ratio > 1.0).then(|| {
            format!(
                "small strain: the largest element rotation is {:.3} rad ({:.1} degrees; block `{}`, element {}), {:.2} times the {:.3} rad ({:.1} degrees) {}; the answer is not to be trusted: rerun with {}",
                self.radians,
                self.degrees,
                self.block,
                self.element,
                ratio,
                SMALL_STRAIN_ROTATION_LIMIT,
                SMALL_STRAIN_ROTATION_LIMIT.to_degrees(),
                LIMIT_SOURCE,
                nlgeom_switch(deck)
            )
        })
    }
}

/// Whether `input` is a deck (`.inp`), for the switch a message names.
pub fn is_deck(input: &std::path::Path) -> bool {
    input
        .extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("inp"))
}

/// `summary["largest_rotation"]` of the state `u` (null without solids),
/// and the warning of a small-strain run past the threshold.
pub fn summary_entry(model: &Model, u: &[f64], deck: bool) -> (Value, Option<String>) {
    match largest_rotation(model, u) {
        Some(r) => {
            let w = r.warning(deck);
            (json!(r), w)
        }
        None => (Value::Null, None),
    }
}

/// What `junta check` says about rotations: it cannot measure one before
/// the solve, so it says what the run reports and when it warns.
pub fn check_note(model: &Model, deck: bool) -> Option<String> {
    if !model.mesh.blocks.iter().any(|b| b.shape.is_solid()) {
        return None;
    }
    Some(match model_kinematics(model) {
        Kinematics::Small => format!(
            "small strain: the run reports its largest element rotation (summary.json `largest_rotation`) and warns past {:.3} rad ({:.1} degrees), {}; a run that rotates further needs {}",
            SMALL_STRAIN_ROTATION_LIMIT,
            SMALL_STRAIN_ROTATION_LIMIT.to_degrees(),
            LIMIT_SOURCE,
            nlgeom_switch(deck)
        ),
        Kinematics::Finite => "large deformation (nlgeom): total-Lagrangian solids, interfaces framed on their current mid-surface; the run reports its largest element rotation (summary.json `largest_rotation`)".to_string(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use junta_core::mesh::generate::{box_mesh, BoxSpec};
    use junta_core::topology::CellShape;
    use junta_core::Element;
    use junta_elements::{solid::Integration, Isotropic, SolidElement};
    use nalgebra::{Rotation3, Unit, Vector3};
    use std::sync::Arc;

    fn model(shape: CellShape, kinematics: Kinematics) -> Model {
        let key = shape.name().to_lowercase();
        let mesh = box_mesh(
            &BoxSpec::new([3.0, 1.0, 0.5], [3, 2, 2], shape),
            "b",
            &key,
            "m",
        )
        .unwrap();
        let mat = Arc::new(Isotropic::new(100.0, 0.3).unwrap());
        let el: Arc<dyn Element> = Arc::new(
            SolidElement::new(shape, Integration::Full, mat)
                .unwrap()
                .with_kinematics(kinematics),
        );
        let n = mesh.nodes.len();
        Model::new(mesh, vec![el], &[], vec![0.0; 3 * n], Vec::new()).unwrap()
    }

    /// A rigid rotation of the mesh by a known angle about a skew axis
    /// through a point gives that angle in every element, to 1e-12, under
    /// either kinematics; with a stretch on top as well.
    #[test]
    fn rigid_rotation_of_a_mesh_gives_its_angle() {
        for shape in [
            CellShape::Hex8,
            CellShape::Hex20,
            CellShape::Hex27,
            CellShape::Wedge6,
            CellShape::Wedge15,
        ] {
            for angle in [1e-4, 0.14, 0.16, 1.0, 2.5] {
                let m = model(shape, Kinematics::Small);
                let axis = Unit::new_normalize(Vector3::new(1.0, -2.0, 0.7));
                let r = Rotation3::from_axis_angle(&axis, angle);
                let c = Vector3::new(0.3, 0.2, -1.0);
                let mut u = vec![0.0; 3 * m.mesh.nodes.len()];
                for (i, x) in m.mesh.nodes.iter().enumerate() {
                    let x = Vector3::from(*x);
                    // stretched along x by 1.2, then turned
                    let y = r * (Vector3::new(1.2 * x[0], x[1], x[2]) - c) + c;
                    u[3 * i..3 * i + 3].copy_from_slice((y - x).as_slice());
                }
                let got = largest_rotation(&m, &u).unwrap();
                assert!(
                    (got.radians - angle).abs() < 1e-12,
                    "{shape:?} {angle}: {}",
                    got.radians
                );
                assert_eq!(got.inverted_elements, 0);
                assert_eq!(got.threshold_radians, Some(SMALL_STRAIN_ROTATION_LIMIT));
                assert!((got.ratio.unwrap() - angle / SMALL_STRAIN_ROTATION_LIMIT).abs() < 1e-9);
                assert_eq!(
                    got.warning(false).is_some(),
                    angle > SMALL_STRAIN_ROTATION_LIMIT
                );
            }
        }
    }

    /// Finite kinematics: the rotation without a ratio or a warning.
    #[test]
    fn finite_runs_report_no_ratio() {
        let m = model(CellShape::Hex8, Kinematics::Finite);
        let r = Rotation3::from_axis_angle(&Vector3::z_axis(), 0.5);
        let u: Vec<f64> = m
            .mesh
            .nodes
            .iter()
            .flat_map(|x| {
                let x = Vector3::from(*x);
                (r * x - x).iter().copied().collect::<Vec<_>>()
            })
            .collect();
        let got = largest_rotation(&m, &u).unwrap();
        assert!((got.radians - 0.5).abs() < 1e-12);
        assert_eq!(got.kinematics, Kinematics::Finite);
        assert!(got.ratio.is_none() && got.warning(false).is_none());
        let v = json!(got);
        assert!(v.get("ratio").is_none() && v["kinematics"] == "finite");
    }

    /// The element that turns most is found: a rotation that grows along
    /// x, `theta(x) = 0.1 x` about z (a beam's bending), read at the
    /// centre of the last element (x = 2.5).
    #[test]
    fn the_element_that_turns_most_is_named() {
        let m = model(CellShape::Hex20, Kinematics::Small);
        let mut u = vec![0.0; 3 * m.mesh.nodes.len()];
        for (i, x) in m.mesh.nodes.iter().enumerate() {
            // the linear field of a bending beam: v = 0.05 x^2, u = -y v'
            let t = 0.1 * x[0];
            u[3 * i] = -x[1] * t;
            u[3 * i + 1] = 0.05 * x[0] * x[0];
        }
        let got = largest_rotation(&m, &u).unwrap();
        // the most turned element is the one at x in [2, 3], y in [0.5, 1]:
        // at its centre (x = 2.5, y = 0.75) F = [[1 - 0.075, -0.25], [0.25, 1]]
        // in the x-y plane, whose rotation factor turns by
        // atan2(F_yx - F_xy, F_xx + F_yy)
        let expected = (0.25f64 + 0.25).atan2(0.925 + 1.0);
        assert!((got.radians - expected).abs() < 1e-12, "{}", got.radians);
        let nodes = m.mesh.blocks[0].element(got.element - 1);
        let centre = nodes
            .iter()
            .map(|&n| m.mesh.nodes[n])
            .fold([0.0; 3], |c, x| [c[0] + x[0], c[1] + x[1], c[2] + x[2]]);
        let (cx, cy) = (centre[0] / 20.0, centre[1] / 20.0);
        assert!(
            (cx - 2.5).abs() < 1e-12 && (cy - 0.75).abs() < 1e-12,
            "{cx} {cy}"
        );
    }
}
