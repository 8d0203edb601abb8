% Elements still past the bounds after smoothing, clean-up and easing are
% left as they are (see polish_rings, kb/strategy.pl).
bound(polish_rings, 0).
