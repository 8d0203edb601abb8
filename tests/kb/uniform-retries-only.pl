% The retries of retry_bound/3 that move a design threshold, and
% refine_fixed_counts, on uniform runs only (built in: a graded mesh that
% falls short is meshed again with them too, free only); gentler_grading
% is tried on graded runs alone either way.
retry_needs(no_sharp_front_corners, uniform).
retry_needs(fronts_merge_nearer, uniform).
retry_needs(flatter_near_horizontal, uniform).
retry_needs(refine_fixed_counts, uniform).
