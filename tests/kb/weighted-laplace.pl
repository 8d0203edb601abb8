% In a run graded by a max_size, Laplace smoothing weighs each neighbour
% by the inverse of the size field at the edge's middle (see
% weighted_laplace, kb/strategy.pl).
graded_bound(weighted_laplace, 1).
