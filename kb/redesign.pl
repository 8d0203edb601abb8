/** Redesign: the constraints an element must meet for the sake of the
remaining domain, and the rules Rd1-Rd13 (Exp. 3) that correct it.

The host places the element of a design action and measures it against
the front nearby; it asks with the relations it found:

  corner_segment(C, V, H, S)   new corner C (n3 or n4) and a front segment
                               at vertical V and horizontal H distance;
                               S is the element's size
  corner_node(C, D, S)         new corner C at distance D of a front node
  edge_point(E, V, H, S, T)    element edge E (e23, e34, e41) and a front
                               node of angle T at distances V, H
  outer_corner(N, Deg)         the angle the remaining domain keeps at N
  inner_corner(N, Deg)         the element's own corner at N
  remaining_corner(N, Deg)     for a3: the angle left at N3 or N4 (theta')

The constraints (paper, "Redesign subsystem"):
  1. every outer corner of the element above the lower bound;
  2. no element edge near a concave point of the remaining domain;
  3. no element corner near the boundary of the remaining domain.

```
?- violation(corner_segment(n3, 0.1, 0.0, 1.0), V).
   V = near_boundary(n3).
?- redesign(ctx(180,180,180,180,180,1,1,1), a1(90,90,1,1),
            [edge_point(e23, 0.1, 0, 1, 270)], R, A).
   R = rd1, A = a1(90, 76.5, 1, 1).
```
*/

:- dynamic(violation/2).
:- dynamic(redesign_rule/5).

%% violation(+Relation, -Violation)
%
% True iff the measured Relation breaks a constraint, named Violation.
% ?- violation(outer_corner(n1, 30), V).
%    V = small_outer_corner(n1).
violation(corner_segment(C, V, H, S), near_boundary(C)) :-
    point_segment_near(V, H, S).
violation(corner_node(C, D, S), near_node(C)) :-
    bound(near_node, K),
    D < K * S.
violation(edge_point(E, V, H, S, T), near_concave(E)) :-
    angle_concave(T),
    point_segment_near(V, H, S).
violation(outer_corner(N, Deg), small_outer_corner(N)) :-
    bound(lower_corner, L),
    Deg < L.
violation(inner_corner(N, Deg), small_corner(N)) :-
    bound(lower_corner, L),
    Deg < L.
violation(inner_corner(N, Deg), large_corner(N)) :-
    bound(upper_corner, U),
    Deg > U.
violation(remaining_corner(N, Deg), small_remaining(N)) :-
    bound(lower_corner, L),
    Deg < L.

%% redesign_rule(?Rule, +Ctx, +Action, +Violation, -NewAction)
%
% Rule corrects Action, which commits Violation, into NewAction.
% ?- redesign_rule(R, ctx(180, 180, 180, 180, 180, 1, 1, 1), a2(90, 90),
%                  near_boundary(n3), A).
%    R = rd6, A = a2(81.0, 81.0) ;  false.

