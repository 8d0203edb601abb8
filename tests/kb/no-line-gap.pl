% Inner lines divided at the size wherever they run (built in:
% bound(line_gap, 1)): a line near a small hole keeps its one segment.
bound(line_gap, 0).
