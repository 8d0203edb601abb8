% A comment in Latin-1, not UTF-8: café.
bound(upper_corner, 140).
