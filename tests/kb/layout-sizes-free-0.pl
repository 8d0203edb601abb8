% Every block layout is finished by its blocks' corners and taper alone,
% whatever its size (blocks/layouts.rs).
bound(layout_sizes_free_over, 0).
