//! Input: what a simulation is read from. The TOML scene ([`scene`], checked
//! by `validate`), the Abaqus/CalculiX deck text ([`inp`]) and the model a
//! deck builds ([`deck`]), Gmsh meshes ([`gmsh`]), and the lay-up builder ([`layup`]: a `[laminate]`
//! becomes plies, ply materials, interfaces and sets). Each turns a file into
//! a [`junta_core::mesh::Mesh`] or a model; errors name the file, the key or
//! the line.

pub mod deck;
pub mod gmsh;
pub mod inp;
pub mod layup;
pub mod scene;
pub mod tie;
pub(crate) mod validate;
