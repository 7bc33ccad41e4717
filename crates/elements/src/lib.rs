//! # junta-elements
//!
//! Solid finite elements of Junta and what they are made of:
//!
//! * [`shape`]: Lagrange / serendipity shape functions and their natural
//!   derivatives for Q4, Q8, Q9 ([`shape::quad_shape`]) and Tri3, Tri6
//!   ([`shape::tri_shape`]; both through [`shape::surface_shape`] on the
//!   faces of the interface elements and for face loads) and H8, H20, H27
//!   ([`shape::hex_shape`]), W6, W15 ([`shape::wedge_shape`]), in the node
//!   order of [`junta_core::topology`].
//! * [`quadrature`]: Gauss-Legendre (1-5 points) and Gauss-Lobatto (2-5
//!   points) rules and their 2D / 3D tensor products; triangle rules (1, 3,
//!   6 points, [`quadrature::triangle_rule`], and the vertex rule) and
//!   triangle x line rules for wedges ([`quadrature::wedge_rule`]).
//! * [`material`]: linear elastic materials implementing
//!   [`junta_core::Material`]: [`Isotropic`] (`isotropic`) and
//!   [`Orthotropic`] (`orthotropic`, with an Abaqus-style orientation).
//! * [`solid`]: the small-strain hexahedral [`SolidElement`], registered as
//!   `h8`, `h20`, `h27`, `h20r`, `h27r`, and the wedges `wedge6` (C3D6),
//!   `wedge15` (C3D15).
//! * [`plane`]: plane strain, plane stress and axisymmetric
//!   quadrilaterals and triangles ([`plane::PlaneElement`]), registered
//!   under the Abaqus names `cpe3`..`cpe9`, `cps3`..`cps9`, `cax3`..`cax9`.
//! * [`layered`]: the hexahedra integrated ply by ply through the
//!   thickness, each point with its ply's material
//!   ([`SolidElement::layered`], Abaqus's `*SOLID SECTION, COMPOSITE`).
//! * [`h8i`]: the 8-node hexahedron with incompatible modes
//!   [`IncompatibleHex8`] (as C3D8I), registered as `h8i`: bends without
//!   shear locking.
//! * [`total_lagrangian`]: Green strain, second Piola-Kirchhoff stress and
//!   the tangent with geometric stiffness, which every solid uses under
//!   `nlgeom` ([`junta_core::Kinematics::Finite`]).
//! * [`rotation`]: the rigid rotation of a solid element (the polar
//!   decomposition of the deformation gradient at its centre), for the
//!   run's largest-rotation diagnostic.
//! * [`face_load`]: consistent nodal forces of pressures and tractions on
//!   solid faces.
//! * [`thermal`]: the thermal strain of a temperature change at an
//!   integration point (the materials' expansion coefficients).
//!
//! Every material and element is registered in the
//! [`junta_core::registry`] with `inventory`; a binary that wants them must
//! reference this crate (`use junta_elements as _;`).
//!
//! Embedding without the registry:
//!
//! ```
//! use std::sync::Arc;
//! use junta_core::{Element, topology::CellShape};
//! use junta_elements::{Isotropic, SolidElement, solid::Integration};
//!
//! let steel = Arc::new(Isotropic::new(210e9, 0.3).unwrap());
//! let h20 = SolidElement::new(CellShape::Hex20, Integration::Full, steel).unwrap();
//! assert_eq!(h20.num_points(), 27);
//! ```

#![warn(missing_docs)]

pub mod body_load;
pub mod face_load;
pub mod h8i;
pub mod layered;
pub mod material;
pub mod plane;
pub mod quadrature;
pub mod rotation;
pub mod shape;
pub mod solid;
pub mod thermal;
pub mod total_lagrangian;

pub use h8i::IncompatibleHex8;
pub use layered::Ply;
pub use material::{EngineeringConstants, Isotropic, Orientation, Orthotropic};
pub use quadrature::{gauss_legendre, gauss_lobatto, tensor_2d, tensor_3d, Rule, Rule1D};
pub use shape::{hex_shape, quad_shape, solid_shape, wedge_shape};
pub use solid::{Integration, SolidElement};

/// Refuse finite kinematics for an element that has no large-deformation
/// form yet.
pub fn small_strain_only(
    key: &str,
    k: junta_core::Kinematics,
) -> Result<(), junta_core::CoreError> {
    if k == junta_core::Kinematics::Finite {
        return Err(junta_core::CoreError::InvalidParameters {
            kind: "element",
            key: key.into(),
            message: format!("{key} has no large-deformation (nlgeom) form yet"),
        });
    }
    Ok(())
}
