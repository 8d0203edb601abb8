% Every edge of a uniform run reads the size, as before the band was on
% by default (built in: bound(uniform_size_band, 1.5)): for tests whose
% domains were chosen for what the rules did then, and that the band now
% meshes otherwise (most within the bounds from the first run).
bound(uniform_size_band, 0).
