% A free mesh with elements outside the bounds is kept as it is, never
% meshed again in blocks (blocks/mod.rs, mesh_free_then_blocks).
bound(blocks_when_out_of_bounds, 0).
