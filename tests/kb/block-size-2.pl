% Blocks of two element sizes: a finer block layout (tests/blocks.rs).
bound(block_size, 2).
