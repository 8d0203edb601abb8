% A feature whose test divides by zero: refused when the file is loaded.
feature(b6, ctx(_, _, T1, _, _, _, _, _)) :-
    Ratio is T1 / 0,
    Ratio > 1.
feature_action(b6, _, a3).
strategy([b6, b4, b5, b3, b2, b1]).
