% the strict closing of a stuck loop keeps only elements exactly the size
% of the loop edges they take (built in: within 1.6 times)
bound(closing_strict_size, 1.0).
