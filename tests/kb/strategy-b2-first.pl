% Tries the plain corner (b2, add two lines) before the extended features.
strategy([b2, b3, b4, b5, b1]).
