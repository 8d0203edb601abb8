% A graded mesh is kept graded however far it falls short (built in: one
% still outside the bounds after its retries is meshed again as without
% its max_size, and that mesh kept where it is within the bounds,
% bound(uniform_when_graded_short, 1)).
bound(uniform_when_graded_short, 0).
