% A uniform run is meshed free first, as the paper meshes; blocks only
% where the free mesh falls short (blocks/mod.rs, mesh_free_then_blocks).
bound(blocks_first, 0).
