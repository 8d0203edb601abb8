/** Boundary features b1-b5 of the remaining domain.

One labelling for every feature (the paper's figures label each figure
anew). The front is walked with the remaining domain on its left; the edge
under consideration is N1N2 and the nodes around it read

    N7 -> N4 -> N1 -> N2 -> N5

Theta_k is the interior angle of the remaining domain at N_k (degrees).
The host measures them and asks with a context term

    ctx(Theta7, Theta4, Theta1, Theta2, Theta5, L5, L6, R)

where L5 = |N4N1| / |N1N2| and L6 = |N2N5| / |N1N2| (lengths relative to
the edge, so l1 = 1), and R is the grading ratio: the size the run aims
for at the edge (its size field, growing from the boundary to max_size)
over |N1N2|, in tenths; 1 where the run is not graded. R well above 1
says the front's edges are finer than the place asks for (coarsen). Every edge is also read mirrored (N1 and N2
swapped, the front walked backwards), so that a feature anchored at the
right end of an edge is found as well.

```
?- context_feature(ctx(90, 180, 90, 180, 90, 1, 1, 1), F).
   F = b4 ;  F = b5 ;  F = b2 ;  false.
?- context_feature(ctx(180, 180, 5, 180, 180, 1, 1, 1), F).
   F = tip ;  false.
?- feature(b1, ctx(180, 180, 180, 180, 180, 1, 1, 1)).
   true.
```
*/

:- dynamic(feature/2).

%% feature(?Feature, +Ctx)
%
% True iff the edge of context Ctx shows boundary feature Feature.
% ?- feature(F, ctx(180, 180, 90, 90, 180, 1, 1, 1)).
%    F = b3 ;  false.

% b1: both ends open (theta1, theta2 >= U_c), Fig. 8(a).
feature(b1, ctx(_, _, T1, T2, _, _, _, _)) :-
    bound(upper_corner, U),
    T1 >= U, T2 >= U.
% b2: a corner at N1 between two open nodes, Fig. 8(b). The scan reads
% theta2, theta4 >= 180; see bound(b2_side, _). N1 is a corner, not a
% tip (below): a2's parallelogram repeats theta1 at N3 and puts
% 180 - theta1 at N2 and N4, above U_c once theta1 is below the tip bound.
feature(b2, ctx(_, T4, T1, T2, _, _, _, _)) :-
    bound(upper_corner, U), bound(b2_side, S),
    not_tip_(T1), T1 =< U, T2 >= S, T4 >= S.
% b3: both ends are corners, Fig. 8(c).
feature(b3, ctx(_, _, T1, T2, _, _, _, _)) :-
    bound(upper_corner, U),
    T1 =< U, T2 =< U.
% b4: corners at N7, N1, N5 with open nodes N4, N2 between them: a
% corner block two elements wide each way, Fig. 9(a). N1 is a corner,
% not a tip: a tip cannot be a corner of a block of four.
feature(b4, ctx(T7, T4, T1, T2, T5, _, _, _)) :-
    bound(upper_corner, U),
    not_tip_(T1), T1 =< U, open_(U, T2), T5 =< U, open_(U, T4), T7 =< U.
% b5: corners at N1 and N5 with one open node N2 between, Fig. 9(b).
% N1 is a corner, not a tip: a5's phi4 = pi - theta1 would leave N4 an
% element corner above U_c (and reach 180 at a cusp).
feature(b5, ctx(_, _, T1, T2, T5, _, _, _)) :-
    bound(upper_corner, U),
    not_tip_(T1), T1 =< U, open_(U, T2), T5 =< U.
% tip: a corner sharper than the tip bound (a spike of the domain, down
% to a cusp of 0 deg where a curve leaves a corner tangent to the other
% side) between two open nodes: Fig. 8(b)'s picture with N1 too sharp to
% share and too sharp for a parallelogram. One element takes the tip
% whole; see bound(tip_corner, _) and the action in design.pl.
feature(tip, ctx(_, T4, T1, T2, _, _, _, _)) :-
    bound(b2_side, S),
    tip_(T1), T2 >= S, T4 >= S.

% coarsen: where the run is graded and the size aimed for is
% bound(coarsen_ratio, _) times the edge or more, a front running flat
% over N4N1, N1N2, N2N5 (theta1, theta2 near straight, the three edges
% of about one length): three edges become one over two rows, in the
% spirit of paving's row adjustments (action t3). theta4 and theta5 are
% open, or a right angle at the foot of a step an earlier transition
% left: the template then meets that step's top, so transitions sit side
% by side and leave a flat front for the next.
feature(coarsen, ctx(_, T4, T1, T2, T5, L5, L6, R)) :-
    bound(coarsen_ratio, C), R >= C,
    flat_(T1), flat_(T2), coarsen_side_(T4), coarsen_side_(T5),
    alike_(L5), alike_(L6).

% refine: the mirror of coarsen, where the size aimed for is
% bound(refine_ratio, _) times the edge or less (an edge far coarser than
% the place asks for: a fixed segment count coarser than the size): the
% edge becomes three over two rows (action r3), its ends running on flat
% or at the foot of the step an earlier refinement left beside it, whose
% top the new template takes, so that refinements sit side by side. A
% ratio of 0 (built in) never refines.
feature(refine, ctx(_, _, T1, T2, _, _, _, R)) :-
    bound(refine_ratio, C), C > 0, R =< C,
    refine_end_(T1), refine_end_(T2).

refine_end_(T) :- flat_(T).
refine_end_(T) :- step_foot_(T).

coarsen_side_(T) :- T >= 150, T =< 240.
coarsen_side_(T) :- step_foot_(T).

% The right angle at the foot of the step a transition leaves beside it.
step_foot_(T) :- T >= 75, T =< 105.

open_(U, T) :- T >= U, T =< 240.

% A front node where the front runs on nearly straight.
flat_(T) :- T >= 165, T =< 195.
% An edge of about the length of N1N2.
alike_(L) :- L >= 0.75, L =< 1.33.

% A tip: an interior angle below bound(tip_corner, _).
tip_(T) :- bound(tip_corner, K), T < K.
not_tip_(T) :- bound(tip_corner, K), T >= K.

%% context_feature(+Ctx, -Feature)
%
% True iff Feature is a feature of the edge, in the order of the strategy.
% ?- context_feature(ctx(180, 180, 90, 180, 180, 1, 1, 1), F).
%    F = b2 ;  false.
context_feature(Ctx, F) :-
    strategy(S),
    member(F, S),
    feature(F, Ctx).
