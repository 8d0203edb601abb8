% A uniform mesh is kept however many elements it has (built in: one
% with more than 1.2 times the domain's area over the size squared is
% meshed again coarser, bound(coarser_when_over, 1.2)).
bound(coarser_when_over, 0).
