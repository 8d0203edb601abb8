% The validity check's clearance doubled to 0.3 of the base edge; a file
% replaces bound/2 name by name, so every other bound keeps its built-in
% value.
bound(valid_clearance, 0.3).
