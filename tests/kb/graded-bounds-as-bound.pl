% The bounds of a run graded by a max_size (graded_bound/2) at bound/2's
% values: rows no taller and transitions no sooner than in a run graded
% for a coarse boundary (the graded runs before graded_bound/2).
graded_bound(row_growth, 1.5).
graded_bound(coarsen_ratio, 1.5).
graded_bound(graded_collapse_below, 0).
