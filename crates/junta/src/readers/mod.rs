//! File-format readers beside the scene reader ([`crate::scene`]): the
//! Abaqus/CalculiX deck text ([`inp`]) and Gmsh meshes ([`gmsh`]). Each
//! turns a file into a [`junta_core::mesh::Mesh`] (and, for decks, the
//! keywords [`crate::deck`] builds a model from); errors name the file and
//! the line.

pub mod gmsh;
pub mod inp;
