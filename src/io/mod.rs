//! Files: the mesh writers and the mesh reader.

pub mod mesh_reader;
pub mod output;
