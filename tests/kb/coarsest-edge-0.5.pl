% a transition never makes an edge longer than half the limit (built in:
% 1.2 times it)
bound(coarsest_edge, 0.5).
