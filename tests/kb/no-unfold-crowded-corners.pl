% A clean-up change that takes an element from a crowded corner is
% judged as its local smoothing leaves it, folded over or not (see
% unfold_crowded_corners, kb/strategy.pl).
bound(unfold_crowded_corners, 0).
