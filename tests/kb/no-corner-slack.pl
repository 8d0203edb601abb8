% Corners counted within the window only inside it (built in: half a
% degree outside it counts as within, bound(corner_slack, 0.5)).
bound(corner_slack, 0).
