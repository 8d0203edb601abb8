//! Files: the mesh writers (MSH, VTK, SVG, JSON, Abaqus `.inp`), the mesh
//! reader, and the DXF outline reader.

pub mod dxf;
mod inp;
pub mod mesh_reader;
mod msh_binary;
pub mod output;
