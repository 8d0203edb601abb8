% The built-in bounds with the corner window narrowed to [55, 125]: a
% file that defines bound/2 gives all of them.
bound(upper_corner, 125).
bound(lower_corner, 55).
bound(b2_side, 160).
bound(reflex_split, 240).
bound(near_vertical, 0.45).
bound(near_horizontal, 0.3).
bound(near_node, 0.5).
bound(redesign_rounds, 4).
bound(max_aspect, 10).
bound(max_taper, 10).
bound(max_size_jump, 2).
bound(valid_corner, 4).
bound(valid_edge, 0.25).
bound(valid_clearance, 0.15).
bound(min_front_angle, 12).
bound(relation_corner, 90).
bound(relation_inner_above, 120).
bound(relation_reach, 1).
bound(centre_search_below, 30).
