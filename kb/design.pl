/** Initial design: the rules "if b_j then a_k" (Exp. 2) and the actions.

An action term says how to place the element N1N2N3N4 over the edge N1N2
(labelling of features.pl); the host's builtins place the nodes:

  a1(Phi1, Phi2, L2, L4)  add three lines: new N4 at angle Phi1 from N1N2
                          and distance L4 from N1, new N3 at angle Phi2 and
                          distance L2 from N2 (lengths relative to |N1N2|).
  a2(Phi2, Phi4)          add two lines: the quad N1 N2 N3 N4 with N4 the
                          front node before N1; new N3 where the line from
                          N2 at Phi2 meets the line from N4 at Phi4.
  a3                      add one line: link the front nodes after N2 and
                          before N1; the element is N1 N2 N5 N4 (Fig. 7(c)
                          calls the node after N2 "N3").
  a4                      new N3 = (N2 + N4 + N6)/3 with N6 = N5 + N7 - N1,
                          the far corner of the block of Fig. 9(a).
  t3(H)                   three edges N4N1, N1N2, N2N5 become one over two
                          rows of four elements: new nodes H (relative
                          to the edges' mean length) above N1 and N2,
                          2H above N4 and N5 (a coarser interior).

```
?- feature_action(b2, ctx(180, 180, 90, 180, 180, 1, 1, 1), A).
   A = a2(90, 90).
?- context_design(ctx(182, 182, 0, 180, 180, 1, 1, 1), F, A).
   F = tip, A = a2(135.0, 135.0).
?- context_design(ctx(180, 180, 180, 180, 180, 1, 1, 1), F, A).
   F = b1, A = a1(90.0, 90.0, 1.0, 1.0).
```
*/

:- dynamic(feature_action/3).

%% feature_action(+Feature, +Ctx, -Action)
%
% Action is the design action for an edge with Feature and context Ctx
% (below, the reflex corner of 270 at N2 is shared by three elements).
% ?- feature_action(b1, ctx(180, 180, 180, 270, 180, 1, 1, 1), A).
%    A = a1(90.0, 90.0, 1.0, 1.0).

% a1 for b1: phi = theta/2, l2 = (l1 + l6)/(2 sin phi2),
% l4 = (l5 + l1)/(2 sin phi1). A reflex angle above bound(reflex_split)
% is shared by more elements: phi = theta/k, k = round(theta/90).
% In a graded run the row grows toward the size aimed for: both sides
% are G times as long, G = R (the grading ratio) within [1, row_growth].
feature_action(b1, ctx(_, _, T1, T2, _, L5, L6, R), a1(Phi1, Phi2, L2, L4)) :-
    corner_share_(T1, Phi1),
    corner_share_(T2, Phi2),
    row_height_(R, G),
    L2 is G * (1 + L6) / (2 * sin(Phi2 * pi / 180)),
    L4 is G * (L5 + 1) / (2 * sin(Phi1 * pi / 180)).
% a2 for b2: phi2 = phi4 = pi - theta1 (a parallelogram).
feature_action(b2, ctx(_, _, T1, _, _, _, _, _), a2(Phi, Phi)) :-
    Phi is 180 - T1.
