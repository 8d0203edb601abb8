% The clean-up never splits two elements into four round two new nodes
% (see split_into_four, kb/strategy.pl).
bound(split_into_four, 0).
