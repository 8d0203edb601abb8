% An action the host has no builtin for.
feature_action(b1, _, a9(1, 2)).
