% A graded mesh is left as the rules, smoothing and the clean-up made it:
% no element under its size field's size is collapsed or merged (see
% graded_collapse_below, kb/strategy.pl).
graded_bound(graded_collapse_below, 0).
