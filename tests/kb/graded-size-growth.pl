% A run graded by a max_size with the size aimed for growing 0.3 a unit
% of distance from the boundary (bound/2's size_growth is 0.6): a bound
% the host reads when it prepares the run, in place from there on.
graded_bound(size_growth, 0.3).
