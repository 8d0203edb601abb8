% A domain without max_size is meshed at the size whatever its fixed
% counts (built in: graded up to the longest boundary segment where one
% is over 1.5 times the size).
bound(coarse_boundary_grading, 0).
