% A feature that never ends at a reflex corner of about 270 degrees.
feature(b6, ctx(_, _, T1, _, _, _, _, _)) :-
    T1 >= 265, T1 =< 275,
    spin_(T1).
spin_(T) :- spin_(T).
feature_action(b6, _, a3).
strategy([b6, b4, b5, b3, b2, b1]).
