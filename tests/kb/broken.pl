% A rule with a syntax error on line 3.
strategy([b4, b5, b3, b2, b1]).
feature(b6, ctx(_, _, T1, _, _, _, _, _) :- T1 < 30.