% A new corner on top of a front node: the fronts meet, use the node.
redesign_rule(rd_merge, _, A, near_node(C), merge(C, A)).
% Unless the merged element takes a front node whole at a corner above
% U_c (the fronts met at an open node): the element is placed as
% designed, the node left open for the elements after it.
redesign_rule(rd_unmerge, _, merge(_, A), large_corner(_), A).
% The outer corner is controlled by decreasing the inner one (paper: "as
% the outer corner of element can be controlled in the stage of initial
% design by decreasing the corresponding inner corner").
redesign_rule(rd_outer, _, a1(P1, P2, L2, L4), small_outer_corner(n1), a1(Q1, P2, L2, L4)) :-
    Q1 is P1 * 0.85.
redesign_rule(rd_outer, _, a1(P1, P2, L2, L4), small_outer_corner(n2), a1(P1, Q2, L2, L4)) :-
    Q2 is P2 * 0.85.
redesign_rule(rd_outer, _, a2(P2, P4), small_outer_corner(n2), a2(Q2, P4)) :-
    Q2 is P2 * 0.85.
redesign_rule(rd_outer, _, a2(P2, P4), small_outer_corner(n4), a2(P2, Q4)) :-
    Q4 is P4 * 0.85.
% Adding three lines, Fig. 12.
redesign_rule(rd1, _, a1(P1, P2, L2, L4), near_concave(e23), a1(P1, Q2, L2, L4)) :-
    Q2 is P2 * 0.85.
redesign_rule(rd2, _, a1(P1, P2, L2, L4), near_concave(e41), a1(Q1, P2, L2, L4)) :-
    Q1 is P1 * 0.85.
redesign_rule(rd3, _, a1(P1, P2, L2, L4), near_concave(e34), a1(P1, P2, M2, M4)) :-
    M2 is L2 * 0.7, M4 is L4 * 0.7.
redesign_rule(rd4, _, a1(P1, P2, L2, L4), near_boundary(n3), a1(P1, Q2, M2, L4)) :-
    Q2 is P2 * 0.9, M2 is L2 * 0.8.
redesign_rule(rd5, _, a1(P1, P2, L2, L4), near_boundary(n4), a1(Q1, P2, L2, M4)) :-
    Q1 is P1 * 0.9, M4 is L4 * 0.8.
% Adding two lines, Fig. 13.
redesign_rule(rd6, _, a2(P2, P4), near_boundary(n3), a2(Q2, Q4)) :-
    Q2 is P2 * 0.9, Q4 is P4 * 0.9.
redesign_rule(rd7, _, a2(P2, P4), near_concave(e23), a2(Q2, P4)) :-
    Q2 is P2 * 0.85.
redesign_rule(rd8, _, a2(P2, P4), near_concave(e34), a2(P2, Q4)) :-
    Q4 is P4 * 0.85.
% Adding one line, Fig. 14: a3 is replaced by a2 on N1N2 or on N2N3
% (shift(1, A): act on the next edge, whose N1 is this N2), else by a1.
% The a2 over a corner is design.pl's: a parallelogram, or the kite of a
% tip.
redesign_rule(rd9, ctx(_, _, T1, _, _, _, _, _), a3, small_corner(n3), a2(P, P)) :-
    corner_a2_(T1, P).
redesign_rule(rd9, ctx(_, _, T1, _, _, _, _, _), a3, large_corner(n4), a2(P, P)) :-
    corner_a2_(T1, P).
redesign_rule(rd10, ctx(_, _, _, T2, _, _, _, _), a3, small_corner(n4), shift(1, a2(P, P))) :-
    corner_a2_(T2, P).
redesign_rule(rd10, ctx(_, _, _, T2, _, _, _, _), a3, large_corner(n3), shift(1, a2(P, P))) :-
    corner_a2_(T2, P).
redesign_rule(rd11, ctx(_, _, T1, _, _, _, _, _), a3, small_remaining(n3), a2(P, P)) :-
    corner_a2_(T1, P).
redesign_rule(rd12, ctx(_, _, _, T2, _, _, _, _), a3, small_remaining(n4), shift(1, a2(P, P))) :-
    corner_a2_(T2, P).
% Otherwise a1 over the edge, which shares the corners at N1 and N2: not
% when either is a tip (a tip is taken whole, never shared).
redesign_rule(rd13, ctx(_, _, T1, T2, _, L5, L6, R), a3, _, A) :-
    not_tip_(T1), not_tip_(T2),
    feature_action(b1, ctx(_, _, T1, T2, _, L5, L6, R), A).

%% redesign(+Ctx, +Action, +Relations, -Rule, -NewAction)
%
% The first violated constraint among Relations that a rule corrects:
% which rule fires and the corrected action. Fails when nothing is
% violated (or no rule applies).
% ?- redesign(ctx(180, 180, 180, 180, 180, 1, 1, 1), a1(90, 90, 1, 1),
%             [outer_corner(n1, 90)], R, A).
%    false.
redesign(Ctx, A, Relations, Rule, NewA) :-
    member(R, Relations),
    violation(R, V),
    redesign_rule(Rule, Ctx, A, V, NewA),
    !.
