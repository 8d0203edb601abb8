% A feature whose test never ends: refused when the file is loaded.
strategy([b6, b4, b5, b3, b2, b1]).
feature(b6, Ctx) :- spin_(Ctx).
feature_action(b6, _, a3).
spin_(Ctx) :- spin_(Ctx).
