% One setting changed: the upper bound of an element's corners. The other
% bounds keep their built-in values.
bound(upper_corner, 140).
