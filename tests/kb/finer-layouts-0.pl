% The finer block layouts are made only where the first one's block mesh
% falls short, whatever its size (blocks/layouts.rs).
bound(finer_layouts_up_to, 0).
