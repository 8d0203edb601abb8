% One setting, then a comment on the last line (the engine alone would
% read that as a syntax error).
bound(upper_corner, 140).
% U_c, from 135.