% A feature that throws only at a reflex corner of about 270 degrees: the
% sample contexts of the load-time check pass, meshing an L-shape meets it.
feature(b6, ctx(_, _, T1, _, _, _, _, _)) :-
    T1 >= 265, T1 =< 275,
    Ratio is 1 / 0,
    Ratio > 0.
feature_action(b6, _, a3).
strategy([b6, b4, b5, b3, b2, b1]).
