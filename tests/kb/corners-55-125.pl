% The corner window narrowed to [55, 125]; a file replaces bound/2 name
% by name, so every other bound keeps its built-in value.
bound(upper_corner, 125).
bound(lower_corner, 55).
