% A byte-order mark first, as editors on Windows write one.
bound(upper_corner, 140).
