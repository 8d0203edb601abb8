% Facing edges keep their own segment counts, however thin the wall.
bound(thin_wall, 0).
