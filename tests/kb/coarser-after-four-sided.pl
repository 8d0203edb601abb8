% A mesh made in four-sided patches is meshed again coarser too where it
% has many elements (built in: it is kept as it is,
% bound(coarser_after_four_sided, 0)).
bound(coarser_after_four_sided, 1).
