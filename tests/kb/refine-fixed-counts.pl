% Refining fixed segment counts coarser than the size (built in: off).
% In a uniform run an edge more than 1.5 times the size, or less than
% its 1/1.5, reads its ratio to the size (R); refine turns an edge of
% 0.45 or less into three over two rows (r3), coarsen (built in, R of
% 1.5 or more) three edges into one.
bound(uniform_size_band, 1.5).
bound(refine_ratio, 0.45).
% A uniform run at the size, not graded for the coarse edges.
bound(coarse_boundary_grading, 0).
