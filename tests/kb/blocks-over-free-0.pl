% The blocks kept wherever they are within the bounds, however many
% elements they have (as before bound(blocks_over_free, K)).
bound(blocks_over_free, 0).
