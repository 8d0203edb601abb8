% Every edge of a uniform run reads the size, as before the band was on
% by default (built in: bound(uniform_size_band, 1.5), an edge outside
% 1.5 times the size is seen as fine or coarse), and no coarser pass
% (bound(coarser_when_over, 0)).
bound(uniform_size_band, 0).
bound(coarser_when_over, 0).
