% Four-sided domains meshed by the layouts alone, never in patches round
% pairs of irregular nodes (blocks/four_sided.rs).
bound(four_sided_pairs, 0).
