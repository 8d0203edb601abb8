% The loops the rules leave open are closed by triangles split in three
% only, as before the pairing (fallback/pairs.rs): every loop edge is
% halved, and the rules' elements along its chords split.
bound(fallback_pairs, 0).