% a3 for b3: link N5 (the paper's N3) and N4.
feature_action(b3, _, a3).
% a2 for a tip: the element takes the tip N1 whole. It is the triangle
% N1 N2 N4 (the tip and its two front neighbours) with a right-angled cap
% over N2N4: its corners at N2 and N4 are the triangle's there, B2 and
% B4, each opened by at most 45 deg (less where that would pass U_c), so
% that its fourth corner, at N3, is a right angle when it can be. For a
% tip with equal sides it is a kite, U_c - theta1/2 at N2 and N4 (down
% to a cusp, theta1 = 0: 135, 90, 135); with unequal sides (L5, the side
% |N4N1| over |N1N2|) it leans to the longer one, where an equal kite
% would not close at all. The parallelogram of b2 would repeat the tip
% at N3 and put 180 - theta1 at N2 and N4; a right trapezoid (90 at N2
% and N4) would put 180 - theta1 at N3. Among elements in the tip's
% wedge the kite also has the least taper (its sides at N3 are the
% longest a corner of at most U_c at N2 and N4 allows).
feature_action(tip, ctx(_, _, T1, _, _, L5, _, _), a2(Phi2, Phi4)) :-
    tip_triangle_(T1, L5, B2, B4),
    tip_cap_(B2, G2),
    tip_cap_(B4, G4),
    Phi2 is B2 + G2,
    Phi4 is B4 + G4.
% a4 for b4: N3 at the centre of the block.
feature_action(b4, _, a4).
% t3 for coarsen: the three edges become one over two rows, the first
% row as high as the edges are long.
feature_action(coarsen, _, t3(1.0)).
% r3 for refine: the edge becomes three over two rows, the mirror of t3
% (its first row a third of the edge high).
feature_action(refine, _, r3(1.0)).
% a5 for b5: phi4 = pi - theta1, phi2 = theta5/(theta1 + theta5) * theta2,
% kept within [30, 150] so that both elements at N2 stay usable.
feature_action(b5, ctx(_, _, T1, T2, T5, _, _, _), a2(Phi2, Phi4)) :-
    Phi4 is 180 - T1,
    Phi2 is min(150, max(30, T5 / (T1 + T5) * T2)).

% The corners B2, B4 at N2 and N4 of the triangle N1 N2 N4 with sides
% |N1N2| = 1, |N1N4| = L5 and the angle T1 between them (law of
% cosines); an isosceles one where the tip is too sharp for its corners
% to be told (a cusp: theta1 rounds to 0) or N2N4 too short.
tip_triangle_(T1, L5, B2, B4) :-
    R is T1 * pi / 180,
    D is sqrt(max(0, 1 + L5 * L5 - 2 * L5 * cos(R))),
    (   ( T1 < 1 ; D < 1.0e-9 ) ->
        B2 is 90 - T1 / 2
    ;   C is max(-1, min(1, (1 + D * D - L5 * L5) / (2 * D))),
        B2 is acos(C) * 180 / pi
    ),
    B4 is 180 - T1 - B2.

% How far the cap opens a triangle corner B: 45 deg, less if B + 45
% would pass U_c; where B is past U_c already, half the way to straight
% (the element stays convex).
tip_cap_(B, G) :-
    bound(upper_corner, U),
    (   B < U -> G is min(45, U - B)
    ;   G is (180 - B) / 2
    ).

% The corners phi2 = phi4 of the element a2 stands over a corner N1 of
% theta1: the parallelogram's pi - theta1 for a corner, the kite's
% U_c - theta1/2 for a tip (the redesign rules that turn a3 into a2 use
% it too). No such element stands over a node that is no corner (theta1
% of 180 or more): fails there.
corner_a2_(T1, Phi) :-
    T1 < 180,
    (   tip_(T1) -> bound(upper_corner, U), Phi is U - T1 / 2
    ;   Phi is 180 - T1
    ).

% How much higher than usual a row is made where the size aimed for is R
% times the edge: 1 in a uniform run (R = 1).
row_height_(R, G) :-
    bound(row_growth, M),
    G is max(1, min(M, R)).

corner_share_(Theta, Phi) :-
    bound(reflex_split, R),
    (   Theta =< R -> Phi is Theta / 2
    ;   K is max(2, round(Theta / 90)), Phi is Theta / K
    ).

%% context_design(+Ctx, -Feature, -Action)
%
% The first feature of the strategy the edge shows, and its action.
% ?- context_design(ctx(90, 180, 90, 180, 90, 1, 1, 1), F, A).
%    F = b4, A = a4.
context_design(Ctx, F, A) :-
    context_feature(Ctx, F),
    feature_action(F, Ctx, A),
    !.

%% context_designs(+Ctxs, -Designs)
%
% Batch form for the host: one d(Feature, Action) per context, or none
% when the edge shows no feature.
% ?- context_designs([ctx(180, 180, 180, 180, 180, 1, 1, 1),
%                     ctx(90, 90, 300, 90, 90, 1, 1, 1)], Ds).
%    Ds = [d(b1, a1(90.0, 90.0, 1.0, 1.0)), none].
context_designs([], []).
context_designs([C | Cs], [D | Ds]) :-
    (   context_design(C, F, A) -> D = d(F, A) ; D = none ),
    context_designs(Cs, Ds).
